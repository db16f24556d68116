"""output.crack_paths through the command line: the Kalthoff-Winkler deck at a coarse
grid (2.5 mm) gives the measured path of each notch crack, symmetric, never faster than
the Rayleigh speed of the model as run."""

from __future__ import annotations

import json

import pytest

from tests.helpers import EXAMPLES, cli

pytestmark = pytest.mark.long  # a Kalthoff-Winkler run (CI: pytest -m long)


def test_kalthoff_winkler_crack_paths_in_summary(tmp_path) -> None:
    out = tmp_path / "kw"
    cli("run", str(EXAMPLES / "kalthoff_winkler" / "deck.yaml"), "--out", str(out), "--quiet",
        "--set", "discretisation.spacing=2.5e-3", check=True)  # fmt: skip
    r = json.loads((out / "summary.json").read_text())["results"]
    upper, lower = r["crack_paths"]["upper"], r["crack_paths"]["lower"]
    # measured 40.7 deg over the first 20 mm at dx = 2.5 mm (71.4 deg at 0.3125 mm, see
    # examples/kalthoff_winkler/README.md); one spacing sideways at the end of the
    # 20 mm chord turns it by 7 deg at this grid
    assert upper["initial_angle_deg"] == pytest.approx(40.7, abs=7.0)
    assert lower["initial_angle_deg"] == pytest.approx(-upper["initial_angle_deg"], abs=1e-6)
    assert upper["length_m"] == pytest.approx(lower["length_m"], rel=1e-9)
    assert upper["length_m"] > 0.05  # the crack runs most of the way to the far edge
    # the surface-corrected model runs at the nominal E: c_R of nu = 1/3 plane stress
    assert r["effective_modulus_ratio"] == pytest.approx(1.0, abs=0.01)
    assert r["rayleigh_speed_m_per_s"] == pytest.approx(2744, rel=0.01)
    assert 0 < upper["max_tip_speed_m_per_s"] < r["rayleigh_speed_m_per_s"]
    assert upper["above_rayleigh_speed"] == 0
    assert len(upper["vertices_m"]) >= 3 and len(upper["tip_speed_m_per_s"]) == len(upper["time_s"])
