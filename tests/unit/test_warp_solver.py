"""``solver.backend: warp`` on Warp's CPU device against the Numba backend: the same
damage (identical bond flags) and fields within 1e-12 for PMB crack branching, LPS with
damage, viscosity + damping + every kinematic condition + body forces, central
difference, SED softening; the instability check stops at the same step; a resumed
run continues the same; refusals name the key. Skipped without warp-lang."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.app.run_resume import read_resume
from peridynamics.build.errors import SetupError
from peridynamics.deck import load_deck, parse_deck
from peridynamics.solvers import SimulationUnstable
from tests.helpers import EXAMPLES

wp = pytest.importorskip("warp", reason="warp-lang not installed (pip install '.[gpu]')")
pytestmark = pytest.mark.gpu  # the Warp tier (pytest -m gpu); the smoke test: test_warp_kernels.py

WARP = ["solver.backend=warp", "solver.device=cpu"]
BRANCHING = [
    "discretisation.spacing=5e-4",
    "solver.end_time=22e-6",
    "output.plot=none",
    "output.vtk_every=0",
]
LPS_DECK = """
name: lps_explicit
geometry: {type: rectangle, size: [0.02, 0.01], thickness: 1.0e-3, plane: stress}
discretisation: {spacing: 5.0e-4, horizon_factor: 3.015}
material: {model: lps, youngs_modulus: 70.0e9, density: 2700.0, poisson_ratio: 0.3}
damage: {model: critical_stretch, critical_stretch: 2.0e-3}
node_sets:
  left: {edge: {normal: [-1.0, 0.0]}}
  right: {edge: {normal: [1.0, 0.0]}}
boundary_conditions:
  - {type: velocity, set: right, components: {x: 5.0}}
  - {type: velocity, set: left, components: {x: -5.0}}
solver: {type: explicit, steps: 200, safety_factor: 0.8}
output: {history_every: 20, plot: none, vtk_every: 0}
"""
EXTRAS_DECK = """
name: extras
geometry: {type: rectangle, size: [0.02, 0.01], thickness: 1.0e-3, plane: strain}
discretisation: {spacing: 5.0e-4, horizon_factor: 3.015}
material:
  model: pmb
  youngs_modulus: 70.0e9
  density: 2700.0
  viscosity: {linear: 0.2, quadratic: 2.0}
damage: {model: critical_stretch, critical_stretch: 1.0e-3}
node_sets:
  left: {edge: {normal: [-1.0, 0.0]}}
  right: {edge: {normal: [1.0, 0.0]}}
  top: {edge: {normal: [0.0, 1.0]}}
boundary_conditions:
  - {type: fixed, set: left, components: [x]}
  - type: displacement
    set: right
    components: {x: 2.0e-5}
    time_function: {type: sine_pulse, duration: 2.0e-5}
  - {type: velocity, set: top, components: {y: 0.5}}
  - {type: body_force, set: all, value: [0.0, -2.65e6]}
solver: {type: explicit, steps: 150, safety_factor: 0.8, damping: 2000.0}
output: {history_every: 10, plot: none, vtk_every: 0}
"""


def _run(deck, out: Path) -> tuple[dict, dict]:
    summary = Simulation.from_deck(deck).run(out, quiet=True)
    data = np.load(out / "final_state.npz")
    return summary, {k: data[k] for k in data.files}


def _compare(tmp: Path, make, tol: float = 1e-10) -> tuple[dict, dict]:
    """Run the deck on both backends; identical bond flags, fields within ``tol`` of
    their largest value. One force pass agrees to ~1e-16 (the host's PMB pass is
    compiled with fast-math, Warp's is not); a few hundred steps of a running crack
    amplify that to ~2e-12 (measured), hence 1e-10 for whole runs."""
    sn, fn = _run(make([]), tmp / "numba")
    sw, fw = _run(make(WARP), tmp / "warp")
    assert sw["results"]["backend"] == "warp" and sw["results"]["device"] == "cpu"
    assert sn["results"].get("backend") is None
    if "intact" in fn:
        assert np.array_equal(fn["intact"], fw["intact"])
    if "damage" in fn:
        assert np.array_equal(fn["damage"], fw["damage"])
    for name in ("u", "v"):
        scale = float(np.abs(fn[name]).max())
        assert scale > 0
        assert np.abs(fw[name] - fn[name]).max() <= tol * scale, name
    hn, hw = sn["results"]["history"], sw["results"]["history"]
    for name in ("strain_energy_J", "kinetic_energy_J"):  # outputs see the device's state
        a, b = np.asarray(hn[name]), np.asarray(hw[name])
        assert a.shape == b.shape and a.max() > 0, name
        assert np.abs(a - b).max() <= 1e-8 * a.max(), name
    return sn, sw


def test_branching_same_damage(tmp_path: Path) -> None:
    deck = EXAMPLES / "crack_branching_2d" / "deck.yaml"
    sn, sw = _compare(tmp_path, lambda extra: load_deck(deck, overrides=BRANCHING + extra))
    assert sn["results"]["bonds_broken"] > 300  # the crack runs
    assert sw["results"]["bonds_broken"] == sn["results"]["bonds_broken"]
    assert sw["results"]["crack_length_m"] == pytest.approx(sn["results"]["crack_length_m"], 1e-12)


@pytest.mark.parametrize("deck", ["bar_wave_1d/deck.yaml", "spalling/test_bar_pd3.yaml"])
def test_one_dimensional_bars(tmp_path: Path, deck: str) -> None:
    path = EXAMPLES / deck
    over = ["output.plot=none", "output.vtk_every=0"]
    _compare(tmp_path, lambda extra: load_deck(path, overrides=over + extra))


def _text_deck(text: str, extra: list[str]):
    import yaml

    from peridynamics.deck import apply_overrides

    raw = yaml.safe_load(text)
    return parse_deck(apply_overrides(raw, extra))


def test_lps_with_damage(tmp_path: Path) -> None:
    sn, _ = _compare(tmp_path, lambda extra: _text_deck(LPS_DECK, extra))
    assert sn["results"]["bonds_broken"] > 0


@pytest.mark.parametrize(
    ("stabilization", "damage"),
    [("lbscmm", "{model: critical_stretch, critical_stretch: 2.0e-3}"),
     ("silling2017", "{model: principal_stress, tensile_strength: 6.0e7}")],
)  # fmt: skip
def test_correspondence_explicit(tmp_path: Path, stabilization: str, damage: str) -> None:
    text = LPS_DECK.replace(
        "model: lps", f"model: correspondence, stabilization: {stabilization}"
    ).replace("damage: {model: critical_stretch, critical_stretch: 2.0e-3}", f"damage: {damage}")
    sn, _ = _compare(tmp_path, lambda extra: _text_deck(text, extra))
    assert sn["results"]["bonds_broken"] > 0


@pytest.mark.parametrize("integrator", ["velocity_verlet", "central_difference"])
def test_conditions_loads_viscosity_damping(tmp_path: Path, integrator: str) -> None:
    extra = [f"solver.integrator={integrator}"]
    _compare(tmp_path, lambda more: _text_deck(EXTRAS_DECK, extra + more))


@pytest.mark.parametrize("friction", [False, True])
def test_sed_softening_rock(tmp_path: Path, friction: bool) -> None:
    """SED softening, Weibull thresholds, no-fail platens, crack-face contact (with
    Coulomb friction in the second case)."""
    deck = EXAMPLES / "rock_compression" / "flaw45.yaml"
    over = ["discretisation.spacing=1e-3", "solver.steps=800", "output.plot=none",
            "output.vtk_every=0"]  # fmt: skip
    if friction:
        over += ["contact.friction_static=0.6", "contact.friction_kinetic=0.5"]
    # 800 steps of softening, breaking and crack-face contact amplify the per-pass
    # rounding difference (1.6e-10 of max |v| measured after 1000 steps); the bond flags
    # stay identical
    make = lambda extra: load_deck(deck, overrides=over + extra)  # noqa: E731
    if not friction:
        sn, _ = _compare(tmp_path, make, tol=1e-8)
        assert sn["results"]["bonds_broken"] > 0
        return
    # friction: the solvers alone (no outputs), the friction work (J) summed on the
    # device in another order than the host's
    states = []
    for extra in ([], WARP):
        solver = Simulation.from_deck(make(extra)).solver
        s = solver.init()
        while not solver.done(s):
            solver.step(s)
        states.append(s)
    a, b = states
    assert a.bonds_broken > 0 and np.array_equal(a.intact, b.intact)
    assert np.abs(a.u - b.u).max() <= 1e-8 * np.abs(a.u).max()
    work = [float(x["friction_work"][0]) for x in states]
    assert work[0] > 0 and work[1] == pytest.approx(work[0], rel=1e-8)


def test_unstable_step_stops_at_the_same_step(tmp_path: Path) -> None:
    over = ["solver.time_step=4e-7", "solver.allow_unstable=true", "solver.end_time=4e-5",
            "damage.critical_stretch=10.0"]  # fmt: skip
    steps = []
    for extra in ([], WARP):
        deck = _text_deck(LPS_DECK.replace("steps: 200, ", ""), over + extra)
        with pytest.raises(SimulationUnstable) as got:
            Simulation.from_deck(deck).run(tmp_path / str(len(extra)), quiet=True)
        steps.append(got.value.step)
        assert got.value.last_good is not None and got.value.last_good.step < got.value.step
    assert steps[0] == steps[1]


def test_resume_continues_the_same(tmp_path: Path) -> None:
    deck = _text_deck(LPS_DECK, WARP)
    Simulation.from_deck(deck).run(tmp_path / "full", quiet=True)
    part = _text_deck(LPS_DECK, [*WARP, "solver.steps=120"])
    Simulation.from_deck(part).run(tmp_path / "part", quiet=True, checkpoint_every=60)
    # continue the same run to 200 steps from its checkpoint at step 120
    ck = json.loads((tmp_path / "part" / "summary.json").read_text())
    assert ck["status"] == "completed"
    sim = Simulation.from_deck(part)
    state, *_ = read_resume(sim.session, tmp_path / "part")
    sim.solver.resume(state)
    sim.solver.n_steps = 200
    while not sim.solver.done(state):
        sim.solver.step(state)
    full = np.load(tmp_path / "full" / "final_state.npz")
    assert np.array_equal(state.intact, full["intact"])
    assert np.array_equal(state.u, full["u"])


def test_observers_copy_back_at_their_interval(tmp_path: Path) -> None:
    deck = _text_deck(LPS_DECK, [*WARP, "output.history_every=1000"])
    summary, _ = _run(deck, tmp_path)
    fields = summary["results"]
    # start, end, final state: a few copies of the fields, not one per step (200)
    n, bonds = 800, 40_000  # an upper bound of this deck's points and bonds
    assert fields["device_to_host_bytes"] < 20 * (n * 2 * 8 * 6 + bonds)


@pytest.mark.parametrize(
    ("extra", "key"),
    [
        (["solver.precision=float32"], "solver.precision"),
        (["solver.type=adr"], "explicit dynamics only"),
        (["solver.type=static"], "explicit dynamics only"),
    ],
)
def test_refusals_name_the_key(extra: list[str], key: str) -> None:
    deck_path = EXAMPLES / "crack_branching_2d" / "deck.yaml"
    with pytest.raises((SetupError, ValueError)) as got:
        Simulation.from_deck(load_deck(deck_path, overrides=BRANCHING + WARP + extra))
    assert key in str(got.value)


def test_without_warp_a_clear_error(monkeypatch: pytest.MonkeyPatch) -> None:
    import peridynamics.backends.warp_device as wd

    monkeypatch.setattr(wd, "wp", None)
    deck = load_deck(EXAMPLES / "crack_branching_2d" / "deck.yaml", overrides=BRANCHING + WARP)
    with pytest.raises(SetupError) as got:
        Simulation.from_deck(deck)
    assert "solver.backend" in str(got.value) and "[gpu]" in str(got.value)


def test_command_line_backend_flag(tmp_path: Path) -> None:
    from tests.helpers import cli

    deck = str(EXAMPLES / "crack_branching_2d" / "deck.yaml")
    sets = [x for pair in zip(["--set"] * 4, [*BRANCHING[:1], "solver.end_time=2e-6",
            *BRANCHING[2:]], strict=True) for x in pair]  # fmt: skip
    out = tmp_path / "run"
    cli("run", deck, *sets, "--backend", "warp", "--set", "solver.device=cpu", "--quiet",
        "--out", str(out), check=True)  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    assert summary["results"]["backend"] == "warp" and summary["results"]["steps"] > 10
    if wp.get_cuda_device_count() == 0:  # no GPU: a clear refusal naming the key
        over = [*BRANCHING, "solver.backend=warp", "solver.device=cuda"]
        with pytest.raises(SetupError) as got:
            Simulation.from_deck(load_deck(deck, overrides=over))
        assert got.value.path == "solver.device" and "no CUDA device" in str(got.value)
