"""examples/thermal at its shipped size (2 500 points, about a second): the centre line
against the series solution, and the figure."""

from __future__ import annotations

import importlib.util
from pathlib import Path

EXAMPLE = Path(__file__).parents[2] / "examples" / "thermal" / "make_figures.py"


def test_thermal_example_matches_the_series(tmp_path: Path) -> None:
    spec = importlib.util.spec_from_file_location("thermal_figures", EXAMPLE)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    err = mod.main(tmp_path, "solver.end_time=2.0")
    assert err < 0.2  # K of an 80 K step (measured 0.049 K at t = 2 s, 0.014 K at 5 s)
    assert (tmp_path / "thermal_plate.png").stat().st_size > 1000
