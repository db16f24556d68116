"""Viscous bond forces (PD wave dispersion (n.d.), eqs 45-56): kernel == NumPy twin,
dissipation, momentum, bitwise identity with plain PD when switched off, coefficients and
stable step."""

from __future__ import annotations

import math

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.families.viscosity import BondViscosity, horizon_volume
from peridynamics.geometry import bar, box, rectangle
from peridynamics.kernels import reference
from peridynamics.solvers.explicit import ExplicitSolver

E, RHO = 193e9, 8027.0


def make(dim: int, viscosity: BondViscosity | None, seed: int = 0):
    dx = 1e-3
    if dim == 1:
        cloud = bar(0.03, dx, area=1e-4)
    elif dim == 2:
        cloud = rectangle((0.012, 0.010), dx, thickness=2e-3)
    else:
        cloud = box((0.006, 0.005, 0.004), dx)
    bonds = build_bonds(cloud, 3.015 * dx, "truncated")
    model = Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), viscosity=viscosity)
    rng = np.random.default_rng(seed)
    u = rng.normal(size=cloud.x.shape) * 1e-6
    v = rng.normal(size=cloud.x.shape) * 1.0
    intact = (rng.random(bonds.n_bonds) > 0.1).astype(np.uint8)
    rev = bonds.reverse_index()
    intact = np.minimum(intact, intact[rev])  # a bond is broken in both directions
    return model, u, v, intact


@pytest.mark.parametrize("dim", [1, 2, 3])
def test_viscous_kernel_matches_numpy_twin_and_conserves_momentum(dim: int) -> None:
    visc = BondViscosity(0.5, 2.0)
    model, u, v, intact = make(dim, visc)
    plain, *_ = make(dim, None)
    f_all, f_el = np.zeros_like(u), np.zeros_like(u)
    ms = np.zeros(model.n_points)
    model.internal_force(u, intact.copy(), f_all, ms, v)
    plain.internal_force(u, intact.copy(), f_el, ms)
    b = model.bonds
    lin, quad = visc.coefficients(dim, b.horizon, model.cloud.cross_section, E, RHO)
    f_ref = reference.viscous_force(
        model.cloud.x, u, v, b.bond_i, b.bond_j, b.bond_length, b.bond_volume, intact, lin, quad
    )
    f_visc = f_all - f_el
    assert np.abs(f_ref).max() > 0
    np.testing.assert_allclose(f_visc, f_ref, rtol=0, atol=1e-9 * np.abs(f_ref).max())
    vol = model.cloud.volume[:, None]
    momentum = np.abs((vol * f_ref).sum(axis=0)).max()
    assert momentum <= 1e-12 * np.abs(vol * f_ref).sum()
    if dim >= 2:  # central forces: no net torque about the origin
        y = model.cloud.x + u
        torque = np.sum(vol[:, 0] * (y[:, 0] * f_ref[:, 1] - y[:, 1] * f_ref[:, 0]))
        assert abs(torque) <= 1e-11 * np.sum(np.abs(vol * f_ref) * np.abs(y).max())


@pytest.mark.parametrize("dim", [1, 2, 3])
def test_viscous_power_is_never_positive(dim: int) -> None:
    model, _, _, intact = make(dim, BondViscosity(0.7, 3.0))
    for seed in range(5):
        rng = np.random.default_rng(seed)
        u = rng.normal(size=model.cloud.x.shape) * 1e-6
        v = rng.normal(size=model.cloud.x.shape)
        p = model.viscous_power(u, v, intact)
        assert p < 0
        # a rigid motion (translation) dissipates nothing
        assert model.viscous_power(u * 0, np.ones_like(v), intact) == pytest.approx(0, abs=1e-9)


def test_broken_bonds_carry_no_viscous_force() -> None:
    model, u, v, intact = make(2, BondViscosity(0.5, 2.0))
    none = np.zeros_like(intact)
    f = np.zeros_like(u)
    model.internal_force(u, none, f, np.zeros(model.n_points), v)
    assert not f.any()


def test_coefficients_and_1d_rate_equivalence() -> None:
    """alpha_p = rho v0 / V_H, alpha_q = rho delta / V_H, and b1 alpha_p = gamma c in 1-D
    with gamma = b1 delta / (4 v0) (PD wave dispersion (n.d.), eqs 39, 53)."""
    delta, area = 3.015e-3, 1e-4
    visc = BondViscosity(0.5, 2.0)
    lin, quad = visc.coefficients(1, delta, area, E, RHO)
    v0 = math.sqrt(E / RHO)
    assert lin == pytest.approx(0.5 * RHO * v0 / (2 * delta * area), rel=1e-14)
    assert quad == pytest.approx(4.0 * RHO * delta / (2 * delta * area), rel=1e-14)
    c = 2 * E / (area * delta**2)
    assert lin == pytest.approx(visc.rate_constant_1d(delta, E, RHO) * c, rel=1e-14)
    assert horizon_volume(2, 2.0, 0.5) == pytest.approx(math.pi * 2.0)
    assert horizon_volume(3, 1.0, 99.0) == pytest.approx(4 * math.pi / 3)
    with pytest.raises(ValueError, match="viscosity.linear"):
        BondViscosity(-0.1, 0.0)
    with pytest.raises(ValueError, match="viscosity.quadratic"):
        BondViscosity(0.0, float("nan"))


def _free_vibration(viscosity, steps=400, integrator="velocity_verlet"):
    model, *_ = make(2, viscosity)
    rng = np.random.default_rng(7)
    solver = ExplicitSolver(model, integrator=integrator)
    s = solver.init()
    s.v[:] = rng.normal(size=s.v.shape) * 0.1
    s.force[:] = 0
    model.internal_force(s.u, s.intact, s.force, s.max_stretch, s.v)
    energies, states = [], []
    f_el = np.zeros_like(s.u)
    rho_v = model.density * model.cloud.volume
    for _ in range(steps):
        solver.step(s)
        # the discrete energy velocity Verlet conserves for a linear elastic body:
        # KE + W - dt^2/8 sum rho V |a_el|^2 (the plain KE + W oscillates at O(dt^2))
        model.internal_force(s.u, s.intact, f_el, s.max_stretch, np.zeros_like(s.v))
        a2 = np.sum(f_el * f_el, axis=1) / model.density**2
        shadow = -(solver.dt**2) / 8 * float(np.sum(rho_v * a2))
        energies.append(model.kinetic_energy(s.v) + model.strain_energy(s.u, s.intact) + shadow)
        states.append(s.u.copy())
    return np.array(energies), np.array(states), solver


@pytest.mark.long
def test_viscosity_never_adds_energy_and_zero_coefficients_are_plain_pd_bitwise() -> None:
    e_plain, u_plain, _ = _free_vibration(None)
    e_zero, u_zero, _ = _free_vibration(BondViscosity(0.0, 0.0))
    assert np.array_equal(u_plain, u_zero) and np.array_equal(e_plain, e_zero)
    for visc in (BondViscosity(0.5, 0.0), BondViscosity(0.0, 2.0), BondViscosity(0.5, 2.0)):
        e, _, _ = _free_vibration(visc)
        assert np.all(np.diff(e) <= 1e-12 * e[0]), visc
        assert e[-1] < 0.99 * e[0]  # it does dissipate
    # plain PD keeps this energy, so the decrease is viscosity's
    assert np.abs(e_plain / e_plain[0] - 1).max() < 1e-5


def test_stable_step_shrinks_with_linear_viscosity() -> None:
    plain, *_ = make(1, None)
    visc, *_ = make(1, BondViscosity(1.0, 0.0))
    dt0, dt1 = plain.stable_time_step(), visc.stable_time_step()
    gamma = BondViscosity(1.0).rate_constant_1d(3.015e-3, E, RHO)
    xi = gamma / dt0
    assert dt1 == pytest.approx(dt0 * (math.sqrt(1 + xi * xi) - xi), rel=1e-6)
    assert dt1 < dt0


def test_viscous_dispersion_1d_seed003() -> None:
    """eq. 44: |v_i/v| = (b1/4) sqrt(S); b1 = 1 gives 0.408 at N_h = 0.5 (n = 3: S = 8/3);
    the complex root solves eq. 41; b1 = 0 is the undamped curve."""
    from peridynamics.analysis import semi_discrete_1d, viscous_1d

    nh = np.linspace(0.01, 2.0, 400)
    d = viscous_1d(nh, 3.015, 1.0)
    assert d.damping_ratio[np.argmin(abs(nh - 0.5))] == pytest.approx(
        math.sqrt(8 / 3) / 4, rel=1e-3
    )
    assert d.damping_ratio.max() == pytest.approx(math.sqrt(8 / 3) / 4, rel=1e-3)
    # periodic in N_h (non-selective): same ratio at N_h and N_h + 1
    a, b = viscous_1d([0.3, 1.3], 3.015, 1.0).damping_ratio
    assert a == pytest.approx(b, rel=1e-12)
    # the root satisfies v'^2 + i g v' - V^2 = 0 in v0 units, with g = -2 v_i
    v = semi_discrete_1d(nh, 3.015).v_over_v0
    root = d.v_real_over_v0 + 1j * d.v_imag_over_v0
    g = -2 * d.v_imag_over_v0
    under = d.v_real_over_v0 > 0
    resid = root**2 + 1j * g * root - v**2
    assert np.abs(resid[under]).max() < 1e-12
    undamped = viscous_1d(nh, 3.015, 0.0)
    np.testing.assert_allclose(undamped.v_real_over_v0, v, rtol=1e-14)
    assert not undamped.v_imag_over_v0.any()


def test_unstable_quadratic_viscosity_stops_with_a_named_point(tmp_path) -> None:
    """A square pulse's jump with b2 = 20 drives the explicit quadratic term unstable:
    the run stops, names a non-finite point and points at the quadratic coefficient."""
    from tests.helpers import EXAMPLES, cli

    proc = cli("run", str(EXAMPLES / "waves" / "pulse_square_plain.yaml"), "--out",
               str(tmp_path), "--set", "material.viscosity.quadratic=20")  # fmt: skip
    assert proc.returncode == 3
    assert "non-finite" in proc.stderr and "material.viscosity.quadratic" in proc.stderr
