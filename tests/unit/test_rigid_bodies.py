"""Rigid bodies in a run: reactions, prescribed and free motion, friction, momentum."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from peridynamics import deck as dk
from peridynamics.app.run import Simulation
from peridynamics.bodies.rigid import RigidBody, RigidSystem, rotation_step
from peridynamics.bodies.rigid_contact import contact_for_shape
from peridynamics.bodies.shapes import Box
from peridynamics.build.errors import SetupError
from peridynamics.kernels.reference_rigid_contact import rigid_shape_force_reference

# the long tier (CI: pytest -m long): rigid-body runs (their kernels compile for a minute cold)
pytestmark = pytest.mark.long

G = 9.81

SLIDE = {
    "name": "slide",
    "geometry": {"type": "rectangle", "size": [0.02, 0.01], "thickness": 0.01},
    "discretisation": {"spacing": 0.002, "horizon_factor": 3.015},
    "material": {"model": "pmb", "youngs_modulus": 1.0e7, "density": 1000.0},
    "rigid_bodies": [
        {
            "name": "floor",
            "shape": {"plane": {"point": [0.0, 0.0], "normal": [0.0, 1.0]}},
            "friction_static": 0.4,
            "friction_kinetic": 0.3,
        }
    ],
    "boundary_conditions": [
        {"type": "body_force", "set": "all", "value": [0.0, -1000.0 * G]},
        {"type": "initial_velocity", "set": "all", "value": [1.0, 0.0]},
    ],
    "solver": {"end_time": 0.04},
    "output": {"history_every": 20},
}


def _run(deck: dict, steps: int | None = None):
    sim = Simulation.from_deck(dk.parse_deck(copy.deepcopy(deck)))
    s = sim.solver.init()
    n = sim.solver.total_steps() if steps is None else steps
    out = [s.copy()]
    for k in range(n):
        sim.solver.step(s)
        if k % 20 == 19:
            out.append(s.copy())
    return sim, s, out


@pytest.mark.long
def test_block_sliding_on_a_rigid_plane_decelerates_at_mu_k_g():
    sim, s, snaps = _run(SLIDE)
    rho_v = sim.model.density * sim.cloud.volume
    t = np.array([q.t for q in snaps])
    vx = np.array([np.sum(rho_v * q.v[:, 0]) / rho_v.sum() for q in snaps])
    late = t > 0.005  # after the block has settled onto the plane
    slope = np.polyfit(t[late], vx[late], 1)[0]
    assert vx[-1] > 0.5  # still sliding at the end
    assert -slope == pytest.approx(0.3 * G, rel=0.01)
    # energy: the friction work is the kinetic energy lost (within the elastic wobble)
    ke = [0.5 * np.sum(rho_v * np.sum(q.v**2, axis=1)) for q in (snaps[0], s)]
    work = float(s["friction_work"][0])
    assert work > 0
    assert work == pytest.approx(ke[0] - ke[1], rel=0.03)


@pytest.mark.parametrize(("push", "sticks"), [(0.2, True), (0.5, False)])
def test_block_at_rest_sticks_below_mu_s_and_slides_above(push, sticks):
    """Bottom row touching the plane, gravity ramped in slowly (no bounce), then a
    tangential push of push x m g: below mu_s = 0.4 it sticks, above it slides."""
    deck = copy.deepcopy(SLIDE)
    deck["geometry"]["origin"] = [0.0, 0.9e-3 - 1e-3]  # bottom points at r_c = 0.9 mm
    deck["boundary_conditions"] = [
        {"type": "body_force", "set": "all", "value": [0.0, -1000.0 * G],
         "time_function": {"type": "ramp", "end": 0.01}},
        {"type": "body_force", "set": "all", "value": [push * 1000.0 * G, 0.0],
         "time_function": {"type": "ramp", "start": 0.01, "end": 0.012}},
    ]  # fmt: skip
    deck["solver"]["end_time"] = 0.03
    sim, s, _ = _run(deck)
    rho_v = sim.model.density * sim.cloud.volume
    vx = np.sum(rho_v * s.v[:, 0]) / rho_v.sum()
    ux = np.sum(rho_v * s.u[:, 0]) / rho_v.sum()
    if sticks:
        assert abs(vx) < 1e-3 and abs(ux) < 1e-5
    else:  # slides: a = (push - mu_k) g over about 18 ms
        assert vx > 0.5 * (push - 0.3) * G * 0.018


PRESS = {
    "name": "press",
    "geometry": {"type": "rectangle", "size": [0.02, 0.02], "thickness": 0.01},
    "discretisation": {"spacing": 0.002, "horizon_factor": 3.015},
    "material": {"model": "pmb", "youngs_modulus": 1.0e9, "density": 1000.0},
    "rigid_bodies": [
        {"name": "floor", "shape": {"plane": {"point": [0.0, 0.0], "normal": [0.0, 1.0]}}},
        {
            "name": "platen",
            "shape": {"box": {"min": [-0.01, 0.0199], "max": [0.03, 0.025]}},
            "velocity": [0.0, -0.5],
            "time_function": {"type": "ramp", "end": 5.0e-5},
        },
    ],
    "solver": {"end_time": 1.0e-3},
    "output": {"history_every": 10},
}


def test_platen_reaction_is_the_contact_force_sum_and_the_motion_is_prescribed():
    sim, s, _ = _run(PRESS)
    rigid = sim.model.rigid
    k = rigid.index("platen")
    # position: integral of 0.5 m/s x ramp(0 -> 1 over 50 us)
    t = s.t
    travel = 0.5 * (t - 0.5 * 5.0e-5)
    # midpoint rule: exact on each linear piece, off by < 1/8 dt of travel in the step
    # that holds the ramp's kink
    dt = sim.solver.dt
    assert abs(s["rigid_position"][k, 1] + travel) < 0.125 * 0.5 * dt
    assert np.allclose(s["rigid_velocity"][k, :2], [0.0, -0.5])
    # the reaction stored in the State == the force sum of the NumPy twin of the law
    body = rigid.bodies[k]
    shape = body.contact.law.shape
    y = sim.cloud.x + s.u
    trans = body.center[:2] + s["rigid_position"][k, :2] - body.center[:2]
    ref = rigid_shape_force_reference(
        y, s.v, sim.cloud.volume, sim.model.density, shape, np.eye(2), trans,
        np.zeros(2), np.zeros(3), body.contact.law.contact_radius, body.contact.law.stiffness,
        0.0, 0.0, 1.0,
    )  # fmt: skip
    force_ref = -(sim.cloud.volume[:, None] * ref[0]).sum(axis=0)
    assert force_ref[1] > 0  # the specimen pushes the platen up
    assert s["rigid_force"][k, :2] == pytest.approx(
        force_ref, rel=1e-12, abs=1e-12 * abs(force_ref[1])
    )
    # equal and opposite: the floor carries the platen's load once the wave has settled
    assert -s["rigid_force"][rigid.index("floor"), 1] == pytest.approx(force_ref[1], rel=0.5)


def test_reaction_history_lands_in_the_summary(tmp_path):
    sim = Simulation.from_deck(dk.parse_deck(copy.deepcopy(PRESS)))
    summary = sim.run(tmp_path, quiet=True, progress=False)
    r = summary["results"]["rigid_bodies"] if "results" in summary else summary["rigid_bodies"]
    f = np.asarray(r["platen"]["force_N"])
    assert len(f) == len(r["time_s"]) and f[-1, 1] > 0
    assert r["platen"]["peak_force_N"] >= abs(f[-1, 1])


def test_free_rigid_body_without_contact_conserves_both_momenta():
    box = Box((0.0, 0.0, 0.0), (0.01, 0.02, 0.03))
    inertia = np.diag([1.0, 2.0, 3.5]) * 1e-4
    body = RigidBody(
        "b", 3, contact_for_shape(box, np.zeros(3), 1e-4, 1.0, 0.0, 0.0), np.zeros(3), "free",
        np.array([1.0, -2.0, 0.5]), None, 0.7, inertia, np.array([3.0, 5.0, -4.0]),
    )  # fmt: skip
    system = RigidSystem([body], np.ones(1), np.ones(1))
    from peridynamics.state import State

    s = State()
    system.init_fields(s)
    p0 = s["rigid_velocity"][0] * body.mass
    l0 = s["rigid_momentum"][0].copy()
    e0 = system.kinetic_energy(s)
    dt = 1e-4
    for k in range(2000):
        system.half_kick(s, dt)
        system.drift(s, k * dt, dt)
        system.half_kick(s, dt)
    rot = s["rigid_rotation"][0].reshape(3, 3)
    assert np.abs(rot.T @ rot - np.eye(3)).max() < 1e-12
    assert np.array_equal(s["rigid_velocity"][0] * body.mass, p0)
    assert np.array_equal(s["rigid_momentum"][0], l0)
    assert np.allclose(s["rigid_position"][0], 0.2 * np.array([1.0, -2.0, 0.5]), rtol=1e-12)
    assert system.kinetic_energy(s) == pytest.approx(e0, rel=1e-3)  # tumbling: approximate


def test_rotation_step_is_the_exact_rotation():
    r = rotation_step(np.array([0.0, 0.0, 2.0]), 0.25)  # 0.5 rad about z
    c, s = np.cos(0.5), np.sin(0.5)
    assert np.allclose(r, [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-15)


STRIKE = {
    "name": "strike",
    "geometry": {"type": "rectangle", "size": [0.02, 0.01], "thickness": 0.01},
    "discretisation": {"spacing": 0.001, "horizon_factor": 3.015},
    "material": {"model": "pmb", "youngs_modulus": 1.0e9, "density": 1000.0},
    "damage": {"critical_stretch": 0.05},
    "rigid_bodies": [
        {
            "name": "striker",
            "motion": "free",
            "shape": {"sphere": {"center": [0.008, 0.0135], "radius": 0.003}},
            "velocity": [0.5, -20.0],
            "angular_velocity": [100.0],
            "density": 7800.0,
            "friction_static": 0.3,
            "friction_kinetic": 0.2,
        }
    ],
    "solver": {"end_time": 1.0e-4},
}


def test_free_striker_and_free_plate_conserve_total_linear_momentum():
    sim, s, snaps = _run(STRIKE)
    m = sim.model.density * sim.cloud.volume
    body = sim.model.rigid.bodies[0]

    def momentum(q):
        return (m[:, None] * q.v).sum(axis=0) + body.mass * q["rigid_velocity"][0, :2]

    p0 = momentum(snaps[0])
    hit = max(np.abs(q["rigid_force"][0, 1]) for q in snaps)
    assert hit > 0  # the striker touched the plate
    assert s["rigid_velocity"][0, 1] > -20.0  # and was slowed down
    scale = abs(p0[1])
    for q in snaps:
        assert np.allclose(momentum(q), p0, rtol=0, atol=1e-12 * scale)


def test_rigid_bodies_need_the_explicit_solver():
    deck = copy.deepcopy(PRESS)
    deck["solver"] = {"type": "adr", "load_steps": 2}
    deck["boundary_conditions"] = []
    with pytest.raises(SetupError, match="rigid_bodies"):
        Simulation.from_deck(dk.parse_deck(deck))
