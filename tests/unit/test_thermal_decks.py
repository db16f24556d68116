"""Thermo-mechanical coupling from a deck (``thermal.expansion``): the staggered
explicit coupling conducts heat exactly as the heat solver does (sub-cycled or not),
the temperature reaches probes and frames, the example bar held at its ends carries
sigma_xx = -E alpha dT, and what the coupling does not run is refused by key."""

from __future__ import annotations

import math

import numpy as np
import pytest

import peridynamics as pd
from peridynamics.build.simulation import SimulationSetup
from peridynamics.deck import DeckError

E, ALPHA, DT = 70e9, 23e-6, 100.0


def _thermal_deck(solver: dict, **extra):
    """The shipped conduction example at 4 mm with hot edges."""
    over = {"discretisation.spacing": 4e-3, "output.vtk_every": 0, "output.plot": "none",
            "solver": solver, **extra}  # fmt: skip
    return pd.Deck.example("thermal", over)


@pytest.mark.parametrize("conductivity", [237.0, 237.0e6])
def test_staggered_conduction_is_the_heat_solver(conductivity):
    """Explicit mechanics with thermal expansion, no mechanical load: after 40 steps
    the temperature is, bit for bit, that of the heat solver run with the coupling's
    sub-step (237 W/(m K): one sub-step per mechanical step; 237e6: the conduction's
    stable step is below the mechanical one, several sub-steps)."""
    coupled = _thermal_deck(
        {"type": "explicit", "steps": 40},
        **{"thermal.expansion": ALPHA, "thermal.conductivity": conductivity,
           "damage.model": "none"},
    )  # fmt: skip
    setup = SimulationSetup.from_deck(coupled)
    solver = setup.solver
    assert solver.coupling == "staggered"
    assert (solver.n_sub > 1) == (conductivity > 1e3)
    s = solver.init()
    for _ in range(40):
        solver.step(s)
    heat = SimulationSetup.from_deck(
        _thermal_deck(
            {"type": "heat", "steps": 40 * solver.n_sub, "time_step": solver.heat_step},
            **{"thermal.conductivity": conductivity},
        )
    ).solver
    h = heat.init()
    while not heat.done(h):
        heat.step(h)
    np.testing.assert_array_equal(s["T"], h["T"])
    assert s.t == pytest.approx(h.t, rel=1e-12)
    eps = setup.model.force_model.strain_per_kelvin * (s["T"] - 293.15)
    np.testing.assert_allclose(s["thermal_strain"], eps, rtol=1e-12, atol=1e-18)


@pytest.mark.parametrize(
    ("over", "key"),
    [
        ({"material.model": "micropolar"}, "thermal.expansion"),
        ({"solver.backend": "warp"}, "solver.backend"),
        ({"solver.precision": "float32"}, "solver.precision"),
        ({"thermal.expansion": None}, "thermal.expansion"),
        (
            {
                "damage.bond_law": "bilinear",
                "damage.tensile_strength": 1e8,
                "damage.fracture_energy": 100.0,
            },
            "damage.bond_law",
        ),  # fmt: skip
        ({"thermal.conductivity": None}, "thermal.conductivity"),
    ],
)
def test_what_the_coupling_does_not_run_is_refused_by_key(over, key):
    base = {"solver": {"type": "explicit", "steps": 2}, "thermal.expansion": ALPHA}
    with pytest.raises(DeckError, match=key.replace(".", r"\.")):
        pd.Deck.example("thermal", {**base, **over})


def test_a_staggered_static_run_is_refused():
    with pytest.raises(DeckError, match=r"thermal\.coupling"):
        pd.Deck.example("thermal/expansion", {"thermal.coupling": "staggered"})


def _bar(tmp_path, model: str, spacing: float):
    over = {"discretisation.spacing": spacing, "material.model": model, "output.vtk_every": 1}
    if model == "pmb":
        over["material.poisson_ratio"] = None
    if model == "correspondence":
        over["material.stabilization"] = "lbscmm"
    sim = pd.Simulation(pd.Deck.example("thermal/expansion", over), out=tmp_path / model)
    probes = sim.run().summary["results"]["probes"]
    return {k: v["values"][-1] for k, v in probes.items()}


def test_example_bar_runs_small(tmp_path):
    """The example at 1 mm (LPS, 40 x 10 points): the middle section in compression near
    -E alpha dT (measured 1.045 of it: the surface layers of a bar 3.3 horizons wide
    carry a share of the load; 1.009 at the example's 0.5 mm:
    test_example_bar_stress_within_one_percent), the temperature in the probes and
    the VTU frames."""
    p = _bar(tmp_path, "lps", 1e-3)
    assert p["middle_sxx"] == pytest.approx(-E * ALPHA * DT, rel=0.06)
    assert abs(p["middle_syy"]) < 0.01 * E * ALPHA * DT
    assert p["middle_T"] == pytest.approx(393.15, rel=1e-14)
    frames = sorted((tmp_path / "lps").rglob("*.vtu"))
    assert frames and b"temperature" in frames[-1].read_bytes()


@pytest.mark.long
@pytest.mark.parametrize("model", ["pmb", "lps", "correspondence"])
def test_example_bar_stress_within_one_percent(tmp_path, model):
    """The example at its spacing (0.5 mm), static solve: the mean sigma_xx of the
    middle section is -E alpha dT within 1 % (measured: pmb +0.40 %, lps +0.89 %,
    correspondence +0.12 %), sigma_yy below 1 % of it."""
    p = _bar(tmp_path, model, 5e-4)
    assert p["middle_sxx"] == pytest.approx(-E * ALPHA * DT, rel=0.01)
    assert abs(p["middle_syy"]) < 0.01 * E * ALPHA * DT
    assert math.isclose(p["middle_T"], 393.15, rel_tol=1e-14)


def test_a_decomposed_run_is_refused_by_key():
    """Under MPI (a communicator of two ranks) the coupling is refused before any build."""
    from peridynamics.build.errors import SetupError

    class TwoRanks:
        def Get_size(self) -> int:
            return 2

    deck = pd.Deck.example("thermal/expansion")
    with pytest.raises(SetupError, match=r"thermal\.expansion"):
        SimulationSetup.from_deck(deck, TwoRanks())


def test_quench_example_runs_small(tmp_path):
    """The thermal-shock example at 0.5 mm, 60 steps: the edges cool by convection
    (staggered conduction), the heat lost equals the change of the stored heat, the
    history records the probe's temperature, no bond breaks yet."""
    over = {"discretisation.spacing": 5e-4, "solver.end_time": None, "solver.steps": 60,
            "output.vtk_every": 0, "output.plot": "none"}  # fmt: skip
    sim = pd.Simulation(pd.Deck.example("thermal/quench", over), out=tmp_path / "q")
    res = sim.run().summary["results"]
    assert res["thermal_coupling"] == "staggered" and res["bonds_broken"] == 0
    edge = res["probes"]["edge_T"]["values"]
    assert edge[0] == pytest.approx(573.15) and edge[-1] < edge[0] - 1.0
    assert res["heat_stored_J"] == pytest.approx(res["heat_in_J"], rel=1e-10)
    assert res["heat_in_J"] < 0.0
    history = np.genfromtxt(tmp_path / "q" / "history.csv", delimiter=",", names=True)
    assert history["edge_T_K"][-1] == pytest.approx(edge[-1], rel=1e-12)


@pytest.mark.long
def test_quench_example_cracks_from_the_edges(tmp_path):
    """The example at its size to 8 ms: cracks start after 4 ms (measured 4.9 ms) from
    the cooled edges only (no damage 1.2 mm inside the plate), the response stays
    quasi-static (kinetic energy below 5 % of the strain energy; measured 2.7 %)."""
    over = {"solver.end_time": 8e-3, "output.vtk_every": 0, "output.plot": "none"}
    sim = pd.Simulation(pd.Deck.example("thermal/quench", over), out=tmp_path / "q")
    res = sim.run().summary["results"]
    assert res["bonds_broken"] > 0
    assert res["max_kinetic_to_strain_energy"] < 0.05
    final = np.load(tmp_path / "q" / "final_state.npz")
    x, dmg = final["x"], final["damage"]
    inner = np.all((x > 1.2e-3) & (x < np.array([0.01, 0.005]) - 1.2e-3), axis=1)
    assert dmg[inner].max() == 0.0 and dmg.max() > 0.2
    history = np.genfromtxt(tmp_path / "q" / "history.csv", delimiter=",", names=True)
    first = history["time_s"][np.flatnonzero(history["max_damage_"] > 0)[0]]
    assert first > 4e-3


def test_a_resumed_coupled_run_continues_bit_for_bit():
    """A copy of the State after 30 steps, resumed by a freshly built solver, reaches the
    State of 60 uninterrupted steps bit for bit (temperature, thermal strain, u): the
    coupling keeps all it needs in the State."""
    over = {"discretisation.spacing": 5e-4, "solver.end_time": None, "solver.steps": 60,
            "output.vtk_every": 0, "output.plot": "none"}  # fmt: skip
    deck = pd.Deck.example("thermal/quench", over)
    whole = SimulationSetup.from_deck(deck).solver
    s = whole.init()
    for _ in range(60):
        whole.step(s)
    first = SimulationSetup.from_deck(deck).solver
    r = first.init()
    for _ in range(30):
        first.step(r)
    saved = r.copy()
    second = SimulationSetup.from_deck(deck).solver
    second.resume(saved)
    for _ in range(30):
        second.step(saved)
    for name in ("T", "thermal_strain", "u", "v"):
        np.testing.assert_array_equal(saved[name], s[name])
