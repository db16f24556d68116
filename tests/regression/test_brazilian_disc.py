"""The Brazilian-disc example (rigid platens, bilinear softening bonds) through its
script: small size by default, the three resolutions of the README as ``slow``.

Tolerances come from the measured values in the comments (AMD EPYC, 2 cores), with
margin."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from tests.helpers import EXAMPLES

HERE = EXAMPLES / "bodies"


def _script():
    spec = importlib.util.spec_from_file_location("bd_script", HERE / "brazilian_disc.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _run(tmp_path: Path, *ratios: str) -> dict:
    assert _script().main(["--ratios", *ratios, "--out", str(tmp_path)]) == 0
    assert (tmp_path / "brazilian_disc.png").stat().st_size > 1000
    return json.loads((tmp_path / "brazilian_disc.json").read_text())


@pytest.mark.long
def test_small_disc_splits_from_the_centre(tmp_path: Path) -> None:
    """D/dx = 30 (716 points): the first damage is at the centre, the crack runs along
    the loaded diameter, the strength is close to the bonds' f_t, the loading is
    quasi-static. Measured: strength 0.896 f_t (D/40: 0.905 f_t), onset at 0 R."""
    c = _run(tmp_path, "30")["cases"]["D30"]
    assert c["first_damage_distance_from_centre_over_R"] < 0.1
    assert c["first_damage_box_size_over_R"] < 0.2  # one spot, not both platens at once
    assert c["mean_offset_from_loaded_diameter_over_R"] < 0.25
    assert c["vertical_extent_over_D"] > 0.7
    assert 0.75 < c["strength_over_f_t"] < 1.05
    assert c["max_kinetic_to_strain_before_peak"] < 0.05


@pytest.mark.slow
def test_three_resolutions_converge(tmp_path: Path) -> None:
    """D/dx = 40, 60, 80 (the README's table). Measured: 0.905, 0.943, 0.969 f_t,
    spread 6.9 % (goal 5 %: missed), the steps shrinking (0.038, then 0.026)."""
    res = _run(tmp_path, "40", "60", "80")
    s = [res["cases"][k]["strength_over_f_t"] for k in ("D40", "D60", "D80")]
    assert s[0] < s[1] < s[2] < 1.05
    assert s[2] - s[1] < s[1] - s[0]
    assert res["strength_spread_over_mean"] < 0.1
    for c in res["cases"].values():
        assert c["first_damage_distance_from_centre_over_R"] < 0.1
