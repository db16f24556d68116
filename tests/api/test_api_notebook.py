"""In a Jupyter kernel: the progress bar is an HTML bar updated in place, a result's
figure is shown as an image, a deck and a result display as tables (the docs tier:
nbclient and ipykernel come with the ``docs`` extra)."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.docs


def test_progress_bar_figures_and_tables_in_a_notebook(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    cells = [
        "import peridynamics as pd\n"
        "deck = pd.Deck.example('crack_branching_2d', {'discretisation.spacing': 2e-3,\n"
        "    'discretisation.horizon': 8e-3, 'solver.end_time': 5e-6, 'output.crack_tip': None})\n"
        "result = pd.Simulation(deck, progress=True).run()",
        "result.plot_damage()",
        "deck",
        "result",
    ]
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(c) for c in cells]
    nbclient.NotebookClient(nb, kernel_name="python3", timeout=300,
                            resources={"metadata": {"path": str(tmp_path)}}).execute()  # fmt: skip
    bar = [o for o in nb.cells[0].outputs if "text/html" in o.get("data", {})]
    assert bar and "<progress value='" in bar[-1]["data"]["text/html"]
    assert "steps" in bar[-1]["data"]["text/html"]
    shown = nb.cells[1].outputs[-1]["data"]
    assert "image/png" in shown, list(shown)
    assert "<table>" in nb.cells[2].outputs[-1]["data"]["text/html"]
    assert "<table>" in nb.cells[3].outputs[-1]["data"]["text/html"]
    assert list(tmp_path.iterdir()) == []  # no files unless asked
