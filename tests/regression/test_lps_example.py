"""examples/lps: LPS plate with a circular hole (plane stress, nu = 0.3, static ADR)
against Kirsch (1898), at a small size and (slow) at the size of the README.

Tolerances come from the measured runs listed in examples/lps/README.md.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from tests.helpers import EXAMPLES

SCRIPT = EXAMPLES / "lps" / "kirsch.py"
DECK = EXAMPLES / "lps" / "plate_hole.yaml"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _load_script():
    spec = importlib.util.spec_from_file_location("lps_kirsch", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _rows_beyond(res: dict, r_over_a: float) -> list[dict]:
    return [row for row in res["profile"] if row["r_over_a"] >= r_over_a]


def _check_outputs(res: dict, out: Path) -> None:
    assert res["run"]["converged"] is True
    saved = json.loads((out / "kirsch.json").read_text())
    assert saved["kt_pd_extrapolated"] == pytest.approx(res["kt_pd_extrapolated"])
    png = out / "kirsch.png"
    assert png.read_bytes()[:8] == PNG_SIGNATURE
    assert png.stat().st_size > 20_000


def test_nonlocal_stress_is_exact_for_an_affine_field() -> None:
    """The least-squares gradient reproduces a homogeneous strain at every point, also on
    the truncated families at the hole and the plate edges; Hooke's law in plane stress."""
    mod = _load_script()
    from peridynamics.build.cloud import build_bonds_for, build_cloud
    from peridynamics.deck import load_deck

    deck = load_deck(DECK, ["discretisation.spacing=2.0e-3"])
    cloud = build_cloud(deck)
    bonds = build_bonds_for(deck, cloud)
    grad = np.array([[1.0e-4, 3.0e-5], [-1.0e-5, -2.5e-5]])
    u = cloud.x @ grad.T + np.array([1e-6, -2e-6])
    sigma, eps = mod.nonlocal_stress(cloud.x, u, bonds, 70e9, 0.3)
    eps_exact = 0.5 * (grad + grad.T)
    assert np.allclose(eps, eps_exact, rtol=0, atol=1e-12)
    c = 70e9 / (1 - 0.3**2)
    sxx = c * (eps_exact[0, 0] + 0.3 * eps_exact[1, 1])
    syy = c * (eps_exact[1, 1] + 0.3 * eps_exact[0, 0])
    sxy = 70e9 / 1.3 * eps_exact[0, 1]
    assert np.allclose(sigma[:, 0, 0], sxx, rtol=1e-9)
    assert np.allclose(sigma[:, 1, 1], syy, rtol=1e-9)
    assert np.allclose(sigma[:, 0, 1], sxy, rtol=1e-9)
    # Kirsch's sigma_xx on theta = 90 deg is the closed-form profile
    r = np.linspace(1.0, 8.0, 9)
    assert np.allclose(mod.kirsch_sigma_xx(0.0 * r, r, 1.0, 1.0), mod.kirsch_profile(r, 1.0))
    assert mod.kirsch_sigma_xx(np.array([0.0]), np.array([1.0]), 1.0, 1.0)[0] == 3.0
    # Howland / Peterson finite-width factor: 3 for an infinite plate
    assert mod.peterson_kt(0.0)["gross"] == pytest.approx(3.0, abs=0.01)


def test_finite_plate_reference_tends_to_kirsch() -> None:
    """The FE reference of the example: an 80a x 80a plate is Kirsch's infinite plate
    within 0.2 % for r >= 1.5 a (measured with 60 x 60 elements); the 16a x 16a plate of
    the deck is not (+3.3 % at 2 a, +1.7 % at 4 a: finite width and length)."""
    mod = _load_script()
    r = np.array([1.5, 2.0, 3.0, 4.0])
    wide = mod.fe_plate_hole(1.0, 40.0, 40.0, 0.3, n=60)
    assert np.interp(r, wide["r"], wide["sigma_xx"]) == pytest.approx(
        mod.kirsch_profile(r, 1.0), rel=3e-3
    )
    plate = mod.fe_plate_hole(1.0, 8.0, 8.0, 0.3, n=60)
    excess = np.interp(r, plate["r"], plate["sigma_xx"]) / mod.kirsch_profile(r, 1.0) - 1
    assert np.all(excess > 0.015)
    assert excess[1] == pytest.approx(0.033, abs=0.002)


@pytest.mark.long
def test_plate_hole_small_size_matches_kirsch(tmp_path: Path) -> None:
    """a = 5 dx (6320 points, delta = 0.8 a). Measured at r = a + 2 delta (2.61 a), 3 a,
    4 a: +0.66, +0.50, -0.56 % against Kirsch; -2.14, -2.01, -2.17 % against the same
    finite plate by FE (whose own excess over Kirsch, +2.9 % to +1.7 % there, offsets the
    PD deficit). No concentration is asserted: with delta = 0.8 a the fit from
    [a + delta, a + 3 delta] misses even on the FE profile (2.98 against 3.14)."""
    mod = _load_script()
    res = mod.main(["--spacing", "1.0e-3", "--out", str(tmp_path)])
    _check_outputs(res, tmp_path)
    assert res["a_over_dx"] == pytest.approx(5.0)
    rows = _rows_beyond(res, 1.0 + 2.0 * res["delta_over_a"] - 1e-9)
    assert len(rows) >= 3
    for row in rows:
        assert abs(row["relative_error"]) < 0.01, row["at"]
        assert -0.03 < row["relative_error_vs_fe"] < 0.0, row["at"]
    assert res["section_balance"] == pytest.approx(0.956, abs=0.01)


@pytest.mark.slow
def test_plate_hole_readme_size_matches_kirsch(tmp_path: Path) -> None:
    """The deck as shipped (a = 10 dx, 25 284 points; examples/lps/README.md). Measured
    at r = a + 2 delta (1.80 a), 2 a, 3 a, 4 a: +0.88, +1.18, +1.27, +0.36 % against
    Kirsch, -2.46, -2.04, -1.26, -1.27 % against the finite plate (FE); concentration
    extrapolated from [a + delta, a + 3 delta] 3.088, FE 3.136 (-1.5 %)."""
    mod = _load_script()
    res = mod.main(["--out", str(tmp_path)])
    _check_outputs(res, tmp_path)
    assert res["a_over_dx"] == pytest.approx(10.0)
    rows = _rows_beyond(res, 1.0 + 2.0 * res["delta_over_a"] - 1e-9)
    assert len(rows) >= 4
    for row in rows:
        assert abs(row["relative_error"]) < 0.02, row["at"]
        assert -0.035 < row["relative_error_vs_fe"] < 0.0, row["at"]
    assert res["kt_pd_extrapolated"] == pytest.approx(res["kt_finite_plate_fe"], rel=0.03)
    assert res["kt_pd_extrapolated"] == pytest.approx(3.0, rel=0.05)
