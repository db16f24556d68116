"""Kinematic conditions and stability checks of the explicit solver (review findings)."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.geometry import bar, rectangle
from peridynamics.loading import PrescribedDisplacement, PrescribedVelocity, Ramp
from peridynamics.solvers import ExplicitSolver, SimulationUnstable


def _bar_model():
    cloud = bar(0.1, 1e-3, area=1e-4)
    return Evaluator(cloud, build_bonds(cloud, 3.015e-3), BondBasedMaterial(70e9, 2700.0))


@pytest.mark.parametrize("integrator", ["velocity_verlet", "central_difference"])
def test_prescribed_displacement_sets_its_rate_as_velocity(integrator: str) -> None:
    model = _bar_model()
    end = np.array([model.n_points - 1])
    ramp_time, amplitude = 1e-5, 1e-6
    bc = PrescribedDisplacement(end, {"x": amplitude}, Ramp(end=ramp_time))
    solver = ExplicitSolver(model, integrator=integrator, constraints=[bc])
    s = solver.run(solver.init(), 20)
    assert s.t < ramp_time
    assert s.u[end[0], 0] == pytest.approx(amplitude * s.t / ramp_time, rel=1e-12)
    assert s.v[end[0], 0] == pytest.approx(amplitude / ramp_time, rel=1e-9)


def test_central_difference_velocity_equals_velocity_verlet() -> None:
    out = {}
    for integrator in ("velocity_verlet", "central_difference"):
        model = _bar_model()
        solver = ExplicitSolver(model, integrator=integrator)
        s = solver.init()
        s.v[:, 0] = np.sin(np.pi * model.cloud.x[:, 0] / 0.1)
        if integrator == "central_difference":  # re-derive u(-dt) for the new v0
            s.u_prev[:] = s.u - solver.dt * s.v
        out[integrator] = solver.run(s, 200)
    a, b = out["velocity_verlet"], out["central_difference"]
    np.testing.assert_allclose(b.u, a.u, rtol=0, atol=1e-12 * np.abs(a.u).max())
    np.testing.assert_allclose(b.v, a.v, rtol=0, atol=1e-9 * np.abs(a.v).max())


@pytest.mark.parametrize("integrator", ["velocity_verlet", "central_difference"])
def test_prescribed_velocity_moves_nodes_at_that_velocity(integrator: str) -> None:
    model = _bar_model()
    end = np.array([0])
    solver = ExplicitSolver(
        model, integrator=integrator, constraints=[PrescribedVelocity(end, {"x": -2.0})]
    )
    s = solver.run(solver.init(), 50)
    assert s.v[0, 0] == -2.0
    assert s.u[0, 0] == pytest.approx(-2.0 * s.t, rel=1e-12)


def test_last_good_state_is_a_consistent_snapshot() -> None:
    cloud = rectangle((0.01, 0.01), 1e-3)
    from peridynamics.damage import CriticalStretch

    model = Evaluator(
        cloud, build_bonds(cloud, 3.015e-3), BondBasedMaterial(70e9, 2700.0), CriticalStretch(1e-4)
    )
    solver = ExplicitSolver(model, check_every=5)
    s = solver.init()
    s.v[:, 0] = 50.0 * (cloud.x[:, 0] - 0.005) / 0.005  # pull apart: bonds break
    solver.run(s, 40)
    assert s.bonds_broken > 0
    good = solver.last_good
    assert good is not None and good.step == 40
    assert good.bonds_broken == s.bonds_broken
    assert np.array_equal(good.intact, s.intact) and np.array_equal(good.u, s.u)
    s.u[3, 0] = np.nan
    with pytest.raises(SimulationUnstable) as info:
        solver.check(s)
    assert info.value.last_good is good and np.array_equal(good.intact, s.intact)


def test_final_steps_are_checked() -> None:
    model = _bar_model()
    solver = ExplicitSolver(
        model, time_step=5 * model.stable_time_step(), allow_unstable=True, check_every=10_000
    )
    s = solver.init()
    s.v[50, 0] = 1.0
    with pytest.raises(SimulationUnstable, match="unstable at step 300"):
        solver.run(s, 300)


def test_rigid_motion_is_not_an_instability() -> None:
    model = _bar_model()
    solver = ExplicitSolver(model)
    s = solver.init()
    s.v[:, 0] = 3000.0  # translates by more than the bar length within the run
    solver.run(s, 2000)
    assert s.u[:, 0].min() > 0.1


def test_overstretched_intact_bond_is_reported() -> None:
    model = _bar_model()
    solver = ExplicitSolver(model)
    s = solver.init()
    s.u[40:, 0] = 2.5e-3  # a 2.5 mm jump over 1 mm bonds: stretch 2.5, no damage law
    model.internal_force(s.u, s.intact, s.force, s.max_stretch)
    with pytest.raises(SimulationUnstable, match="intact bond stretched"):
        solver.check(s)
