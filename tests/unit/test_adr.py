"""Unit tests of the PMB analytic tangent and of the ADR solver's pieces.

Oracles: central finite differences of ``V * force_of(u)`` for the tangent; the
equations of Kilic & Madenci (2010) written out in NumPy for the update kernels;
bit-for-bit equality for checkpoint/resume.
"""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, CriticalStretch, Evaluator, build_bonds
from peridynamics.families.pmb.tangent import pmb_tangent
from peridynamics.geometry import box, rectangle
from peridynamics.kernels.adr import adr_norms, adr_update
from peridynamics.loading import (
    BodyForce,
    Fixed,
    PrescribedDisplacement,
    PrescribedVelocity,
    Ramp,
)
from peridynamics.loading.conditions import Kinematic
from peridynamics.solvers.adr import ADRSolver
from peridynamics.solvers.explicit import SimulationUnstable

E, RHO = 70e9, 2700.0


# small problems: one Numba thread is faster than several (results do not depend on it)
pytestmark = pytest.mark.usefixtures("serial_numba")


def _plate_model(nx: int = 10, ny: int = 6, **kw: object) -> Evaluator:
    dx = 1e-3
    cloud = rectangle((nx * dx, ny * dx), dx)
    return Evaluator(cloud, build_bonds(cloud, 3.015 * dx), BondBasedMaterial(E, RHO), **kw)  # type: ignore[arg-type]


def _fd_tangent(model: Evaluator, u: np.ndarray, intact: np.ndarray, h: float) -> np.ndarray:
    """-d(V f)/du by central differences, dense (n dim, n dim)."""
    vol = model.cloud.volume[:, None]
    m = u.size
    out = np.empty((m, m))
    for c in range(m):
        up, um = u.copy(), u.copy()
        up.reshape(-1)[c] += h
        um.reshape(-1)[c] -= h
        df = vol * (model.force_of(up, intact) - model.force_of(um, intact))
        out[:, c] = -df.reshape(-1) / (2 * h)
    return out


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("amplitude", [0.0, 2e-6])
def test_pmb_tangent_equals_finite_differences(dim: int, amplitude: float) -> None:
    if dim == 2:
        cloud = rectangle((8e-3, 5e-3), 1e-3)
    else:
        cloud = box((4e-3, 4e-3, 3e-3), 1e-3)
    model = Evaluator(cloud, build_bonds(cloud, 3.015e-3), BondBasedMaterial(E, RHO))
    u = np.random.default_rng(dim).normal(0.0, amplitude, cloud.x.shape)
    s = model.new_state()
    s.u[...] = u
    k = model.tangent(s)
    assert k.shape == (u.size, u.size)
    dense = k.toarray()
    fd = _fd_tangent(model, u, s.intact, h=1e-9)
    scale = np.abs(dense).max()
    assert np.abs(dense - fd).max() <= 1e-6 * scale
    assert np.abs(dense - dense.T).max() <= 1e-13 * scale
    # u = 0: positive semi-definite with the rigid motions (3 in 2-D, 6 in 3-D) as kernel
    if amplitude == 0.0:
        eig = np.linalg.eigvalsh(0.5 * (dense + dense.T))
        n_rigid = 3 if dim == 2 else 6
        assert np.all(eig > -1e-9 * scale)
        assert np.all(np.abs(eig[:n_rigid]) < 1e-9 * scale)
        assert eig[n_rigid] > 1e-6 * scale


def test_pmb_tangent_skips_broken_bonds() -> None:
    model = _plate_model(8, 5)
    s = model.new_state()
    rng = np.random.default_rng(3)
    s.u[...] = rng.normal(0.0, 1e-6, s.u.shape)
    rev = model.bonds.reverse_index()
    cut = rng.random(model.bonds.n_bonds) < 0.2
    cut |= cut[rev]  # both directions of a bond fail together
    s.intact[cut] = 0
    dense = pmb_tangent(model.force_model, s).toarray()  # type: ignore[arg-type]
    fd = _fd_tangent(model, s.u, s.intact, h=1e-9)
    assert np.abs(dense - fd).max() <= 1e-6 * np.abs(dense).max()


def test_update_kernel_follows_the_adr_equations() -> None:
    rng = np.random.default_rng(0)
    m = 13
    u, v = rng.normal(size=m), rng.normal(size=m)
    f, b = rng.normal(size=m), rng.normal(size=m)
    lam = rng.uniform(1.0, 2.0, m)
    free = (rng.random(m) < 0.7).astype(np.uint8)
    target = rng.normal(size=m)
    c, dt = 0.37, 1.0
    # V^{n+1/2} = ((2 - c dt) V^{n-1/2} + 2 dt F / lambda) / (2 + c dt); U += dt V
    v_ref = ((2 - c * dt) * v + 2 * dt * (f + b) / lam) / (2 + c * dt)
    u_ref = u + dt * v_ref
    uu, vv = u.copy(), v.copy()
    adr_update(uu, vv, f, b, 1.0 / lam, free, target, c, dt, False)
    fr = free == 1
    np.testing.assert_allclose(vv[fr], v_ref[fr], rtol=1e-14)
    np.testing.assert_allclose(uu[fr], u_ref[fr], rtol=1e-14)
    assert np.all(vv[~fr] == 0.0) and np.array_equal(uu[~fr], target[~fr])
    # first step: V^{1/2} = dt F^0 / (2 lambda)
    uu, vv = u.copy(), v.copy()
    adr_update(uu, vv, f, b, 1.0 / lam, free, target, c, dt, True)
    np.testing.assert_allclose(vv[fr], (0.5 * dt * (f + b) / lam)[fr], rtol=1e-14)


def test_norm_kernel_follows_the_adr_equations() -> None:
    rng = np.random.default_rng(1)
    m = 1001  # more dofs than chunks, not a multiple of them
    u, v = rng.normal(size=m), rng.normal(size=m)
    v[::7] = 0.0
    f, fp, b = rng.normal(size=m), rng.normal(size=m), rng.normal(size=m)
    vol, lam = rng.uniform(1, 2, m), rng.uniform(1, 2, m)
    free = (rng.random(m) < 0.8).astype(np.uint8)
    out = np.zeros(4)
    adr_norms(u, v, f, fp, b, vol, 1.0 / lam, free, 1.0, out)
    fr = free == 1
    r = vol * (f + b)
    with np.errstate(divide="ignore", invalid="ignore"):
        k_local = np.where(v != 0, -(f - fp) / (lam * v), 0.0)  # 1K_ii, dt = 1
    expected = [
        np.sum(r[fr] ** 2),
        np.sum(r[~fr] ** 2),
        np.sum((u * u * k_local)[fr]),
        np.sum(u[fr] ** 2),
    ]
    np.testing.assert_allclose(out, expected, rtol=1e-12)


def test_fictitious_density_from_the_stiffness_bound() -> None:
    model = _plate_model()
    tight = ADRSolver(model).lam  # the per-point bound lowered by the Lanczos estimate
    model.use_spectral_bound = False
    solver = ADRSolver(model)
    assert np.all(tight <= solver.lam) and np.any(tight < solver.lam)
    bound = model.stiffness_bound()
    np.testing.assert_array_equal(solver.lam, np.repeat(bound, 2))  # factor 4: 4/4 dt^2 K_i
    # Gershgorin stability for PMB: sum_j |K_ij| / (V_i lambda_i) <= 4 / dt^2
    s = model.new_state()
    k = abs(model.tangent(s)).sum(axis=1).A1 / np.repeat(model.cloud.volume, 2)
    assert np.all(k / solver.lam <= (1 + np.sqrt(2)) + 1e-12)
    assert np.all(k / solver.lam < 4.0)


def test_constructor_refuses_bad_input() -> None:
    model = _plate_model()
    nodes = np.array([0])
    with pytest.raises(ValueError, match="prescribed velocity"):
        ADRSolver(model, [PrescribedVelocity(nodes, {"x": 1.0})])
    for kw in (
        {"load_steps": 0},
        {"tolerance": 0.0},
        {"tolerance": 1.0},
        {"max_iterations": 0},
        {"max_damage_rounds": 0},
        {"load_time": 0.0},
        {"density_factor": 2.0},
    ):
        with pytest.raises(ValueError):
            ADRSolver(model, **kw)  # type: ignore[arg-type]


def test_load_stepping_scales_loads_and_displacements() -> None:
    model = _plate_model(nx=6, ny=4)
    x = model.cloud.x
    right = np.flatnonzero(x[:, 0] > 5e-3)
    left = np.flatnonzero(x[:, 0] < 1e-3)
    bc: list[Kinematic] = [Fixed(left), PrescribedDisplacement(right, {"x": 1e-6})]
    solver = ADRSolver(model, bc, load_steps=4, tolerance=1e-9)
    s = solver.init()
    assert s.step == 0 and np.all(s.u == 0)
    solver.step(s)
    solver.step(s)
    assert s.step == 2 and s.t == pytest.approx(0.5)
    assert np.all(s.u[right, 0] == 0.5e-6) and np.all(s.u[left] == 0.0)
    assert np.all(s.v == 0.0)
    # not proportional: the time function alone, evaluated at t_k = k/N * load_time
    ramp: list[Kinematic] = [Fixed(left), PrescribedDisplacement(right, {"x": 1e-6}, Ramp(end=2.0))]
    solver = ADRSolver(model, ramp, load_steps=4, proportional=False, load_time=2.0)
    s = solver.init()
    solver.step(s)
    assert s.t == pytest.approx(0.5)
    assert np.all(s.u[right, 0] == pytest.approx(0.25e-6, rel=1e-14))
    # body forces: lambda_k b(t_k)
    body = BodyForce(right, (1e9, 0.0))
    model_b = _plate_model(nx=6, ny=4, body_forces=[body])
    solver = ADRSolver(model_b, [Fixed(left)], load_steps=4)
    s = solver.init()
    solver.step(s)
    assert np.all(s.body[right, 0] == 0.25e9) and np.all(s.body[left] == 0.0)


def _pulled_model(s0: float) -> tuple[Evaluator, list[Kinematic]]:
    cloud = rectangle((12e-3, 6e-3), 1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    model = Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), CriticalStretch(s0))
    x = cloud.x
    left = np.flatnonzero(x[:, 0] < 1e-3)
    right = np.flatnonzero(x[:, 0] > 11e-3)
    return model, [Fixed(left), PrescribedDisplacement(right, {"x": 2e-5})]


def test_resume_continues_bit_for_bit() -> None:
    model, bc = _pulled_model(1.2e-3)
    solver = ADRSolver(model, bc, load_steps=5, tolerance=1e-7)
    s = solver.init()
    while not solver.done(s):
        solver.step(s)
    assert s.bonds_broken > 0  # damage in the run, so the history fields matter
    model2, bc2 = _pulled_model(1.2e-3)
    first = ADRSolver(model2, bc2, load_steps=5, tolerance=1e-7)
    part = first.init()
    for _ in range(2):
        first.step(part)
    saved = part.copy()  # what a checkpoint holds
    model3, bc3 = _pulled_model(1.2e-3)
    second = ADRSolver(model3, bc3, load_steps=5, tolerance=1e-7)
    second.resume(saved)
    while not second.done(saved):
        second.step(saved)
    for name in s:
        assert np.array_equal(s[name], saved[name], equal_nan=True), name
    assert saved.bonds_broken == s.bonds_broken
    assert second.summary_fields(saved) == solver.summary_fields(s)


def test_resume_refuses_a_state_without_history() -> None:
    model, bc = _pulled_model(1.0)
    solver = ADRSolver(model, bc, load_steps=3)
    with pytest.raises(ValueError, match="ADR history"):
        solver.resume(model.new_state())


def test_non_finite_state_raises_simulation_unstable() -> None:
    model, bc = _pulled_model(1.0)
    solver = ADRSolver(model, bc, load_steps=3)
    s = solver.init()
    solver.step(s)
    s.u[7, 1] = np.nan
    with pytest.raises(SimulationUnstable, match="point 7") as info:
        solver.check(s)
    assert "load step 1" in str(info.value)
    assert info.value.point == 7 and info.value.last_good is not None
    assert np.isfinite(info.value.last_good.u).all()


def test_summary_fields() -> None:
    model, bc = _pulled_model(1.0)
    solver = ADRSolver(model, bc, load_steps=2, tolerance=1e-6)
    s = solver.init()
    r = solver.step(s)
    assert r.accepted and r.converged and r.residual <= 1e-6 and r.iterations > 0
    out = solver.summary_fields(s)
    assert out["solver"] == "adr" and out["load_steps"] == 2 and out["load_steps_done"] == 1
    assert out["iterations"] == r.iterations == out["iterations_per_load_step"][0]
    assert out["residual"] == r.residual and out["converged"] is True
    assert out["time_step_s"] is None and out["not_converged_load_steps"] == []
    assert not solver.done(s) and solver.total_steps() == 2
