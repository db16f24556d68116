"""Elastic-plastic LPS (Mitchell 2011) under the static (Newton) solver: the analytic
tangent is the consistent one of the return map (central differences of the force and
the finite-difference tangent, not the elastic tangent), every evaluation returns from
the committed history, the backtracked Newton converges past yield where full steps
cycle, the history is committed on converged levels only (a failed level and a cut-back
leave it), the static curve of a bar is the ADR one, and (long) the example bar against
ADR and closed-form J2."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from peridynamics.app.run import Simulation
from peridynamics.deck import parse_deck
from peridynamics.families.lps import plastic as pl
from peridynamics.families.lps.tangent import lps_tangent
from peridynamics.families.tangent import finite_difference_tangent
from tests.helpers import count_commits

E, SY, H = 200e9, 200e6, 20e9
LENGTH = 0.008
PLASTICITY = {"type": "j2", "yield_stress": SY, "hardening_modulus": H}
DECK = {
    "name": "lps_plastic_static",
    "geometry": {"type": "box", "size": [LENGTH, 0.003, 0.003]},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 2.015},
    "material": {"model": "lps", "youngs_modulus": E, "poisson_ratio": 0.3, "density": 7800.0,
                 "plasticity": PLASTICITY},
    "node_sets": {"left": {"box": {"min": [-1, -1, -1], "max": [0.001, 1, 1]}},
                  "right": {"box": {"min": [LENGTH - 0.001, -1, -1], "max": [1, 1, 1]}}},
    "output": {"plot": "none", "vtk_every": 0},
}  # fmt: skip


def _deck(strain: float, values: list[float], steps: int, **solver) -> dict:
    """The 8 x 3 x 3 bar, its left end layer fixed, its right one pulled in x to
    ``strain`` times the distance of the end layers, following ``values`` at times
    linspace(0, 1); static solver (``solver`` overrides)."""
    d = copy.deepcopy(DECK)
    times = list(np.linspace(0.0, 1.0, len(values)))
    d["boundary_conditions"] = [
        {"type": "fixed", "set": "left"},
        {"type": "displacement", "set": "right", "components": {"x": strain * (LENGTH - 1e-3)},
         "time_function": {"type": "table", "times": times, "values": values}},
    ]  # fmt: skip
    d["solver"] = {"type": "static", "load_steps": steps, "tolerance": 1e-9,
                   "proportional": False, "max_iterations": 30, **solver}  # fmt: skip
    return d


def _sim(strain: float, values: list[float], steps: int, **solver) -> Simulation:
    return Simulation.from_deck(parse_deck(_deck(strain, values, steps, **solver)))


def _yielded_iterate(sim: Simulation):
    """The first Newton iterate of a level at the yield strain: its prescribed end jumped,
    the rest where the last equilibrium (u = 0) left it; many points past yield."""
    solver, model = sim.solver, sim.model
    s = solver.init()
    target = solver._set_loads(s, 1.0)
    q = solver._gather(s).reshape(-1)
    q[solver.fixed] = target[solver.fixed]
    solver._scatter(q.reshape(-1, 3), s)
    model.evaluate(s, commit=False)
    dq = solver.system.solve(s, solver._unbalanced(s))
    q[solver.system.free] += dq
    solver._scatter(q.reshape(-1, 3), s)
    model.evaluate(s, commit=False)
    return s


def _directional_errors(sim: Simulation, s, k, seed: int) -> list[float]:
    """||K v + d(V f)/dh|| / ||d(V f)/dh|| for three random directions v, the derivative
    by central differences (h = 1e-11 m; displacements ~1e-5 m)."""
    fm = sim.model.force_model
    vol = fm.cloud.volume[:, None]

    def vf(u: np.ndarray) -> np.ndarray:
        w = s.copy()
        w.u[...] = u
        fm.prepass(w)
        fm.force(w)
        return (w.force * vol).reshape(-1)

    rng = np.random.default_rng(seed)
    h, out = 1e-11, []
    for _ in range(3):
        v = rng.standard_normal(s.u.shape)
        fd = -(vf(s.u + h * v) - vf(s.u - h * v)) / (2 * h)
        out.append(float(np.linalg.norm(k @ v.reshape(-1) - fd) / np.linalg.norm(fd)))
    return out


def test_the_tangent_is_the_consistent_one_of_the_return_map() -> None:
    """Measured: the analytic tangent against central differences of V f 1.4e-10 and
    against the finite-difference tangent 2.3e-7 (its own truncation); the elastic LPS
    tangent misses by 0.40 to 0.47."""
    sim = _sim(1e-3, [0.0, 1.0], 1)
    model, fm = sim.model, sim.model.force_model
    s = _yielded_iterate(sim)
    assert (s[pl.SCALE] < 1.0).sum() > 20  # on the plastic branch
    k = model.tangent(s)
    assert max(_directional_errors(sim, s, k, 4)) < 1e-7
    fd = finite_difference_tangent(fm, s)
    assert abs(k - fd).max() < 1e-5 * abs(fd).max()
    elastic = lps_tangent(fm, s)
    assert min(_directional_errors(sim, s, elastic, 4)) > 0.05  # the elastic one is not it


def test_the_tangent_with_a_random_history_and_broken_bonds() -> None:
    """A committed history that is not deviatoric (S_i != 0: the nonsymmetric term) and
    5 % of the bonds broken; 46 of the 72 points yielding. Measured 8.8e-11 to 1.5e-10
    against central differences."""
    sim = _sim(1e-3, [0.0, 1.0], 1)
    fm = sim.model.force_model
    rng = np.random.default_rng(7)
    s = sim.model.new_state()
    s.u[...] = fm.cloud.x @ np.diag([1e-3, -3.3e-4, -2.5e-4])
    s.u[...] += 1e-7 * rng.standard_normal(s.u.shape)
    cut = rng.random(len(s.intact)) < 0.05
    s.intact[cut | cut[fm.reverse]] = 0
    s[pl.EXTENSION][...] = 2e-7 * rng.standard_normal(fm.bonds.n_bonds)
    s[pl.STRAIN][...] = 1e-3 * rng.random(fm.cloud.n_points)
    fm.prepass(s)
    yielding = int((s[pl.SCALE] < 1.0).sum())
    assert 10 < yielding < fm.cloud.n_points - 10, yielding
    k = sim.model.tangent(s)
    assert max(_directional_errors(sim, s, k, 5)) < 1e-7
    asym = abs(k - k.T).max() / abs(k).max()
    assert asym > 1e-3  # the plastic term of a non-deviatoric history (measured 0.041)


def test_every_evaluation_returns_from_the_committed_history() -> None:
    """The force and the tangent read the committed ep, q; garbage in the trial fields
    (the last iterate's return) changes neither."""
    sim = _sim(1e-3, [0.0, 1.0], 1)
    model = sim.model
    s = _yielded_iterate(sim)
    force, k = s.force.copy(), model.tangent(s).toarray()
    s[pl.EXTENSION_TRIAL][...] = 1e-3
    s[pl.STRAIN_TRIAL][...] = 0.5
    model.evaluate(s, commit=False)
    assert np.array_equal(s.force, force)
    s[pl.EXTENSION_TRIAL][...] = 1e-3
    assert np.array_equal(model.tangent(s).toarray(), k)
    s[pl.STRAIN][...] = 1e-3  # another committed history: another force
    model.evaluate(s, commit=False)
    assert not np.allclose(s.force, force)


def test_backtracked_newton_converges_past_yield_where_full_steps_cycle() -> None:
    """Loading to 3e-3 (3 yield strains) and unloading to 1.5e-3 in 4 levels: every level
    converges without a cut-back (measured 5, 5, 8, 6 Newton iterations, 8 halvings in
    all); the same first level with full Newton steps does not converge in 12 (measured:
    nor in 200; the yielded set cycles, the residual stays ~2)."""
    sim = _sim(3e-3, [0.0, 1.0, 0.5], 4, max_cutbacks=0)
    s = sim.solver.init()
    its = []
    while not sim.solver.done(s):
        res = sim.solver.step(s)
        assert res.converged and not res.events, res
        its.append(res.iterations)
    assert max(its) <= 10, its
    assert s[pl.STRAIN].max() > 1e-3  # yielded
    assert sim.solver.stats["line_search_halvings"] > 0
    full = _sim(3e-3, [0.0, 1.0, 0.5], 4, max_cutbacks=0, max_iterations=12)
    full.solver.line_search = False
    r = full.solver.init()
    assert not full.solver.step(r).converged


def test_only_the_plastic_lps_asks_for_the_line_search() -> None:
    """The correspondence laws and the elastic LPS keep full Newton steps (their static
    results are unchanged bit for bit)."""
    d = _deck(3e-3, [0.0, 1.0], 1)
    assert Simulation.from_deck(parse_deck(copy.deepcopy(d))).solver.line_search
    d["material"]["model"] = "correspondence"
    assert not Simulation.from_deck(parse_deck(copy.deepcopy(d))).solver.line_search
    del d["material"]["plasticity"]
    d["material"]["model"] = "lps"
    assert not Simulation.from_deck(parse_deck(d)).solver.line_search


def test_history_is_committed_on_converged_levels_only() -> None:
    sim = _sim(3e-3, [0.0, 1.0], 2)
    fm = sim.model.force_model
    calls = count_commits(fm)
    s = sim.solver.init()
    assert sim.solver.step(s).converged  # 1.5e-3, past yield
    assert calls == [1]  # once, after Newton, from the converged u
    committed = s[pl.EXTENSION].copy(), s[pl.STRAIN].copy()
    assert committed[1].max() > 0
    sim.solver.max_iterations, sim.solver.max_cutbacks = 1, 0
    res = sim.solver.step(s)  # fails: back to the last equilibrium, history untouched
    assert not res.converged and "not_converged" in res.events
    assert calls == [1]
    assert np.array_equal(s[pl.EXTENSION], committed[0])
    assert np.array_equal(s[pl.STRAIN], committed[1])


def test_a_cut_back_restarts_from_the_committed_history() -> None:
    """A level past yield cut back after a yielded equilibrium: the history of the
    accepted (cut) level is the one reached directly from the last commit."""
    sim = _sim(3e-3, [0.0, 1.0], 2)
    s = sim.solver.init()
    assert sim.solver.step(s).converged  # 1.5e-3: yielded
    sim.solver.max_iterations, sim.solver.max_cutbacks = 4, 6
    res = sim.solver.step(s)  # to 3e-3 in 4 iterations fails: cut back
    assert res.converged and "cut_back" in res.events
    lam = sim.solver.lam
    assert 0.5 < lam < 1.0
    ref = _sim(3e-3, [0.0, 1.0], 2)
    r = ref.solver.init()
    assert ref.solver.step(r).converged
    before = r[pl.STRAIN].copy()
    assert ref.solver._equilibrium(r, lam)[0]  # the cut level directly from the commit
    ref.model.force_model.commit_history(r, fresh=True)
    assert r[pl.STRAIN].max() > before.max()  # it yielded further
    for name in (pl.EXTENSION, pl.STRAIN):
        scale = np.abs(r[name]).max()
        assert np.abs(s[name] - r[name]).max() <= 1e-6 * scale


def _curve(deck: dict) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """Axial strain between two inner sections, axial stress from the reaction of the
    pulled end, per load step; the iterations of every step."""
    sim = Simulation.from_deck(parse_deck(copy.deepcopy(deck)))
    x, vol = sim.model.cloud.x[:, 0], sim.model.cloud.volume
    length = deck["geometry"]["size"][0]
    side = deck["geometry"]["size"][1]
    dx = deck["discretisation"]["spacing"]
    layers = np.unique(np.round(x / (1e-3 * dx)) * (1e-3 * dx))
    xa, xb = layers[len(layers) // 3], layers[len(layers) - 1 - len(layers) // 3]
    a, b, right = np.abs(x - xa) < 1e-4 * dx, np.abs(x - xb) < 1e-4 * dx, x > length - dx
    s = sim.solver.init()
    eps, sig, its = [], [], []
    while not sim.solver.done(s):
        res = sim.solver.step(s)
        assert res.converged
        its.append(res.iterations)
        eps.append((s.u[b, 0].mean() - s.u[a, 0].mean()) / (xb - xa))
        sig.append(-(s.force[right, 0] * vol[right]).sum() / side**2)
    return np.array(eps), np.array(sig), its


def test_the_static_curve_of_a_small_bar_is_the_adr_one() -> None:
    """Loading past yield and unloading, 4 levels: static and ADR (tolerance 1e-10) give
    the same strain and stress at every level (measured 5.2e-11 and 2.1e-10 of the
    largest; the issue asks for 1 %)."""
    deck = _deck(3e-3, [0.0, 1.0, 0.5], 4)
    e_s, s_s, _ = _curve(deck)
    deck["solver"] = {"type": "adr", "load_steps": 4, "proportional": False,
                      "tolerance": 1e-10, "max_iterations": 50000}  # fmt: skip
    e_a, s_a, _ = _curve(deck)
    assert np.abs(s_s - s_a).max() < 1e-6 * np.abs(s_a).max()
    assert np.abs(e_s - e_a).max() < 1e-6 * np.abs(e_a).max()


@pytest.mark.long
def test_the_example_bar_static_against_adr_and_closed_form_j2() -> None:
    """``examples/plasticity/lps_bar.yaml`` with its left end fixed in x, y and z (the
    static solve needs no rigid-body modes) under the static solver and under ADR:
    the same curve (measured: 1.1e-9 of the stress, 3.0e-10 of the strain at every
    level; the issue asks for 1 %); against closed-form J2 with the bounds of
    test_lps_plasticity.py: elastic slope 1.0241 E, yield 1.0306 sigma_y, hardening slope
    1.0108 E H / (E + H), unloading slope 1.0028 x the elastic one. Newton iterations per
    level 7, 6, 7, 6, 6, 6, 8, 6 (docs/theory_plasticity.md)."""
    path = Path(__file__).resolve().parents[2] / "examples" / "plasticity" / "lps_bar.yaml"
    deck = yaml.safe_load(path.read_text())
    deck["boundary_conditions"][0].pop("components")
    e_a, s_a, _ = _curve(deck)
    deck["solver"] = {"type": "static", "load_steps": 8, "proportional": False,
                      "tolerance": 1e-9, "max_iterations": 30}  # fmt: skip
    e_s, s_s, its = _curve(deck)
    assert max(its) <= 10, its  # Newton iterations per level
    assert np.all(np.abs(s_s - s_a) <= 1e-6 * np.abs(s_a))
    assert np.all(np.abs(e_s - e_a) <= 1e-6 * np.abs(e_a))
    ep, sg = np.concatenate([[0.0], e_s]), np.concatenate([[0.0], s_s])
    k = int(np.argmax(ep))
    slope = np.diff(sg) / np.diff(ep)
    e_bar, hard = slope[0], slope[k - 1]
    eps_y = (sg[k] - hard * ep[k]) / (e_bar - hard)
    et = E * H / (E + H)
    assert abs(e_bar / E - 1) < 0.04
    assert abs(e_bar * eps_y / SY - 1) < 0.04
    assert abs(hard / et - 1) < 0.03
    assert abs(slope[k] / e_bar - 1) < 0.005  # unloading: the bar's own elastic slope
