"""Several deformable bodies in one model: composite force model, interfaces, deck path."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics import deck as dk
from peridynamics.app.run import Simulation
from peridynamics.bodies.build import select_bonds
from peridynamics.bodies.composite import BodiesMaterial, BodyPart
from peridynamics.bodies.composite_damage import BodiesDamage
from peridynamics.bodies.interface import InterfaceBonds
from peridynamics.build.errors import SetupError
from peridynamics.damage import CriticalStretch
from peridynamics.geometry import rectangle
from peridynamics.solvers.explicit import ExplicitSolver

DX = 1e-3


def _plate(nx: int = 12, ny: int = 8):
    return rectangle((nx * DX, ny * DX), DX, thickness=DX, plane="stress")


def _two_blocks():
    """Two 6 x 8 blocks side by side: body 0 the left, body 1 the right half."""
    cloud = _plate()
    order = np.argsort(cloud.x[:, 0] > 6 * DX, kind="stable")
    from peridynamics.geometry.cloud import PointCloud

    cloud = PointCloud(cloud.x[order], cloud.volume[order], DX, DX, "stress")
    n0 = int(np.sum(cloud.x[:, 0] < 6 * DX))
    body = (np.arange(cloud.n_points) >= n0).astype(np.int64)
    bonds_all = build_bonds(cloud, 3.015 * DX)
    within = select_bonds(bonds_all, body[bonds_all.bond_i] == body[bonds_all.bond_j])
    across = select_bonds(bonds_all, body[bonds_all.bond_i] != body[bonds_all.bond_j])
    return cloud, n0, within, across


def _explicit(model: Evaluator, steps: int, pull: float) -> np.ndarray:
    solver = ExplicitSolver(model, safety_factor=0.5)
    s = solver.init()
    right = model.cloud.x[:, 0] > model.cloud.x[:, 0].max() - 1.5 * DX
    for _ in range(steps):
        s.v[right, 0] = pull
        solver.step(s)
    return s


def test_one_body_through_the_composite_path_is_bit_for_bit():
    cloud = _plate()
    bonds = build_bonds(cloud, 3.015 * DX)
    mat = BondBasedMaterial(70e9, 2700.0)
    dmg = CriticalStretch(2e-3)
    plain = Evaluator(cloud, bonds, mat, dmg, surface_correction=True)
    part = BodyPart("main", 0, cloud.n_points, mat, dmg)
    multi = Evaluator(
        cloud, bonds, BodiesMaterial((part,)), BodiesDamage((part,)), surface_correction=True
    )
    a = _explicit(plain, 300, 20.0)
    b = _explicit(multi, 300, 20.0)
    assert a.bonds_broken > 0  # the run breaks bonds: the damage path is exercised
    assert a.bonds_broken == b.bonds_broken
    assert np.array_equal(a.u, b.u) and np.array_equal(a.intact, b.intact)


def test_separate_bodies_do_not_interact_and_keep_their_own_results():
    """Two blocks without an interface: each moves as it would alone (same bits for the
    left block as a model of the left block only)."""
    cloud, n0, within, _ = _two_blocks()
    m0 = BondBasedMaterial(70e9, 2700.0)
    m1 = BondBasedMaterial(20e9, 1000.0)
    d = CriticalStretch(1.0)
    parts = (BodyPart("a", 0, n0, m0, d), BodyPart("b", n0, cloud.n_points, m1, d))
    multi = Evaluator(cloud, within, BodiesMaterial(parts), BodiesDamage(parts))
    s = multi.new_state()
    rng = np.random.default_rng(3)
    s.u[...] = rng.normal(0, 1e-3 * DX, s.u.shape)
    multi.evaluate(s, commit=False)
    from peridynamics.bodies.composite import sub_bonds, sub_cloud

    alone = Evaluator(sub_cloud(cloud, 0, n0), sub_bonds(within, 0, n0), m0, d)
    f = alone.force_of(s.u[:n0])
    assert np.array_equal(f, s.force[:n0])
    assert multi.density[0] == 2700.0 and multi.density[-1] == 1000.0


def test_interface_bonds_break_at_their_own_stretch_and_show_as_damage():
    cloud, n0, within, across = _two_blocks()
    mat = BondBasedMaterial(70e9, 2700.0)
    c0 = mat.micromodulus_constant(2, 3.015 * DX, DX, "stress")
    iface = InterfaceBonds("a/b", across, c0, 2e-4)
    strong = CriticalStretch(1e-2)
    parts = (BodyPart("a", 0, n0, mat, strong), BodyPart("b", n0, cloud.n_points, mat, strong))
    model = Evaluator(cloud, within, BodiesMaterial(parts, (iface,)), BodiesDamage(parts))
    s = model.new_state()
    s.u[n0:, 0] = 1e-3 * DX * 2  # right block moved: interface bonds stretch, bodies do not
    broken = model.evaluate(s, commit=True)
    assert broken == int(np.count_nonzero(s["interface_intact"] == 0)) > 0
    assert s.intact.all()  # no bond inside a body broke
    phi = model.point_damage(s.intact, s["interface_intact"])
    assert phi[n0 - 1] > 0 and phi[0] == 0


DECK = {
    "name": "two",
    "geometry": {"type": "rectangle", "size": [0.04, 0.02], "thickness": 0.01},
    "discretisation": {"spacing": 0.002, "horizon_factor": 3.015},
    "material": {"model": "pmb", "youngs_modulus": 30e9, "density": 2400},
    "damage": {"critical_stretch": 0.001},
    "bodies": [
        {
            "name": "aggregate",
            "region": {"ball": {"center": [0.02, 0.01], "radius": 0.005}},
            "material": {"model": "lps", "youngs_modulus": 60e9, "poisson_ratio": 0.2,
                         "density": 2700},
        }
    ],
    "interfaces": [{"bodies": ["main", "aggregate"], "critical_stretch": 0.0005}],
    "node_sets": {"left": {"edge": {"normal": [-1, 0]}}, "right": {"edge": {"normal": [1, 0]}}},
    "boundary_conditions": [
        {"type": "fixed", "set": "left"},
        {"type": "velocity", "set": "right", "components": {"x": 0.5}},
    ],
    "solver": {"steps": 50},
}  # fmt: skip


def test_deck_with_a_carved_body_builds_contiguous_bodies_with_their_materials():
    sim = Simulation.from_deck(dk.parse_deck(copy.deepcopy(DECK)))
    c = sim.cloud
    agg = c.node_set("aggregate")
    main = c.node_set("main")
    assert main[0] == 0 and agg[0] == main[-1] + 1 and agg[-1] == c.n_points - 1
    r = np.linalg.norm(c.x[agg] - [0.02, 0.01], axis=1)
    assert r.max() <= 0.005 + 1e-12
    fm = sim.model.force_model
    assert [m.name for m in fm.models] == ["pmb", "lps"]
    assert sim.model.density[agg].min() == 2700.0
    s = sim.solver.init()
    for _ in range(50):
        sim.solver.step(s)
    assert np.isfinite(s.u).all()


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (lambda d: d["bodies"][0].update(region={"ball": {"center": [1, 1], "radius": 0.001}}),
         "bodies"),
        (lambda d: d["node_sets"].update(aggregate={"edge": {"normal": [0, 1]}}),
         "node_sets.aggregate"),
    ],
)  # fmt: skip
def test_bad_bodies_are_setup_errors_naming_the_key(edit, key):
    d = copy.deepcopy(DECK)
    edit(d)
    with pytest.raises(SetupError) as err:
        Simulation.from_deck(dk.parse_deck(d))
    assert err.value.path.startswith(key)


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        (lambda d: d["bodies"][0].update(geometry={"type": "rectangle", "size": [0.01, 0.01]}),
         "bodies.0.*region"),
        (lambda d: d["interfaces"][0].update(bodies=["main", "nope"]),
         "interfaces.0.bodies.*unknown body 'nope'"),
        (lambda d: d["bodies"][0].update(name="main"), "bodies.0.name.*twice"),
        (lambda d: d.update(rigid_bodies=[{"name": "p", "shape": {"box": {"min": [0, 0, 0],
         "max": [1, 1, 1]}}}]), "rigid_bodies.0.shape.box.min"),
        (lambda d: d.update(rigid_bodies=[{"name": "p", "motion": "free", "shape": {"plane": {
         "point": [0, 0], "normal": [0, 1]}}, "density": 1.0}]), "plane has no finite mass"),
        (lambda d: d.update(contact={"friction_static": 0.2, "friction_kinetic": 0.3}),
         "friction_kinetic"),
    ],
)  # fmt: skip
def test_deck_schema_rejects_bad_body_sections(edit, match):
    d = copy.deepcopy(DECK)
    edit(d)
    with pytest.raises(dk.DeckError, match=match):
        dk.parse_deck(d)


def test_a_body_name_is_a_node_set_for_conditions_and_probes():
    d = copy.deepcopy(DECK)
    d["output"] = {"probes": [{"name": "agg_ux", "quantity": "displacement", "set": "aggregate",
                               "component": "x"}]}  # fmt: skip
    deck = dk.parse_deck(d)
    assert deck.output.probes[0].set == "aggregate"


def test_static_solve_of_two_bodies_with_an_interface_converges_like_one_body():
    d = copy.deepcopy(DECK)
    d["boundary_conditions"][1] = {
        "type": "displacement", "set": "right", "components": {"x": 2e-5},
        "time_function": {"type": "ramp", "end": 1.0},
    }  # fmt: skip
    d["solver"] = {"type": "static", "load_steps": 2}
    d.pop("damage")  # a linear elastic solve: nothing can break
    d["interfaces"] = [{"bodies": ["main", "aggregate"]}]
    sim = Simulation.from_deck(dk.parse_deck(d))
    s = sim.solver.init()
    r = sim.solver.step(s)
    assert r.converged and r.iterations <= 3


def test_static_solver_refuses_bodies_whose_bonds_can_break():
    """Its breaking schemes read one critical-stretch law: the bodies' and interfaces'
    bonds would never break, so the deck is refused with the key and the way out."""
    d = copy.deepcopy(DECK)
    d["boundary_conditions"][1] = {
        "type": "displacement",
        "set": "right",
        "components": {"x": 2e-5},
    }
    d["solver"] = {"type": "static", "load_steps": 2}
    with pytest.raises(SetupError, match="solver.type: adr"):
        Simulation.from_deck(dk.parse_deck(d))
