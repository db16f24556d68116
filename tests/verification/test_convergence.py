"""delta-convergence at fixed m = delta/dx: the PD force density of a smooth field tends
to the local (Navier) operator at second order in delta.

1-D: u = A sin(kx), f -> E u''. 2-D plane stress with the energy surface correction
(which removes the O(1) lattice error of the partial-volume rule at fixed m):
u = (A sin(kx), 0), f_x -> E/(1 - nu^2) u_xx with nu = 1/3, f_y -> 0.
Amplitudes are tiny so that the geometric nonlinearity of the stretch does not set a
floor.
"""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics.bonds import build_bonds
from peridynamics.evaluation import Evaluator
from peridynamics.families.pmb import BondBasedMaterial
from peridynamics.geometry import bar, rectangle

E = 70e9


def _force(model: Evaluator, u: np.ndarray) -> np.ndarray:
    f = np.zeros_like(u)
    model.internal_force(u, model.bonds.bond_intact.copy(), f, np.zeros(model.n_points))
    return f


def _error_1d(dx: float, m: int = 3) -> float:
    k = 2 * np.pi / 0.25
    cloud = bar(1.0, dx)
    model = Evaluator(cloud, build_bonds(cloud, m * dx), BondBasedMaterial(E, 2700.0))
    x = cloud.x[:, 0]
    f = _force(model, (1e-9 * np.sin(k * x))[:, None])[:, 0]
    exact = -E * 1e-9 * k * k * np.sin(k * x)
    inner = (x > 0.1) & (x < 0.9)
    return float(np.abs(f[inner] - exact[inner]).max() / np.abs(exact).max())


def _error_2d(dx: float, corrected: bool = True) -> tuple[float, float]:
    k, size, m = 2 * np.pi / 0.02, (0.04, 0.02), 3.015
    cloud = rectangle(size, dx)
    model = Evaluator(
        cloud,
        build_bonds(cloud, m * dx),
        BondBasedMaterial(E, 2700.0),
        surface_correction=corrected,
    )
    x = cloud.x
    u = np.zeros_like(x)
    u[:, 0] = 1e-10 * np.sin(k * x[:, 0])
    f = _force(model, u)
    exact = -E / (1 - 1 / 9) * 1e-10 * k * k * np.sin(k * x[:, 0])
    margin = 2 * m * dx + 0.002
    inner = np.all((x > margin) & (x < np.asarray(size) - margin), axis=1)
    scale = np.abs(exact).max()
    return (
        float(np.abs(f[inner, 0] - exact[inner]).max() / scale),
        float(np.abs(f[inner, 1]).max() / scale),
    )


def test_1d_second_order_in_delta() -> None:
    errors = [_error_1d(dx) for dx in (4e-3, 2e-3, 1e-3)]
    rates = np.log2(np.array(errors[:-1]) / errors[1:])
    assert errors[-1] < 3e-4  # measured 2.6e-4
    np.testing.assert_allclose(rates, 2.0, atol=0.05)  # measured 1.997, 1.999


def test_2d_second_order_in_delta_with_surface_correction() -> None:
    results = [_error_2d(dx) for dx in (5e-4, 2.5e-4, 1.25e-4)]
    errors = [r[0] for r in results]
    rates = np.log2(np.array(errors[:-1]) / errors[1:])
    np.testing.assert_allclose(rates, 2.0, atol=0.1)  # measured 1.995, 1.998
    assert max(r[1] for r in results) < 1e-6  # no spurious transverse force


@pytest.mark.parametrize("dx", [5e-4, 2.5e-4])
def test_2d_without_correction_keeps_the_lattice_error(dx: float) -> None:
    # the truncated partial-volume rule at m = 3.015 is 14 % too soft in the bulk:
    # refining at fixed m does not remove it (why the correction exists)
    assert 0.13 < _error_2d(dx, corrected=False)[0] < 0.16
