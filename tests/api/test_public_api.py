"""The public API: the names a script imports from ``peridynamics``, each documented with
an example that runs (doctest), and none of them may disappear without a deprecation
(docs/api.md, "Versioning and deprecation")."""

from __future__ import annotations

import doctest
import inspect

import pytest

import peridynamics

#: the public API of 0.2.0; a name leaves it only after a release that deprecates it
PUBLIC_NAMES = {
    "BondBasedMaterial",
    "Bonds",
    "Callback",
    "CriticalStretch",
    "Deck",
    "DeckError",
    "Evaluator",
    "ExplicitSolver",
    "PointCloud",
    "Result",
    "RunInterrupted",
    "SetupError",
    "Simulation",
    "SimulationUnstable",
    "State",
    "SweepResult",
    "__version__",
    "build_bonds",
    "ensemble",
    "sweep",
}
DOCUMENTED = sorted(PUBLIC_NAMES - {"__version__"})


def test_no_public_name_disappears():
    missing = PUBLIC_NAMES - set(peridynamics.__all__)
    assert not missing, f"public names removed without deprecation: {sorted(missing)}"
    for name in peridynamics.__all__:
        assert getattr(peridynamics, name) is not None
    assert set(peridynamics.__all__) <= set(dir(peridynamics))


def test_version_is_semantic():
    parts = peridynamics.__version__.split("+")[0].split(".")
    assert len(parts) == 3 and all(p.isdigit() for p in parts), peridynamics.__version__


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'Simulaton'"):
        peridynamics.Simulaton  # noqa: B018


@pytest.mark.parametrize("name", DOCUMENTED)
def test_every_public_name_has_an_example_that_runs(name, tmp_path, monkeypatch):
    """The docstring of each public name holds an ``Examples`` section, and it runs."""
    obj = getattr(peridynamics, name)
    doc = inspect.getdoc(obj) or ""
    assert "Examples\n--------" in doc and ">>>" in doc, f"{name}: no example in its docstring"
    monkeypatch.chdir(tmp_path)  # nothing an example writes lands in the source tree
    finder = doctest.DocTestFinder(recurse=False)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in finder.find(obj, name, globs={}):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.attempted > 0 and result.failed == 0, f"{name}: {result}"
