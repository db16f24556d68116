"""The striker example (free rigid ball on a clamped glass plate, 3-D) through its
script at a coarse size: the regular grid shows grid-axis bias, a jittered cloud less.
The README's runs (1 mm grid, seeds 1-3) are ``slow``."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from tests.helpers import EXAMPLES


def _script():
    path = EXAMPLES / "bodies" / "striker_plate.py"
    spec = importlib.util.spec_from_file_location("striker_script", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.long
def test_coarse_striker_runs_and_the_ball_is_stopped(tmp_path: Path) -> None:
    """1 mm grid for 15 us (6 400 points), one jittered seed: the ball touches the plate, slows
    down and breaks bonds under the impact; the figure and the numbers are written."""
    args = [
        "--seeds",
        "1",
        "--out",
        str(tmp_path),
        "--set",
        "discretisation.spacing=1.0e-3",
        "--set",
        "solver.end_time=1.5e-5",
    ]
    assert _script().main(args) == 0
    res = json.loads((tmp_path / "striker_plate.json").read_text())
    assert (tmp_path / "striker_plate.png").stat().st_size > 1000
    for c in res["cases"].values():
        assert c["ball_peak_force_N"] > 0
        assert -15.0 < c["ball_final_vz_m_s"] < 0.0  # slowed, not yet bounced back
        assert c["mean_damage"] > 0.05


@pytest.mark.slow
def test_jittered_clouds_remove_the_grid_axis_bias(tmp_path: Path) -> None:
    """The README's runs: the 8-fold (and 4-fold) harmonic of the bottom-face damage
    around the impact is several times smaller on jittered clouds than on the grid."""
    assert _script().main(["--out", str(tmp_path)]) == 0
    res = json.loads((tmp_path / "striker_plate.json").read_text())
    grid = res["cases"]["grid"]
    assert res["jittered_A8_mean"] < 0.5 * grid["A8"]
    assert res["jittered_A4_mean"] < 0.6 * grid["A4"]
