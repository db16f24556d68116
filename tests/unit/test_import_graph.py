"""The layer picture of docs/architecture.md (docs/_ext/import_graph.py): the layer order
read from an import-linter contract, the import edges found by ``ast``, and the drawing."""

from __future__ import annotations

from pathlib import Path

from tests.helpers import ROOT, load_script

graph = load_script(ROOT / "docs" / "_ext" / "import_graph.py", "import_graph")


def test_layers_come_from_the_import_linter_contract(tmp_path: Path) -> None:
    toml = tmp_path / "pyproject.toml"
    toml.write_text(
        '[[tool.importlinter.contracts]]\nname = "x"\ntype = "forbidden"\n'
        'source_modules = ["a"]\nforbidden_modules = ["b"]\n'
        '[[tool.importlinter.contracts]]\nname = "layers"\ntype = "layers"\n'
        'containers = ["peridynamics"]\n'
        'layers = ["cli", "app", "peridynamics.build | deck", "kernels"]\n'
    )
    assert graph.read_layers(toml) == [["cli"], ["app"], ["build", "deck"], ["kernels"]]
    assert graph.read_layers(tmp_path / "missing.toml") == graph.DEFAULT_LAYERS


def test_edges_join_top_level_packages_and_cover_lazy_imports(tmp_path: Path) -> None:
    pkg = tmp_path / "peridynamics"
    for sub in ("kernels", "solvers"):
        (pkg / sub).mkdir(parents=True)
        (pkg / sub / "__init__.py").write_text("")
    (pkg / "kernels" / "loops.py").write_text("import numpy\n")
    (pkg / "solvers" / "step.py").write_text(
        "def f():\n    from peridynamics.kernels import loops\n    from . import other\n"
    )
    (pkg / "solvers" / "other.py").write_text("from ..kernels.loops import x\n")
    (pkg / "state.py").write_text("")
    old = graph.SRC
    graph.SRC = pkg
    try:
        edges, nodes = graph.import_edges(pkg)
    finally:
        graph.SRC = old
    assert nodes == {"kernels", "solvers", "state"}
    assert edges == {("solvers", "kernels"): 2}


def test_the_picture_of_the_package_is_drawn(tmp_path: Path) -> None:
    against = graph.draw(tmp_path / "layers.svg")
    assert (tmp_path / "layers.svg").read_text().lstrip().startswith("<?xml")
    assert all(" -> " in line for line in against)
