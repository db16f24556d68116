"""Kalthoff-Winkler example: the crack paths of examples/kalthoff_winkler at a small size
(fast) and at the deck's resolution (slow), measured with the crack-path extraction.

The expected angles are the values measured by ``examples/kalthoff_winkler/refinement.py``
(README.md of the example): the chord over the first 20 mm of each notch crack, from the
notch direction, 59.9 deg at dx = 1.25 mm and 71.4 deg at dx = 0.3125 mm.
"""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest

from tests.helpers import EXAMPLES

SCRIPT = EXAMPLES / "kalthoff_winkler" / "refinement.py"


def _script():
    spec = importlib.util.spec_from_file_location("kalthoff_winkler_refinement", SCRIPT)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _check_common(r: dict) -> None:
    up, lo = r["upper"], r["lower"]
    # symmetric problem: both cracks alike (lower angle reported mirrored)
    assert up["initial_angle_deg"] == pytest.approx(lo["initial_angle_deg"], abs=1.0)
    assert up["length_m"] == pytest.approx(lo["length_m"], rel=0.05)
    # the path stays on its own side of the notch and ends near the top edge (y = 0.1 m)
    assert up["tip_m"][1] > 0.07 and lo["tip_m"][1] < -0.07
    assert 0.07 < up["length_m"] < 0.11
    # tip speed from the path: below the Rayleigh speed of the model, none flagged ...
    assert r["rayleigh_speed_m_per_s"] == pytest.approx(
        0.9176 * math.sqrt(190e9 / (2 * (4 / 3)) / 8000.0), rel=1e-3
    )
    assert 1000.0 < r["max_speed_m_per_s"] < r["rayleigh_speed_m_per_s"]
    assert r["records_above_rayleigh"] == 0
    # ... while the old farthest-damaged-point tip jumps to the other notch
    assert r["old_tip_max_speed_m_per_s"] > r["rayleigh_speed_m_per_s"]
    assert np.max(r["history"]["old_tip_distance_m"]) > 0.11


@pytest.mark.long
def test_kalthoff_winkler_small(tmp_path) -> None:
    """dx = 1.25 mm (12 800 points, 450 steps; a few seconds). Measured: 59.9 deg.
    Tolerance 5 deg: moving the end of the 20 mm chord by one spacing sideways turns it
    by atan(1.25 / 20) = 3.6 deg, and one halving of dx moves the angle by 6.1 deg
    (59.9 -> 66.0), so a change of the model of the size of the discretisation error
    fails, grid-scale jitter of the path does not."""
    mod = _script()
    r = mod.run_one(1.25e-3, tmp_path / "kw", [], 2.0e-6, 0.02)
    assert r["n_points"] == 12800
    assert r["upper"]["initial_angle_deg"] == pytest.approx(59.9, abs=5.0)
    _check_common(r)


@pytest.mark.slow
def test_kalthoff_winkler_deck_resolution(tmp_path) -> None:
    """dx = 0.3125 mm, the deck's own resolution (204 800 points, 1799 steps; about 2 min
    on 2 cores). Measured 71.4 deg; experiment about 70 deg (Kalthoff & Winkler (1988)).
    Tolerance 3 deg: about 3 spacings sideways at the end of the 20 mm chord, and it
    keeps the angle within 5 deg of the experiment."""
    mod = _script()
    r = mod.run_one(3.125e-4, tmp_path / "kw", [], 2.0e-6, 0.02)
    assert r["n_points"] == 204800
    assert r["upper"]["initial_angle_deg"] == pytest.approx(71.4, abs=3.0)
    assert abs(r["upper"]["initial_angle_deg"] - 70.0) <= 5.0
    _check_common(r)
