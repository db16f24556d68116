"""Time functions and boundary conditions."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, ExplicitSolver, build_bonds
from peridynamics.geometry import Box, bar, rectangle
from peridynamics.loading import (
    BodyForce,
    Constant,
    Fixed,
    PrescribedDisplacement,
    PrescribedVelocity,
    Ramp,
    Table,
    TriangularPulse,
    traction_as_body_force,
)


def test_time_functions():
    assert Constant()(5.0) == 1.0 and Constant(2.5)(0.0) == 2.5
    r = Ramp(end=2.0, start=1.0)
    assert [r(t) for t in (0.0, 1.0, 1.5, 2.0, 9.0)] == [0.0, 0.0, 0.5, 1.0, 1.0]
    tb = Table(times=[0.0, 1.0, 3.0], values=[0.0, 2.0, -2.0])
    assert [tb(t) for t in (-1.0, 0.5, 2.0, 5.0)] == [0.0, 1.0, 0.0, -2.0]
    p = TriangularPulse(peak=4.0, rise_time=1.0, duration=3.0)
    assert [p(t) for t in (-1.0, 0.0, 0.5, 1.0, 2.0, 3.0, 4.0)] == [
        0.0,
        0.0,
        2.0,
        4.0,
        2.0,
        0.0,
        0.0,
    ]
    with pytest.raises(ValueError):
        Ramp(end=1.0, start=1.0)
    with pytest.raises(ValueError):
        Table(times=[0.0, 0.0], values=[1.0, 2.0])
    with pytest.raises(ValueError):
        TriangularPulse(peak=1.0, rise_time=2.0, duration=1.0)


def test_kinematic_conditions_apply():
    u = np.ones((4, 2))
    v = np.ones((4, 2))
    PrescribedDisplacement(np.array([1, 2]), {"y": 0.5}, Ramp(end=1.0)).apply(u, v, 0.5, 0.1)
    assert np.allclose(u[[1, 2], 1], 0.25) and np.allclose(v[[1, 2], 1], 0.5)
    assert np.all(u[:, 0] == 1.0) and u[0, 1] == 1.0
    Fixed(np.array([3]), components=("x",)).apply(u, v, 0.0, 0.1)
    assert u[3, 0] == 0.0 and v[3, 0] == 0.0 and u[3, 1] == 1.0
    Fixed(np.array([0])).apply(u, v, 0.0, 0.1)
    assert np.all(u[0] == 0.0)
    with pytest.raises(ValueError, match="component"):
        PrescribedDisplacement(np.array([0]), {"z": 1.0}).apply(u, v, 0.0, 0.1)


def test_traction_layer_and_body_force():
    cloud = rectangle((0.01, 0.004), 1e-3)
    top = cloud.select(Box([-np.inf, 0.0025], [np.inf, np.inf]))  # two rows
    bf = traction_as_body_force(top, np.array([0.0, 2e6]), cloud.x, cloud.spacing)
    assert bf.value == pytest.approx((0.0, 2e6 / 2e-3))
    b = np.zeros((cloud.n_points, 2))
    bf.add_to(b, 0.0)
    # total force per unit thickness = traction * length
    assert np.sum(b[:, 1] * cloud.volume) == pytest.approx(2e6 * 0.01, rel=1e-12)


def test_prescribed_velocity_and_body_force_in_a_run():
    cloud = bar(0.02, 1e-3, area=1e-6)
    model = Evaluator(
        cloud,
        build_bonds(cloud, 3e-3),
        BondBasedMaterial(200e9, 7850.0),
        body_forces=[BodyForce(np.array([10]), (1e6,), Ramp(end=1e-7))],
    )
    end = np.array([19])
    solver = ExplicitSolver(
        model, constraints=[PrescribedVelocity(end, {"x": 2.0}), Fixed(np.array([0]))]
    )
    s = solver.init()
    solver.run(s, 50)
    assert s.u[19, 0] == pytest.approx(2.0 * s.t, rel=1e-12)
    assert s.v[19, 0] == 2.0
    assert s.u[0, 0] == 0.0 and s.v[0, 0] == 0.0
    b = np.zeros((cloud.n_points, 1))
    model.external_force(5e-8, b)
    assert b[10, 0] == pytest.approx(0.5e6) and np.count_nonzero(b) == 1
