"""Sensitivities of the linear static solve to E and nu (LPS plate in plane stress):
the direct derivatives of u and of the reactions, and the adjoint derivative of a
scalar output, against central finite differences of the whole solve (<= 1e-6
relative; measured: see docs/calibration.md)."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics.bonds import build_bonds
from peridynamics.families.lps.material import LPSMaterial
from peridynamics.geometry import rectangle
from peridynamics.solvers.linear_sensitivity import (
    finite_difference_check,
    linear_static_sensitivities,
)
from peridynamics.solvers.linear_static import solve_linear_static

DX = 1e-3
E, NU, RHO = 70.0e9, 0.3, 2700.0


@pytest.fixture(scope="module")
def plate():
    """A 12 x 6 plate: the left column fixed in x, its first point in y too; the
    right column pulled by a prescribed displacement (the reactions scale with the
    moduli) and pushed sideways by a body force (u depends on E and nu)."""
    cloud = rectangle((12 * DX, 6 * DX), DX, plane="stress")
    bonds = build_bonds(cloud, 3.015 * DX, "truncated")
    x = cloud.x
    left = np.flatnonzero(x[:, 0] < x[:, 0].min() + 0.5 * DX)
    right = np.flatnonzero(x[:, 0] > x[:, 0].max() - 0.5 * DX)
    fixed = np.concatenate([2 * left, [2 * left[0] + 1], 2 * right])
    values = np.zeros(fixed.size)
    values[-right.size :] = 1.0e-5  # m
    body = np.zeros((len(x), 2))
    body[right, 1] = 2.0e5 / DX  # N/m^3, a shear part

    def model_at(p):
        return LPSMaterial(float(p[0]), float(p[1]), RHO).force_model(cloud, bonds)

    return model_at, fixed, values, body


def _solve(model_at, fixed, values, body):
    def run(p):
        return solve_linear_static(model_at(p), fixed, values, body)

    return run


def _reactions(model_at, fixed, values, body):
    from peridynamics.solvers.linear_sensitivity import _system

    def run(p):
        model = model_at(p)
        u = solve_linear_static(model, fixed, values, body)
        k, rhs = _system(model, body)
        return (k @ u.reshape(-1) - rhs)[fixed]

    return run


def _rel(a, b):
    return float(np.abs(a - b).max() / np.abs(b).max())


def test_direct_and_adjoint_match_central_differences(plate, serial_numba):
    model_at, fixed, values, body = plate
    p = [E, NU]
    g = np.zeros(body.size)
    g[1::2] = 1.0e6  # J = 1e6 N/m * sum of u_y + the pulling force on the right column
    a = (values > 0).astype(float)
    sens, dj = linear_static_sensitivities(model_at, p, fixed, values, body, adjoint=(g, a))
    u_ref = solve_linear_static(model_at(p), fixed, values, body)
    assert _rel(sens.u, u_ref) < 1e-12
    fd_u = finite_difference_check(_solve(model_at, fixed, values, body), p)
    fd_r = finite_difference_check(_reactions(model_at, fixed, values, body), p)
    for k, name in enumerate(("E", "nu")):
        err_u, err_r = _rel(sens.du_dp[k], fd_u[k]), _rel(sens.dreactions_dp[k], fd_r[k])
        print(f"{name}: du/dp {err_u:.2e}, dR/dp {err_r:.2e} (relative to central differences)")
        assert err_u <= 1e-6 and err_r <= 1e-6, name
    # equilibrium in x: the reactions on the x dofs sum to zero for every E and nu
    on_x = fixed % 2 == 0
    scale = np.abs(sens.reactions).max()
    assert abs(sens.reactions[on_x].sum()) < 1e-9 * scale
    assert np.abs(sens.dreactions_dp[:, on_x].sum(axis=1)).max() < 1e-9 * scale / np.array(p).min()
    # adjoint == direct for J = g.u + a.R
    direct = np.array([g @ sens.du_dp[k].reshape(-1) + a @ sens.dreactions_dp[k]
                       for k in range(2)])  # fmt: skip
    assert dj is not None
    print("adjoint against direct:", np.abs(dj - direct) / np.abs(direct))
    np.testing.assert_allclose(dj, direct, rtol=1e-10, atol=1e-12 * np.abs(direct).max())
    # E enters linearly in K: E dR/dE = R minus the part of the body force (which does
    # not scale), and E du/dE = -(u of the body force alone)
    u_body = solve_linear_static(model_at(p), fixed, 0.0, body)
    assert _rel(E * sens.du_dp[0], -u_body) < 1e-8


def test_bad_input_is_named(plate):
    model_at, fixed, _, body = plate
    with pytest.raises(ValueError, match="external_force"):
        linear_static_sensitivities(model_at, [E, NU], fixed, 0.0, body[:-1])
    with pytest.raises(ValueError, match="params\\[1\\]"):
        linear_static_sensitivities(model_at, [E, 0.0], fixed, 0.0, body)
