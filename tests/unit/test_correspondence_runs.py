"""Correspondence through decks: key errors, explicit dynamics (stable step, energy,
bond breaking) and the damage factor history."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.deck import DeckError, parse_deck

BASE = {
    "name": "cc",
    "geometry": {"type": "rectangle", "size": [0.02, 0.01], "thickness": 1e-3},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
    "material": {
        "model": "correspondence",
        "youngs_modulus": 70e9,
        "poisson_ratio": 0.3,
        "density": 2700.0,
    },
    "node_sets": {
        "left": {"edge": {"normal": [-1.0, 0.0], "layers": 2}},
        "right": {"edge": {"normal": [1.0, 0.0], "layers": 2}},
    },
    "solver": {"steps": 10},
}


def _deck(**sections: object) -> dict:
    d = copy.deepcopy(BASE)
    for key, value in sections.items():
        if isinstance(value, dict) and isinstance(d.get(key), dict):
            d[key].update(value)
        else:
            d[key] = value
    return d


@pytest.mark.parametrize(
    ("sections", "key"),
    [
        ({"material": {"stabilization_g": 0.5}}, "material.stabilization_g"),
        ({"material": {"stabilization": "hourglass"}}, "material.stabilization"),
        ({"material": {"poisson_ratio": 0.5}}, "material.poisson_ratio"),
        ({"damage": {"model": "principal_stress"}}, "damage.tensile_strength"),
        (
            {
                "damage": {
                    "model": "principal_stress",
                    "tensile_strength": 1e6,
                    "critical_stretch": 1e-3,
                }
            },
            "damage.model",
        ),
    ],
)
def test_bad_keys_name_the_key(sections: dict, key: str) -> None:
    with pytest.raises(DeckError) as err:
        parse_deck(_deck(**sections))
    assert key in str(err.value)


def test_tensile_strength_needs_correspondence() -> None:
    d = _deck(damage={"critical_stretch": 1e-3, "tensile_strength": 1e6})
    d["material"] = {"youngs_modulus": 70e9, "density": 2700.0}
    with pytest.raises(DeckError, match="damage.tensile_strength"):
        parse_deck(d)


def test_correspondence_is_not_1d() -> None:
    d = _deck(geometry={"type": "bar", "length": 0.02})
    d["geometry"] = {"type": "bar", "length": 0.02}
    d["node_sets"] = {}
    with pytest.raises(DeckError, match="material.model"):
        parse_deck(d)


def _free_vibration(stab: str, dt_factor: float, steps: int = 1000) -> tuple[float, float]:
    """(initial energy, largest energy) of a free plate released from a random
    displacement, velocity Verlet at dt_factor x the model's stable step."""
    deck = parse_deck(_deck(material={"stabilization": stab}))
    m = Simulation.from_deck(deck).model
    s = m.new_state()
    s.u[...] = np.random.default_rng(5).normal(size=s.u.shape) * 1e-8
    dt = dt_factor * m.stable_time_step()
    inv_m = 1.0 / m.density[:, None]
    m.evaluate(s, commit=False)
    e0 = sum(m.state_energies(s))
    top = e0
    for k in range(steps):
        s.v += 0.5 * dt * s.force * inv_m
        s.u += dt * s.v
        m.evaluate(s, commit=False)
        s.v += 0.5 * dt * s.force * inv_m
        if k % 50 == 49:
            e = sum(m.state_energies(s))
            top = e if not np.isfinite(e) else max(top, e)
            if not np.isfinite(top) or top > 1e3 * e0:
                break
    return e0, top


@pytest.mark.parametrize("stab", ["none", "silling2017", "lbscmm"])
def test_explicit_step_from_the_stiffness_bound_is_stable(stab: str) -> None:
    """At the stable step the energy stays bounded (velocity Verlet's energy oscillates
    by O((omega dt)^2), it does not grow); at 3 x the step (beyond the measured
    looseness of the bound, 2.2-2.7 x in dt) it grows: the test can fail."""
    e0, top = _free_vibration(stab, 1.0)
    assert top <= 1.3 * e0
    e0, top = _free_vibration(stab, 3.0, steps=400)
    assert not top <= 10 * e0


def test_explicit_pull_breaks_bonds_and_records_the_damage_factor(tmp_path: Path) -> None:
    d = _deck(
        damage={"critical_stretch": 2e-3, "tensile_strength": 300e6, "no_fail": ["left", "right"]},
        precracks=[{"points": [[0.01, -0.001], [0.01, 0.004]]}],
        boundary_conditions=[
            {"type": "fixed", "set": "left"},
            {"type": "velocity", "set": "right", "components": {"x": 5.0}},
        ],
        solver={"end_time": 8e-6, "steps": None},
        output={"history_every": 20, "vtk_every": 0, "plot": "none"},
    )
    Simulation.from_deck(parse_deck(d)).run(tmp_path)
    r = json.loads((tmp_path / "summary.json").read_text())["results"]
    factor = r["history"]["damage_factor"]
    assert r["bonds_broken"] > 0
    assert factor[0] == 0 and factor[-1] > 0
    assert factor[-1] == pytest.approx(r["bonds_broken"] / r["n_bonds"])
    assert np.all(np.diff(factor) >= 0)


@pytest.mark.long
def test_static_newton_and_adr_agree(tmp_path: Path) -> None:
    """The implicit static solver (finite-difference tangent) and ADR give the same
    reaction of a pulled correspondence plate (SVK: geometrically nonlinear)."""
    reactions = []
    for solver in (
        {"type": "static", "load_steps": 2},
        {"type": "adr", "load_steps": 1, "tolerance": 1e-10},
    ):
        d = _deck(
            boundary_conditions=[
                {"type": "fixed", "set": "left"},
                {"type": "displacement", "set": "right", "components": {"x": 1e-5}},
            ],
            output={
                "probes": [
                    {"name": "r", "quantity": "reaction_force", "set": "right", "component": "x"}
                ],
                "plot": "none",
                "vtk_every": 0,
            },
        )
        d["solver"] = solver
        out = tmp_path / solver["type"]
        Simulation.from_deck(parse_deck(d)).run(out)
        r = json.loads((out / "summary.json").read_text())["results"]
        reactions.append(r["probes"]["r"]["values"][-1])
    assert reactions[0] > 0
    assert reactions[1] == pytest.approx(reactions[0], rel=1e-8)  # measured 2e-10


def test_static_solver_refuses_the_principal_stress_law() -> None:
    """The static solver breaks bonds by critical stretch between solves; with the
    principal-stress law it would never break one, so the deck is refused by key."""
    from tests.helpers import EXAMPLES, cli

    proc = cli(
        "check", "--bonds", str(EXAMPLES / "correspondence" / "plate_hole_damage.yaml"),
        "--set", "damage.model=principal_stress", "--set", "damage.critical_stretch=null",
        "--set", "damage.tensile_strength=3e8", "--set", "solver={type: static}",
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "damage.tensile_strength: the principal-stress failure criterion" in proc.stderr
    assert "solver.type: adr" in proc.stderr
