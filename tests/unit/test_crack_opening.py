"""Crack-opening profile and K_I by displacement extrapolation: the Williams mode-I
near-tip field sampled on a grid, the exact opening of Griffith's crack (Westergaard),
a rotated crack line and the refusals."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics.analysis.crack_opening import (
    crack_opening,
    k_and_tip_from_opening,
    k_from_opening,
    lefm_opening,
)
from tests.unit.test_j_integral import DX, K_I, E, _williams


def _grid() -> np.ndarray:
    g = (np.arange(-30, 30) + 0.5) * DX
    return np.stack(np.meshgrid(g, g, indexing="ij"), -1).reshape(-1, 2)


def test_williams_opening_profile_on_a_grid() -> None:
    """The bins of a cell-centred grid (points at +-dx/2 from the crack line): measured
    COD / (8 K/E sqrt(r/2pi)) = 0.9941 in the bin at the tip (r = 0.5 dx), within
    7.4e-4 from r = 3.5 dx on and 8.5e-5 from 10 dx on."""
    x = _grid()
    u, _ = _williams(x)
    s, cod = crack_opening(x, u, [(-0.03, 0.0), (0.0, 0.0)], DX)
    r = 0.03 - s
    assert len(s) == 30 and r.min() == pytest.approx(0.5 * DX)
    ratio = cod / lefm_opening(r, K_I, E)
    assert np.all(np.abs(ratio[r > 3 * DX] - 1.0) < 1e-3)
    assert np.all(np.abs(ratio[r > 10 * DX] - 1.0) < 1e-4)
    assert abs(ratio[-1] - 1.0) < 0.01


def test_williams_k_by_extrapolation() -> None:
    """Window 3 to 15 dx behind the tip: measured K/K_I = 0.99936."""
    x = _grid()
    u, _ = _williams(x)
    s, cod = crack_opening(x, u, [(-0.03, 0.0), (0.0, 0.0)], DX)
    k, r_fit, k_app = k_from_opening(0.03 - s, cod, E, (3 * DX, 15 * DX))
    assert k / K_I == pytest.approx(1.0, abs=1e-3)
    assert len(r_fit) == 12 and k_app.shape == r_fit.shape


def test_griffith_opening_extrapolates_the_next_term() -> None:
    """Griffith crack of half length a in an infinite plane stress plate under a remote
    sigma: COD = 4 sigma/E sqrt(a^2 - x^2) (Westergaard), K = sigma sqrt(pi a). K(r) =
    K sqrt(1 - r/2a) falls by 5 % over r < a/5; the straight line recovers K within
    measured 0.046 % (the r^2 term left)."""
    a, sig = 0.02, 10e6
    x = np.linspace(0.0, a, 401)[:-1]
    cod = 4 * sig / E * np.sqrt(a**2 - x**2)
    k, _, k_app = k_from_opening(a - x, cod, E, (0.05 * a, 0.2 * a))
    k_ref = sig * np.sqrt(np.pi * a)
    assert k_app.min() / k_ref < 0.96
    assert k / k_ref == pytest.approx(1.0, abs=1e-3)


def test_griffith_opening_with_a_shifted_tip() -> None:
    """The same crack read with the tip assumed 0.5 mm short of the true one: the
    straight line in r is off (measured K/K_ref = 1.108), the fit with the tip finds K
    and the shift to round-off (COD^2 is a quadratic in r)."""
    a, sig, d = 0.02, 10e6, 5e-4
    x = np.linspace(0.0, a, 401)[:-1]
    cod = 4 * sig / E * np.sqrt(a**2 - x**2)
    k_ref = sig * np.sqrt(np.pi * a)
    r = a - d - x
    k_lin, _, _ = k_from_opening(r, cod, E, (0.1 * a, 0.4 * a))
    k, shift = k_and_tip_from_opening(r, cod, E, (0.1 * a, 0.4 * a))
    assert k_lin / k_ref > 1.04
    assert k / k_ref == pytest.approx(1.0, abs=1e-9)
    assert shift == pytest.approx(d, rel=1e-6)


def test_rotated_line_and_3d_points() -> None:
    """The profile does not depend on the frame; 3-D points are read in the plane."""
    x = _grid()
    u, _ = _williams(x)
    want = crack_opening(x, u, [(-0.03, 0.0), (0.0, 0.0)], DX)
    rot = np.array([[0.0, -1.0], [1.0, 0.0]])
    xr, ur = x @ rot.T + 0.01, u @ rot.T
    z = np.zeros((len(x), 1))
    got = crack_opening(np.hstack([xr, z]), np.hstack([ur, z]), [(0.01, -0.02), (0.01, 0.01)], DX)
    np.testing.assert_allclose(got[0], want[0], rtol=1e-12)
    np.testing.assert_allclose(got[1], want[1], rtol=1e-9)


def test_refusals() -> None:
    x = _grid()
    u = np.zeros_like(x)
    with pytest.raises(ValueError, match="coincide"):
        crack_opening(x, u, [(0.0, 0.0), (0.0, 0.0)], DX)
    with pytest.raises(ValueError, match="spacing"):
        crack_opening(x, u, [(0.0, 0.0), (0.01, 0.0)], 0.0)
    with pytest.raises(ValueError, match="two"):
        k_from_opening(np.array([1e-3, 2e-3]), np.ones(2), E, (5e-3, 6e-3))
