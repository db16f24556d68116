"""Explicit solver: stable time step, refusal of unstable steps, blow-up detection."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, ExplicitSolver, State, build_bonds
from peridynamics.geometry import bar, rectangle
from peridynamics.solvers import SimulationUnstable, UnstableTimeStep

E, RHO = 200e9, 7850.0
DX = 1e-3


def bar_model(horizon_ratio=1.0, rule="truncated"):
    cloud = bar(0.05, DX, area=1e-4)
    return Evaluator(
        cloud,
        build_bonds(cloud, horizon_ratio * DX, partial_volume=rule),
        BondBasedMaterial(E, RHO),
    )


def test_stable_time_step_1d_nearest_neighbour_equals_cfl():
    """delta = dx, truncated: c = 2E/(A dx^2), weight 1/2, so stiffness/|xi| = E/dx^2 per
    bond, two bonds: dt = sqrt(2 rho dx^2 / (2 E)) = dx / sqrt(E / rho)."""
    model = bar_model()
    solver = ExplicitSolver(model)
    assert solver.stable_time_step == pytest.approx(DX / math.sqrt(E / RHO), rel=1e-12)
    assert solver.dt == pytest.approx(0.8 * solver.stable_time_step, rel=1e-15)
    assert ExplicitSolver(model, safety_factor=0.5).dt == pytest.approx(
        0.5 * solver.stable_time_step, rel=1e-15
    )


def test_stable_time_step_1d_three_neighbours():
    """delta = 3 dx, truncated: weights 1, 1, 1/2 at 1, 2, 3 dx; c = 2E/(9 A dx^2);
    sum over both sides of c beta A dx / (n dx) = (4/9)(1 + 1/2 + 1/6) E/dx^2."""
    model = bar_model(3.0)
    acc = (4.0 / 9.0) * (1 + 0.5 + 1 / 6) * E / DX**2
    spectral = ExplicitSolver(model).stable_time_step  # the Lanczos estimate: longer
    model.use_spectral_bound = False
    analytic = ExplicitSolver(model).stable_time_step
    assert analytic == pytest.approx(math.sqrt(2 * RHO / acc), rel=1e-12)
    assert spectral > analytic


def test_time_step_above_limit_is_refused_unless_allowed():
    model = bar_model()
    stable = ExplicitSolver(model).stable_time_step
    with pytest.raises(UnstableTimeStep, match="allow_unstable") as info:
        ExplicitSolver(model, time_step=1.01 * stable)
    assert isinstance(info.value, ValueError)
    ok = ExplicitSolver(model, time_step=1.01 * stable, allow_unstable=True)
    assert ok.dt == 1.01 * stable
    assert ExplicitSolver(model, time_step=0.99 * stable).dt == 0.99 * stable
    for bad in (0.0, -1e-9):
        with pytest.raises(ValueError):
            ExplicitSolver(model, time_step=bad)
    with pytest.raises(ValueError, match="integrator"):
        ExplicitSolver(model, integrator="euler")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="safety_factor"):
        ExplicitSolver(model, safety_factor=1.5)


@pytest.mark.parametrize("integrator", ["velocity_verlet", "central_difference"])
def test_blow_up_is_reported_with_step_time_and_point(integrator):
    model = bar_model()
    stable = ExplicitSolver(model).stable_time_step
    solver = ExplicitSolver(model, time_step=3 * stable, allow_unstable=True, integrator=integrator)
    s = solver.init()
    s.v[:] = np.random.default_rng(0).normal(0.0, 1.0, s.v.shape)  # m/s, noise
    if integrator == "central_difference":
        s.u_prev[:] = s.u - solver.dt * s.v
    with pytest.raises(SimulationUnstable) as info:
        solver.run(s, 2000)
    err = info.value
    msg = str(err)
    assert f"step {err.step}" in msg
    assert re.search(r"t = [0-9.e+-]+ s", msg)
    assert f"point {err.point}" in msg
    assert err.step % solver.check_every == 0 and err.step > 0
    assert err.time == pytest.approx(err.step * solver.dt, rel=1e-12)
    assert 0 <= err.point < model.n_points
    np.testing.assert_allclose(err.coordinates, model.cloud.x[err.point])
    # the offending point really is bad in the returned state
    k = err.point
    finite = np.isfinite(s.u[k]).all() and np.isfinite(s.v[k]).all()
    assert not finite or np.abs(s.u[k]).max() > solver.blowup_factor * model.cloud.size
    good = err.last_good
    assert isinstance(good, State) and good.step == err.step - solver.check_every
    assert np.all(np.isfinite(good.u))


def test_stable_run_does_not_trip_the_check():
    model = bar_model()
    solver = ExplicitSolver(model)  # 0.8 x stable
    s = solver.init()
    s.v[:] = np.random.default_rng(0).normal(0.0, 1.0, s.v.shape)
    solver.run(s, 2000)
    assert np.abs(s.u).max() < 1e-3 * model.cloud.size


def test_velocity_verlet_and_central_difference_give_the_same_trajectory():
    """Both are the Stormer-Verlet scheme; with u(dt) = u0 + dt v0 + dt^2 a0 / 2 their
    displacements agree step by step (up to round-off)."""
    cloud = rectangle((0.01, 0.008), DX)
    model = Evaluator(cloud, build_bonds(cloud, 3.015 * DX), BondBasedMaterial(E, RHO))
    rng = np.random.default_rng(5)
    v0 = rng.normal(0.0, 0.5, cloud.x.shape)
    runs = []
    for integ in ("velocity_verlet", "central_difference"):
        solver = ExplicitSolver(model, integrator=integ)
        s = solver.init()
        s.v[:] = v0
        if integ == "central_difference":  # redo the Taylor start with the new v0
            a0 = s.force / RHO
            s.u_prev[:] = s.u - solver.dt * s.v + 0.5 * solver.dt**2 * a0
        solver.run(s, 200)
        runs.append(s.u.copy())
    scale = np.abs(runs[0]).max()
    assert scale > 0
    np.testing.assert_allclose(runs[1], runs[0], rtol=0, atol=1e-9 * scale)


def test_restart_from_copied_state_is_bit_for_bit():
    cloud = rectangle((0.01, 0.008), DX)
    model = Evaluator(cloud, build_bonds(cloud, 3.015 * DX), BondBasedMaterial(E, RHO))
    solver = ExplicitSolver(model)
    s = solver.init()
    s.v[:] = np.random.default_rng(1).normal(0.0, 0.5, s.v.shape)
    solver.run(s, 25)
    saved = State.from_arrays(s.copy().to_arrays())
    solver.run(s, 25)
    solver.run(saved, 25)
    assert saved.step == s.step == 50 and saved.t == s.t
    for name in ("u", "v", "force"):
        assert np.array_equal(getattr(saved, name), getattr(s, name))
