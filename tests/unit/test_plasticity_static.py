"""Elastic-plastic correspondence under the static (Newton) solver: the history is
committed on a converged load level only (never inside Newton, kept through a cut-back
or a failed level), and (long) a 3-D J2 bar against the closed-form uniaxial response."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.deck import parse_deck
from peridynamics.families.correspondence.plastic_force import HISTORY, TRIAL
from tests.helpers import count_commits

E, NU = 200e9, 0.3
LENGTH = 0.02

DECK = {
    "name": "plastic_static",
    "geometry": {"type": "box", "size": [LENGTH, 0.004, 0.004]},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
    "material": {
        "model": "correspondence",
        "youngs_modulus": E,
        "poisson_ratio": NU,
        "density": 7800.0,
    },
    "node_sets": {
        "left": {"box": {"min": [-1, -1, -1], "max": [0.001, 1, 1]}},
        "right": {"box": {"min": [LENGTH - 0.001, -1, -1], "max": [1, 1, 1]}},
    },
    "output": {"plot": "none", "vtk_every": 0},
}


def _sim(
    plasticity: dict, strain: float, values: list[float], steps: int, small: bool = False, **solver
) -> Simulation:
    """A 3-D bar, 20 x 4 x 4 points (``small``: 8 x 3 x 3, horizon 2.015 dx), its left
    end layer fixed, its right one pulled in x (y, z free), the end displacement
    following ``values`` at times linspace(0, 1), static solver."""
    d = copy.deepcopy(DECK)
    length = LENGTH
    if small:
        length = 0.008
        d["geometry"]["size"] = [length, 0.003, 0.003]
        d["discretisation"]["horizon_factor"] = 2.015
        d["node_sets"]["right"]["box"]["min"][0] = length - 0.001
    d["material"]["plasticity"] = plasticity
    times = list(np.linspace(0.0, 1.0, len(values)))
    d["boundary_conditions"] = [
        {"type": "fixed", "set": "left"},
        {"type": "displacement", "set": "right", "components": {"x": strain * (length - 1e-3)},
         "time_function": {"type": "table", "times": times, "values": values}},
    ]  # fmt: skip
    d["solver"] = {"type": "static", "load_steps": steps, "tolerance": 1e-9,
                   "proportional": False, **solver}  # fmt: skip
    return Simulation.from_deck(parse_deck(d))


J2 = {"type": "j2", "yield_stress": 200e6, "hardening_modulus": 20e9}


def test_history_is_committed_on_converged_levels_only() -> None:
    sim = _sim(J2, 3e-3, [0.0, 1.0], 2, small=True, max_iterations=30)
    fm = sim.model.force_model
    calls = count_commits(fm)
    s = sim.solver.init()
    res = sim.solver.step(s)  # strain 1.5e-3, past yield (1e-3)
    assert res.converged and calls == [1]  # once, after Newton, from the converged u
    committed = s[HISTORY].copy()
    assert np.abs(committed).max() > 0  # yielded
    # the next level with one Newton iteration and no cut-back fails: back to the last
    # equilibrium, the committed history untouched
    sim.solver.max_iterations, sim.solver.max_cutbacks = 1, 0
    res = sim.solver.step(s)
    assert not res.converged and "not_converged" in res.events
    assert calls == [1]
    assert np.array_equal(s[HISTORY], committed)


def test_a_cut_back_restarts_from_the_committed_history() -> None:
    kw = {"max_iterations": 3, "max_cutbacks": 6}
    sim = _sim(J2, 3e-3, [0.0, 1.0], 1, small=True, **kw)
    s = sim.solver.init()
    res = sim.solver.step(s)  # one level to 3e-3 fails in 3 iterations: cut back
    assert res.converged and "cut_back" in res.events
    lam = sim.solver.lam
    assert 0.0 < lam < 1.0
    # the same level reached directly from the virgin state: the same history
    ref = _sim(J2, 3e-3 * lam, [0.0, 1.0], 1, small=True, max_iterations=30)
    r = ref.solver.init()
    assert ref.solver.step(r).converged
    scale = np.abs(r[HISTORY]).max()
    assert np.abs(s[HISTORY] - r[HISTORY]).max() <= 1e-6 * scale


@pytest.mark.long
def test_static_j2_bar_against_the_closed_form() -> None:
    sy, h = 200e6, 20e9
    sim = _sim({"type": "j2", "yield_stress": sy, "hardening_modulus": h}, 3e-3, [0, 1, 0.5], 8)
    fm = sim.model.force_model
    s = sim.solver.init()
    mid = np.abs(sim.model.cloud.x[:, 0] - LENGTH / 2) < 0.0016
    rows = []
    for _ in range(8):
        assert sim.solver.step(s).converged
        f = s["deformation_gradient"].reshape(-1, 3, 3)
        sig = fm.point_stress(s)
        rows.append(
            (f[mid, 0, 0].mean() - 1.0, sig[mid, 0, 0].mean(), np.abs(sig[mid, 1, 1]).max())
        )
    eps, sig, lateral = (np.array(c) for c in zip(*rows, strict=True))
    et = E * h / (E + h)
    want = np.where(eps <= sy / E, E * eps, sy + et * (eps - sy / E))
    assert abs(sig[0] / (E * eps[0]) - 1) < 0.01  # elastic slope
    assert np.all(np.abs(sig[:4] / want[:4] - 1) < 0.01)  # yield and hardening
    assert abs((sig[3] - sig[2]) / (eps[3] - eps[2]) / et - 1) < 0.01  # hardening slope
    assert abs((sig[3] - sig[4]) / (eps[3] - eps[4]) / E - 1) < 0.01  # unloading slope
    assert lateral.max() < 0.01 * sig.max()
    print("static J2 bar", sim.solver.stats["newton_iterations"], sig / want)


def test_the_tangent_perturbs_about_the_committed_history() -> None:
    """The finite-difference tangent reads the committed history (on a copy of the
    state), never the trial one the last evaluation left."""
    sim = _sim(J2, 3e-3, [0.0, 1.0], 2, small=True, max_iterations=30)
    s = sim.solver.init()
    assert sim.solver.step(s).converged
    k = sim.model.tangent(s).toarray()
    trial = s[TRIAL].copy()
    s[TRIAL][...] = 1e3  # garbage in the trial history
    assert np.array_equal(sim.model.tangent(s).toarray(), k)
    s[TRIAL][...] = trial
    s[HISTORY][...] = 0.0  # another committed history: another tangent
    assert not np.allclose(sim.model.tangent(s).toarray(), k)
