"""``examples/toy_family/toy_figure.py``: the toy family's force against the central-
difference gradient of its energy, and its figure (about 1 s)."""

from __future__ import annotations

import json
from pathlib import Path

from tests.helpers import EXAMPLES, load_script


def test_toy_figure_force_is_minus_the_energy_gradient(tmp_path: Path) -> None:
    """Measured: largest gap 4.2e-10 of the largest force (central differences, step
    1e-9 m); a force of the wrong sign or a missing factor 2 gives a gap of order 1."""
    script = load_script(EXAMPLES / "toy_family" / "toy_figure.py", "toy_figure")
    rec = script.main(["--out", str(tmp_path)])
    assert rec["n_checked"] == 40
    assert rec["max_relative_gap"] < 1e-6
    assert json.loads((tmp_path / "toy_family.json").read_text()) == rec
    assert (tmp_path / "toy_family.png").stat().st_size > 10_000
