"""Fatigue by the remaining-life law with cycle jumping (:mod:`peridynamics.damage.fatigue`,
:mod:`peridynamics.solvers.fatigue`, docs/theory_fatigue.md).

Oracles: the NumPy twin of the kernels; the S-N law N = 1 / (A1 eps^m1) of a chain of
equal bonds (delta just above dx: every bond carries the same strain, so the first
break is the S-N life to rounding) at three amplitudes and three load ratios; a
brute-force loop that consumes life one cycle at a time and re-solves after every
break (the jumps must reproduce its breaks, in order, within a cycle per event); the
deck route, its refusals by key and the example deck at a small size.
"""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.bonds.bonds import build_bonds
from peridynamics.build.errors import SetupError
from peridynamics.damage.fatigue import LIFE, RemainingLife
from peridynamics.deck import DeckError, parse_deck
from peridynamics.geometry.generators import rectangle
from peridynamics.kernels import reference_fatigue as ref
from peridynamics.kernels.fatigue import advance_life, fatigue_rates
from peridynamics.solvers.fatigue import CYCLES, FatigueSolver
from peridynamics.solvers.linear import SingularSystem

pytestmark = pytest.mark.usefixtures("serial_numba")

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "fatigue" / "edge_crack.yaml"
A1, M1 = 1.0e9, 3.0  # N = 1e9^-1 eps^-3: 1e-3 -> 1 cycle, 1e-4 -> 1000 cycles


def _bar(strain: float, ratio: float = 0.0, horizon: float = 1.015, n: int = 11) -> dict:
    """A chain of ``n`` points dx = 1 cm, fixed at x = 0, pulled to ``strain`` at the far
    end (prescribed displacement)."""
    length = (n - 1) * 0.01
    return {
        "name": "fatigue_bar",
        "geometry": {"type": "bar", "length": length, "area": 1.0e-4, "nodes_on_boundary": True},
        "discretisation": {
            "spacing": 0.01,
            "horizon_factor": horizon,
            "surface_correction": False,
        },  # fmt: skip
        "material": {"youngs_modulus": 70.0e9, "density": 2700.0},
        "damage": {
            "model": "fatigue",
            "fatigue": {"m1": M1, "a1": A1, "m2": 4.0, "a2": 1.0e12},
        },
        "node_sets": {"left": {"point": [0.0]}, "right": {"point": [length]}},
        "boundary_conditions": [
            {"type": "fixed", "set": "left", "components": ["x"]},
            {"type": "displacement", "set": "right", "components": {"x": strain * length}},
        ],
        "solver": {
            "type": "fatigue",
            "load_ratio": ratio,
            "max_cycles": 1.0e12,
            "batch_tolerance": 1.0e-9,
        },  # fmt: skip
        "output": {"plot": "none", "bonds": False, "history_csv": False},
    }


def _run(solver: FatigueSolver, limit: int = 10_000) -> Any:
    s = solver.init()
    steps = 0
    while not solver.done(s):
        solver.step(s)
        steps += 1
        assert steps < limit
    return s


# ------------------------------------------------------------------------- kernels
def test_kernels_match_their_numpy_twins() -> None:
    cloud = rectangle((0.01, 0.006), 1e-3, thickness=1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    rng = np.random.default_rng(7)
    nb, n = bonds.n_bonds, cloud.n_points
    stretch = rng.normal(0.0, 1e-3, nb)
    intact = (rng.random(nb) > 0.1).astype(np.uint8)
    life = rng.random(nb)
    two = (rng.random(n) > 0.7).astype(np.uint8)
    can = (rng.random(n) > 0.05).astype(np.uint8)
    args = (0.9, 1e9, 3.0, 1e12, 4.2)
    rate, cycles = np.empty(nb), np.empty(nb)
    fatigue_rates(bonds.offsets, bonds.bond_j, stretch, intact, life, two, can, *args, rate, cycles)
    want_rate, want_cycles = ref.fatigue_rates(
        bonds.bond_i, bonds.bond_j, stretch, intact, life, two, can, *args
    )
    np.testing.assert_allclose(rate, want_rate, rtol=1e-14, atol=0)
    np.testing.assert_allclose(cycles, want_cycles, rtol=1e-14, atol=0)
    assert np.isinf(cycles[intact == 0]).all() and (rate[intact == 0] == 0).all()
    got = life.copy()
    advance_life(got, rate, intact, 123.5)
    np.testing.assert_allclose(got, ref.advance_life(life, rate, intact, 123.5), rtol=1e-14)


# ------------------------------------------------------------------------- S-N law
@pytest.mark.parametrize("strain", [2.0e-4, 5.0e-4, 1.0e-3])
@pytest.mark.parametrize("ratio", [0.0, 0.5, -1.0])
def test_uniform_bar_breaks_at_the_sn_life(strain: float, ratio: float) -> None:
    sim = Simulation.from_deck(parse_deck(_bar(strain, ratio)))
    solver = sim.solver
    assert isinstance(solver, FatigueSolver)
    s = _run(solver)
    # every bond of the chain has the stretch strain (rounding) and breaks at one jump
    eps = abs(1.0 - ratio) * strain
    want = 1.0 / (A1 * eps**M1)
    first = solver.stats["first_break_cycles"]
    assert math.isclose(first, want, rel_tol=1e-9), (first, want)
    assert int(s.intact.sum()) == 0 and solver.stats["increments"] == 1
    assert s[CYCLES][0] == first and np.all(s[LIFE] <= 0)


def test_sn_point_gives_a1() -> None:
    d = _bar(1e-3)
    d["damage"]["fatigue"] = {
        "m1": 3.0, "sn_point": {"strain_range": 2e-4, "cycles": 5e5}, "m2": 4.0, "a2": 1.0,
    }  # fmt: skip
    spec = parse_deck(d).damage.fatigue
    assert spec is not None
    assert math.isclose(spec.phase_one_a * 2e-4**3 * 5e5, 1.0, rel_tol=1e-12)


# ---------------------------------------------------------------- cycle jumping
def _brute_force(solver: FatigueSolver, max_cycles: int) -> list[tuple[int, tuple[int, ...]]]:
    """Consume life one cycle at a time; after a cycle that spends a bond's life, break
    it (both directions) and re-solve at the peak. Returns (cycle, broken bonds)."""
    s = solver.init()
    while solver.lam < 1.0:
        solver.step(s)
    law, fm, model = solver.law, solver.model.force_model, solver.model
    b = model.bonds
    events = []
    for n in range(1, max_cycles + 1):
        law.rates(s, fm.bond_stretch(s), model.point_damage(s.intact), solver.load_ratio)
        law.advance(s, 1.0)
        spent = np.flatnonzero((s[LIFE] <= 0) & (s.intact != 0))
        if spent.size == 0:
            continue
        both = np.unique(np.concatenate([spent, solver.reverse[spent]]))
        s.intact[both] = 0
        events.append((n, tuple(both.tolist())))
        solver.system.remove_pairs(s, both[b.bond_i[both] < b.bond_j[both]])
        try:
            converged, _, _ = solver._equilibrium(s, 1.0)
        except SingularSystem:  # a piece fell out: the end of the run
            break
        assert converged
    return events


def test_cycle_jumping_equals_a_cycle_by_cycle_loop() -> None:
    d = _bar(1.0e-4, ratio=0.1, horizon=3.015, n=13)  # end effects: bonds differ
    d["damage"]["fatigue"] = {"m1": 3.0, "a1": 5.0e7, "m2": 3.0, "a2": 2.0e8}
    d["solver"]["batch_tolerance"] = 0.0
    d["solver"]["max_cycles"] = 20_000.0
    deck = parse_deck(d)
    jump = Simulation.from_deck(deck).solver
    assert isinstance(jump, FatigueSolver)
    s = jump.init()
    events = []
    while not jump.done(s):
        before = s.intact.copy()
        jump.step(s)
        gone = np.flatnonzero(before != s.intact)
        if gone.size:
            events.append((s[CYCLES][0], tuple(gone.tolist())))
    brute = _brute_force(Simulation.from_deck(deck).solver, 20_000)
    # the loop breaks together what fails within one cycle: merge such jump events
    merged: list[tuple[float, tuple[int, ...]]] = []
    for n, gone in events:
        if merged and math.ceil(n) == math.ceil(merged[-1][0]):
            merged[-1] = (merged[-1][0], tuple(sorted(merged[-1][1] + gone)))
        else:
            merged.append((n, gone))
    assert len(merged) >= 3, events
    assert len(merged) == len(brute)
    assert [e[1] for e in merged[:-1]] == [e[1] for e in brute[:-1]]
    # the last event cuts the bar: the jumps stop at its first bond (the body falls
    # apart), the loop breaks the whole cycle's bonds before it solves
    assert set(merged[-1][1]) <= set(brute[-1][1])
    for k, ((n_jump, _), (n_loop, _)) in enumerate(zip(merged, brute, strict=True)):
        # the loop rounds each event up to a whole cycle: at most one cycle per event
        assert n_jump <= n_loop + 1e-9 and n_loop - n_jump <= k + 1, (k, n_jump, n_loop)


# ------------------------------------------------------------------- deck route
def test_deck_refusals_name_their_key() -> None:
    def paths(d: dict) -> list[str]:
        with pytest.raises(DeckError) as info:
            parse_deck(d)
        return [p for p, _ in info.value.errors]

    d = _bar(1e-3)
    d["solver"] = {"type": "static"}
    assert "solver.type" in paths(d)
    d = _bar(1e-3)
    d["damage"] = {"model": "critical_stretch", "critical_stretch": 0.01}
    assert "damage.model" in paths(d)
    d = _bar(1e-3)
    d["damage"]["critical_stretch"] = 0.01
    assert any(p.startswith("damage") for p in paths(d))
    d = _bar(1e-3)
    d["damage"]["fatigue"]["sn_point"] = {"strain_range": 1e-3, "cycles": 10.0}
    assert any(p.startswith("damage") for p in paths(d))
    d = _bar(1e-3)
    d["solver"]["backend"] = "warp"
    assert any(p.startswith("solver") for p in paths(d))
    d = _bar(1e-3)
    d["solver"]["load_ratio"] = 1.0
    assert any(p.startswith("solver.load_ratio") for p in paths(d))


def test_mpi_is_refused_by_key() -> None:
    from peridynamics.build.decomposed import _refuse

    with pytest.raises(SetupError) as info:
        _refuse(parse_deck(_bar(1e-3)), 2)
    assert "solver.type" in str(info.value) and "fatigue" in str(info.value)


def test_parameters_are_checked() -> None:
    with pytest.raises(ValueError, match="A1"):
        RemainingLife(a1=0.0, m1=3.0, a2=1.0, m2=3.0)
    with pytest.raises(ValueError, match="phase_two_damage"):
        RemainingLife(a1=1.0, m1=3.0, a2=1.0, m2=3.0, phase_two_damage=1.0)


def test_example_deck_runs_small(tmp_path: Path) -> None:
    """The example's edge-cracked plate at 4 mm spacing: the crack grows from the
    pre-crack, the summary and history report cycles and broken bonds."""
    import yaml

    d = yaml.safe_load(EXAMPLE.read_text())
    d["discretisation"]["spacing"] = 4.0e-3
    d["precracks"][0]["points"] = [[-0.001, 0.04], [0.01, 0.04]]
    d["solver"]["max_solves"] = 12
    sim = Simulation.from_deck(parse_deck(copy.deepcopy(d)))
    sim.run(tmp_path, quiet=True, progress=False)
    res = json.loads((tmp_path / "summary.json").read_text())["results"]
    assert res["solver"] == "fatigue" and res["fatigue_bonds_broken"] > 0
    assert 0 < res["first_break_cycles"] <= res["cycles"]
    header = (tmp_path / "history.csv").read_text().splitlines()[0]
    assert "cycles [-]" in header and "crack_tip [m]" in header
    assert "crack_length [m]" in header


def test_resume_continues_the_same_run() -> None:
    """A solver resumed from a copy of the State (what a checkpoint holds: the remaining
    lives and the cycle count are State fields) breaks the same bonds at the same N."""
    d = _bar(1.0e-4, ratio=0.1, horizon=3.015, n=13)
    d["damage"]["fatigue"] = {"m1": 3.0, "a1": 5.0e7, "m2": 3.0, "a2": 2.0e8}
    deck = parse_deck(d)
    whole = Simulation.from_deck(deck).solver
    s_whole = _run(whole)
    first = Simulation.from_deck(deck).solver
    s = first.init()
    for _ in range(3):
        first.step(s)
    again = Simulation.from_deck(deck).solver
    s2 = s.copy()
    again.resume(s2)
    while not again.done(s2):
        again.step(s2)
    assert again.cycles == whole.cycles
    np.testing.assert_array_equal(s2.intact, s_whole.intact)
    np.testing.assert_allclose(s2[LIFE], s_whole[LIFE], rtol=1e-12, atol=1e-15)


def test_load_control_ends_in_final_failure() -> None:
    """Under a traction the bar falls apart at its S-N life: the run ends there with
    ``final_failure`` (the end of its life, not a solver failure)."""
    d = _bar(1e-3)
    d["boundary_conditions"][1] = {"type": "traction", "set": "right", "value": [7.0e6]}
    d["solver"]["max_iterations"] = 4
    solver = Simulation.from_deck(parse_deck(d)).solver
    assert isinstance(solver, FatigueSolver)
    s = _run(solver)
    fields = solver.summary_fields(s)
    assert fields["final_failure"] is True and fields["converged"] is True
    # the cut chain leaves the loaded end point without stiffness: Newton cannot
    # balance the traction (or the stiffness is singular): both are final failure
    assert fields["end"].startswith("final failure") and fields["cycles"] < 1e12
    assert fields["cycles"] == fields["first_break_cycles"]
