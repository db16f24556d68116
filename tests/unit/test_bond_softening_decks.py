"""Tension-softening PMB bonds through decks: a plate in tension softens gradually,
dynamic relaxation commits the bond history on accepted load steps, ``bond_law:
brittle`` is the critical-stretch path bit for bit, and the deck's checks name the key."""

from __future__ import annotations

import copy
import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, CriticalStretch, Evaluator
from peridynamics.app.run import Simulation
from peridynamics.build.cloud import build_bonds_for
from peridynamics.build.materials import build_damage
from peridynamics.damage import CriticalStretchLaw
from peridynamics.damage.bond_softening import SofteningBonds
from peridynamics.deck import DeckError, parse_deck
from peridynamics.kernels.reference import stretch

E, RHO, FT, G0 = 30e9, 2400.0, 3e6, 20.0  # concrete-like: s0 = f_t / E = 1e-4
H = 1e-3  # plate thickness (m)


@pytest.mark.long
def test_dynamic_relaxation_commits_on_accepted_load_steps() -> None:
    d = {
        "name": "bar",
        "geometry": {"type": "bar", "length": 0.02, "area": 1e-4},
        "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
        "material": {"youngs_modulus": E, "density": RHO},
        "damage": {
            "bond_law": "trilinear",
            "tensile_strength": FT,
            "fracture_energy": G0,
            "no_fail": ["left", "right"],
        },
        "node_sets": {
            "left": {"edge": {"normal": [-1.0], "layers": 3}},
            "right": {"edge": {"normal": [1.0], "layers": 3}},
        },
        "boundary_conditions": [
            {"type": "fixed", "set": "left"},
            {"type": "displacement", "set": "right", "components": {"x": 2e-5}},
        ],
        "solver": {"type": "adr", "load_steps": 5, "tolerance": 1e-8},
        "output": {"vtk_every": 0, "plot": "none"},
    }
    sim = Simulation.from_deck(parse_deck(d))
    m, b, solver = sim.model, sim.model.bonds, sim.solver
    s = solver.init()
    right = m.cloud.node_set("right")
    loads = []
    while not solver.done(s):
        before, intact = s["bond_kappa"].copy(), s.intact.copy()
        assert solver.step(s).converged
        st = stretch(m.cloud.x, s.u, b.bond_i, b.bond_j, b.bond_length)
        expected = np.where(intact > 0, np.maximum(before, st), before)
        np.testing.assert_allclose(s["bond_kappa"], expected, rtol=1e-12, atol=1e-15)
        loads.append(-float(np.sum(s.force[right, 0] * m.cloud.volume[right])))
    assert s["bond_kappa"].max() > m.force_model.envelope.s0
    assert loads[0] > loads[-1] > 0  # softening, not failure: the load decreases


# ------------------------------------------------------------------------ decks
PLATE = {
    "name": "soft_plate",
    "geometry": {"type": "rectangle", "size": [0.02, 0.01], "thickness": H},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
    "material": {"youngs_modulus": E, "density": RHO},
    "node_sets": {
        "left": {"edge": {"normal": [-1.0, 0.0], "layers": 3}},
        "right": {"edge": {"normal": [1.0, 0.0], "layers": 3}},
    },
    "precracks": [{"points": [[0.01, -0.001], [0.01, 0.003]]}],
    "boundary_conditions": [
        {"type": "fixed", "set": "left"},
        {
            "type": "velocity",
            "set": "right",
            "components": {"x": 0.2},
            "time_function": {"type": "ramp", "end": 2e-5},
        },
    ],
    "solver": {"end_time": 1.2e-4, "damping": 2e5},
    "output": {
        "history_every": 10,
        "vtk_every": 0,
        "plot": "none",
        # the fixed side: the reaction without the damping force of the moving side
        "probes": [{"name": "F", "quantity": "reaction_force", "set": "left", "component": "x"}],
    },
}


def plate(damage: dict) -> dict:
    d = copy.deepcopy(PLATE)
    d["damage"] = {"no_fail": ["left", "right"], **damage}
    return d


def load_curve(d: dict, out: Path) -> np.ndarray:
    Simulation.from_deck(parse_deck(d)).run(out, quiet=True, progress=False)
    r = json.loads((out / "summary.json").read_text())["results"]
    assert r["bonds_broken"] > 0
    return -np.asarray(r["probes"]["F"]["values"])


@pytest.mark.long
def test_deck_plate_in_tension_has_a_softening_tail(tmp_path: Path) -> None:
    soft = load_curve(
        plate({"bond_law": "bilinear", "tensile_strength": FT, "fracture_energy": G0}),
        tmp_path / "soft",
    )
    brittle = load_curve(plate({"fracture_energy": G0}), tmp_path / "brittle")
    peak = int(np.argmax(soft))
    tail = soft[peak:] / soft[peak]
    assert tail[-1] < 0.05  # it does separate
    drops = -np.diff(tail)
    assert drops.max() < 0.2  # no sudden drop ...
    assert np.count_nonzero((tail > 0.2) & (tail < 0.9)) >= 8  # ... but a gradual tail
    b = brittle[int(np.argmax(brittle)) :] / brittle.max()  # the brittle plate lets go
    assert (-np.diff(b)).max() > 2 * drops.max()
    assert np.count_nonzero(b[: np.argmax(b < 0.2)] < 0.9) <= 2


def test_brittle_law_is_the_critical_stretch_path_bit_for_bit() -> None:
    """``bond_law: brittle`` (the default) builds the critical-stretch law, and a short
    explicit run equals one of a hand-built Evaluator with CriticalStretch bit for bit."""
    d = plate({"bond_law": "brittle", "fracture_energy": G0})
    d["solver"] = {"steps": 300, "damping": 2e5}
    deck = parse_deck(d)
    sim = Simulation.from_deck(deck)
    cloud = sim.cloud
    material = BondBasedMaterial(E, RHO)
    bonds = build_bonds_for(deck, cloud)
    s0 = material.critical_stretch(G0, 2, bonds.horizon, H, "stress")
    no_fail = np.union1d(cloud.node_set("left"), cloud.node_set("right"))
    hand = Evaluator(
        cloud,
        bonds,
        material,
        CriticalStretch(s0, no_fail),
        surface_correction=True,
        damping=2e5,
    )
    runs = []
    for solver in (sim.solver, dataclasses.replace(sim.solver, model=hand)):
        assert isinstance(solver.model.damage_law, CriticalStretchLaw)
        s = solver.init()
        while not solver.done(s):
            solver.step(s)
        runs.append(s)
    a, b = runs
    assert a.bonds_broken == b.bonds_broken > 0
    for name in ("u", "v", "force", "intact", "max_stretch"):
        assert np.array_equal(a[name], b[name]), name


@pytest.mark.parametrize(
    ("damage", "key"),
    [
        ({"bond_law": "bilinear", "fracture_energy": G0}, "damage.tensile_strength"),
        ({"bond_law": "bilinear", "tensile_strength": FT}, "damage.fracture_energy"),
        (
            {"bond_law": "trilinear", "tensile_strength": FT, "critical_stretch": 1e-3},
            "damage.critical_stretch",
        ),
        (
            {
                "bond_law": "bilinear",
                "tensile_strength": FT,
                "fracture_energy": G0,
                "model": "none",
            },
            "damage.bond_law",
        ),
        (
            {
                "bond_law": "bilinear",
                "tensile_strength": FT,
                "fracture_energy": G0,
                "sed_softening": {"levels": 4},
            },
            "damage.sed_softening",
        ),
        (
            {
                "bond_law": "bilinear",
                "tensile_strength": FT,
                "fracture_energy": G0,
                "weibull": {"shape": 10},
            },
            "damage.weibull",
        ),
        (
            {
                "bond_law": "bilinear",
                "tensile_strength": FT,
                "fracture_energy": G0,
                "trilinear_knee": [0.3, 0.3],
            },
            "damage.trilinear_knee",
        ),
        (
            {
                "bond_law": "trilinear",
                "tensile_strength": FT,
                "fracture_energy": G0,
                "trilinear_knee": [0.3, 1.2],
            },
            "damage.trilinear_knee",
        ),
        ({"bond_law": "quadratic", "fracture_energy": G0}, "damage.bond_law"),
    ],
)
def test_deck_rejects_bad_softening_combinations(damage: dict, key: str) -> None:
    with pytest.raises(DeckError) as info:
        parse_deck(plate(damage))
    assert key in [path for path, _ in info.value.errors], info.value.errors


def test_deck_softening_needs_a_bond_based_material() -> None:
    d = plate({"bond_law": "bilinear", "tensile_strength": FT, "fracture_energy": G0})
    d["material"] = {"model": "lps", "youngs_modulus": E, "poisson_ratio": 0.25, "density": RHO}
    with pytest.raises(DeckError) as info:
        parse_deck(d)
    paths = [path for path, _ in info.value.errors]
    assert "damage.bond_law" in paths and "damage.tensile_strength" not in paths


def test_deck_softening_needs_a_solver_that_commits_its_history() -> None:
    d = plate({"bond_law": "bilinear", "tensile_strength": FT, "fracture_energy": G0})
    d["solver"] = {"type": "static"}
    with pytest.raises(DeckError) as info:
        parse_deck(d)
    assert [p for p, _ in info.value.errors] == ["damage.bond_law"]
    d["solver"] = {"type": "adr"}
    parse_deck(d)


def test_deck_strength_too_high_for_the_horizon_is_a_setup_error() -> None:
    d = plate({"bond_law": "bilinear", "tensile_strength": 60e6, "fracture_energy": 1.0})
    with pytest.raises(ValueError, match="damage.tensile_strength") as info:
        Simulation.from_deck(parse_deck(d))
    assert "smaller horizon" in str(info.value)


def test_build_damage_gives_the_softening_parameters() -> None:
    deck = parse_deck(
        plate(
            {
                "bond_law": "trilinear",
                "tensile_strength": FT,
                "fracture_energy": G0,
                "trilinear_knee": [0.25, 0.3],
            }
        )
    )
    sim = Simulation.from_deck(deck)
    dmg = build_damage(deck.damage, deck.material, sim.model.material, sim.cloud, sim.model.bonds)
    assert isinstance(dmg, SofteningBonds)
    assert dataclasses.astuple(dmg)[:4] == ("trilinear", FT, G0, (0.25, 0.3))
    assert np.array_equal(
        dmg.no_fail, np.union1d(sim.cloud.node_set("left"), sim.cloud.node_set("right"))
    )
    assert sim.model.force_model.knee == (0.25, 0.3)
