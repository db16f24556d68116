"""Every example in the API modules' docstrings (the methods'; the public names' own
docstrings are run by test_public_api.py) runs."""

from __future__ import annotations

import doctest
import importlib

import pytest

import peridynamics

#: the API modules whose methods carry examples (result and batch: their public names')
MODULES = ["peridynamics.api.deck", "peridynamics.api.simulation"]


@pytest.mark.parametrize("module", MODULES)
def test_module_examples_run(module, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    mod = importlib.import_module(module)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in doctest.DocTestFinder().find(mod):
        if test.name.rsplit(".", 1)[-1] in peridynamics.__all__:
            continue  # a public name's own docstring: tests/api/test_public_api.py runs it
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.attempted > 0 and result.failed == 0, result
