"""Right by default, robust at the edges: Ctrl-C, resume, size and value guards, YAML
numbers, --set errors and the smaller command-line faults (issue 11, items 7-13).

Most tests call the command line in-process (``peridynamics.cli.main``) or the Python
API; the two subprocess tests are the ones that need a real signal or exit code."""

from __future__ import annotations

import copy
import json
import math
import signal
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import pytest
import yaml

from peridynamics.app import checks as cli_mod
from peridynamics.app.run import RunInterrupted, Simulation
from peridynamics.build.errors import SetupError
from peridynamics.build.estimates import estimate_size, estimate_steps
from peridynamics.cli import main
from peridynamics.deck import DeckError, load_deck, yaml_load
from peridynamics.io.checkpoint import CHECKPOINT_NAME, read_checkpoint, read_checkpoint_meta
from tests.helpers import EXAMPLES, same_final_fields, sigint_at, subprocess_env

BAR = EXAMPLES / "bar_wave_1d" / "deck.yaml"
PLATE = EXAMPLES / "crack_branching_2d" / "deck.yaml"
# 60 steps of the 1-D bar (201 points): a fraction of a second on an idle machine
QUICK_BAR = [
    "solver.end_time=null",
    "solver.steps=60",
    "output.vtk_every=20",
    "output.plot=none",
    "output.history_every=5",
]


def _same_results(a: Path, b: Path) -> None:
    sa = json.loads((a / "summary.json").read_text())
    sb = json.loads((b / "summary.json").read_text())
    assert sa["results"] == sb["results"]
    same_final_fields(a, b, ("u", "v", "damage", "intact", "t", "step"))


# ------------------------------------------------------------------ 7. Ctrl-C
@pytest.fixture
def python_sigint_handler():
    """Python's own SIGINT handler for the test: a shell that starts pytest in the
    background leaves SIGINT ignored, which the run loop would (rightly) restore."""
    saved = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, saved)


def test_ctrl_c_stops_after_the_step_and_resumes_bitwise(
    tmp_path, capsys, python_sigint_handler
) -> None:
    deck = load_deck(BAR, QUICK_BAR)
    ref, cut = tmp_path / "ref", tmp_path / "cut"
    Simulation.from_deck(deck).run(ref, quiet=True)
    sim = Simulation.from_deck(deck)
    sigint_at(sim, 23)
    with pytest.raises(RunInterrupted) as info:
        sim.run(cut, quiet=True, checkpoint_every=10)
    assert info.value.step == 23 and info.value.checkpoint == cut / CHECKPOINT_NAME
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
    summary = json.loads((cut / "summary.json").read_text())
    assert summary["status"] == "interrupted" and summary["results"]["steps"] == 23
    state, records, _ = read_checkpoint(cut)
    assert state.step == 23 and records["checkpoint_every"] == 10
    assert read_checkpoint_meta(cut) == {"finished": False}
    # resume without an interval: the original run's 10 is kept
    Simulation.from_deck(deck).run(cut, quiet=False, resume=True, progress=False)
    assert "resuming from step 23 (t = 2.3e-05 s)" in capsys.readouterr().out
    _same_results(ref, cut)
    assert json.loads((cut / "summary.json").read_text())["status"] == "completed"
    state, _, _ = read_checkpoint(cut)
    assert state.step == 60 and read_checkpoint_meta(cut) == {"finished": True}
    pvd = (cut / "bar_wave_1d.pvd").read_text()
    assert pvd.count("<DataSet") == len(list(cut.glob("frame_*.vtu")))


def test_sigint_to_the_command_line_exits_130_with_a_resume_hint(tmp_path) -> None:
    out = tmp_path / "run"
    env = subprocess_env()
    sets = ["solver.end_time=null", "solver.steps=1000000", "output.history_every=1000"]
    sets += ["output.plot=none", "output.vtk_every=0"]
    args = [sys.executable, "-m", "peridynamics", "run", str(BAR), "--out", str(out)]
    args += [a for s in sets for a in ("--set", s)] + ["--checkpoint-every", "50", "--quiet"]
    proc = subprocess.Popen(
        args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env
    )
    deadline = time.time() + 120
    while not (out / CHECKPOINT_NAME).exists() and proc.poll() is None and time.time() < deadline:
        time.sleep(0.05)
    assert proc.poll() is None, "the run ended before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr and "KeyboardInterrupt" not in stderr
    assert f"--resume {out}" in stderr and "--set solver.steps=1000000" in stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    state, _, _ = read_checkpoint(out)
    assert state.step == summary["results"]["steps"] > 0
    assert not (out / (CHECKPOINT_NAME + ".tmp")).exists()


def test_ctrl_c_without_checkpoints_says_how_to_get_them(tmp_path, monkeypatch, capsys) -> None:
    real = Simulation.run

    def run_interrupted(self, out, **kw):  # noqa: ANN001, ANN202, ANN003
        sigint_at(self, 5)
        return real(self, out, **kw)

    monkeypatch.setattr(Simulation, "run", run_interrupted)
    code = main(["run", str(BAR), "--out", str(tmp_path), "--quiet", *_sets(QUICK_BAR)])
    assert code == 130
    err = capsys.readouterr().err
    assert "interrupted after step 5 of 60" in err and "--checkpoint-every N" in err
    assert not (tmp_path / CHECKPOINT_NAME).exists()


def _sets(items: list[str]) -> list[str]:
    return [a for s in items for a in ("--set", s)]


# ------------------------------------------------------------------ 10. --resume
def test_resume_of_a_finished_run_is_refused(tmp_path, capsys) -> None:
    deck = load_deck(BAR, QUICK_BAR)
    out = tmp_path / "done"
    (out).mkdir()
    (out / (CHECKPOINT_NAME + ".tmp")).write_bytes(b"half a checkpoint from a crash")
    Simulation.from_deck(deck).run(out, quiet=True, checkpoint_every=7)  # 60 % 7 != 0
    assert not (out / (CHECKPOINT_NAME + ".tmp")).exists()
    before = (out / "summary.json").read_text()
    with pytest.raises(SetupError, match="already finished"):
        Simulation.from_deck(deck).run(out, quiet=True, resume=True)
    code = main(["run", str(BAR), "--resume", str(out), "--quiet", *_sets(QUICK_BAR)])
    assert code == 2 and "already finished (60 steps" in capsys.readouterr().err
    assert (out / "summary.json").read_text() == before


def test_resume_finishes_a_run_whose_outputs_were_not_written(tmp_path) -> None:
    deck = load_deck(BAR, QUICK_BAR)
    out = tmp_path / "run"
    Simulation.from_deck(deck).run(out, quiet=True, checkpoint_every=20)
    (out / "summary.json").unlink()  # a crash while writing the outputs
    summary = Simulation.from_deck(deck).run(out, quiet=True, resume=True)
    assert summary["status"] == "completed" and summary["timing"]["steps"] == 0


# ------------------------------------------------------------- 8. size guards
def test_size_estimate_is_close_to_the_model() -> None:
    deck = load_deck(PLATE, ["discretisation.spacing=1e-3", "discretisation.horizon=3e-3"])
    est = estimate_size(deck)
    assert est is not None
    sim = Simulation.from_deck(deck)
    assert est.points == pytest.approx(sim.cloud.n_points, rel=0.01)
    assert est.bonds == pytest.approx(sim.model.bonds.n_bonds, rel=0.15)
    steps = estimate_steps(deck)
    assert steps == pytest.approx(sim.solver.total_steps(), rel=0.25)
    assert cli_mod.available_memory()[0] > 0


@pytest.mark.parametrize(
    ("sets", "key"),
    [
        (["discretisation.spacing=1.0e-7"], "discretisation.spacing"),
        (["discretisation.horizon=null", "discretisation.horizon_factor=1e4"], "horizon_factor"),
    ],
)
@pytest.mark.parametrize("bonds", [False, True])
def test_a_model_too_large_is_refused_before_it_is_built(sets, key, bonds, capsys, monkeypatch):
    def never(*a, **k):  # noqa: ANN002, ANN003, ANN202
        raise AssertionError("built the model")

    monkeypatch.setattr("peridynamics.build.cloud.build_cloud", never)
    args = ["check", str(PLATE), *_sets(sets)] + (["--bonds"] if bonds else [])
    assert main(args) == 2
    err = capsys.readouterr().err
    assert key in err and "too large" in err and "GB" in err and "--allow-large" in err
    assert main(["run", str(PLATE), *_sets(sets), "--quiet"]) == 2


def test_memory_error_anywhere_is_exit_2(tmp_path, capsys, monkeypatch) -> None:
    def oom(*a, **k):  # noqa: ANN002, ANN003, ANN202
        raise MemoryError("Unable to allocate 2.91 TiB")

    monkeypatch.setattr("peridynamics.build.cloud.build_cloud", oom)
    assert main(["check", str(BAR), "--allow-large"]) == 2
    assert "out of memory" in capsys.readouterr().err
    monkeypatch.setattr(Simulation, "from_deck", classmethod(oom))
    assert main(["run", str(BAR), "--out", str(tmp_path), "--quiet"]) == 2
    assert "out of memory" in capsys.readouterr().err


# ---------------------------------------------------------- 9. absurd values
@pytest.mark.parametrize(
    ("sets", "key"),
    [
        (["material.youngs_modulus=1e308"], "material.youngs_modulus"),
        (["material.youngs_modulus=1e200"], "material.youngs_modulus"),
        (["material.density=1e-300"], "material.density"),
    ],
)
def test_absurd_material_values_name_the_key(sets, key, capsys) -> None:
    with pytest.raises(DeckError) as info:
        load_deck(PLATE, sets)
    assert info.value.errors[0][0] == key
    assert "wave speed" in info.value.errors[0][1]
    assert main(["check", str(PLATE), "--bonds", *_sets(sets)]) == 2
    assert key in capsys.readouterr().err


def test_zero_or_non_finite_time_step_is_refused() -> None:
    for dt in (0.0, math.inf, math.nan):
        solver = SimpleNamespace(stable_time_step=dt, dt=dt, total_steps=lambda: 10)
        sim = SimpleNamespace(
            solver=solver, model=SimpleNamespace(bonds=SimpleNamespace(n_bonds=1))
        )
        problem = cli_mod.built_problem(sim, allow_large=False)
        assert problem is not None and problem.startswith("material.youngs_modulus")


def test_a_run_of_years_is_refused_unless_allowed(capsys) -> None:
    sets = ["solver.end_time=1e3"]
    assert main(["check", str(PLATE), *_sets(sets)]) == 2
    err = capsys.readouterr().err
    assert "bond updates" in err and "years" in err and "--allow-large" in err
    assert main(["check", str(PLATE), *_sets(sets), "--allow-large"]) == 0


# ------------------------------------------------------------- 11. --set
@pytest.mark.parametrize("value", ["[1,", "{a: 1", "'open", "a: b: c"])
def test_malformed_set_value_names_the_key(value, capsys) -> None:
    with pytest.raises(DeckError) as info:
        load_deck(BAR, [f"solver.steps={value}"])
    assert info.value.errors[0][0] == "solver.steps"
    assert main(["check", str(BAR), "--set", f"solver.steps={value}"]) == 2
    err = capsys.readouterr().err
    assert "solver.steps" in err and "not valid YAML" in err and "Traceback" not in err


# --------------------------------------------------------- 12. YAML numbers
@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("1e6", 1e6),
        ("1.0e6", 1e6),
        ("1.0e+6", 1e6),
        ("-2.5E-3", -2.5e-3),
        ("+1e3", 1e3),
        ("6.02e23", 6.02e23),
        (".5e3", 500.0),
        ("1.e5", 1e5),
        ("70.0e9", 70e9),
        ("1.5", 1.5),
        ("12", 12),
    ],
)
def test_scientific_notation_is_a_number(text, value) -> None:
    got = yaml_load(text)
    assert got == value and type(got) is type(value)
    assert yaml_load(f"name: {text}e") == {"name": f"{text}e"}  # not a number: a string


def test_integer_keys_take_integral_scientific_notation(tmp_path) -> None:
    data = yaml.safe_load(BAR.read_text())
    text = yaml.safe_dump(data).replace("end_time: 0.0003", "steps: 1e3")
    text = text.replace("history_every: 1", "history_every: 1.0e1")
    text = text.replace("youngs_modulus: 20000000000.0", "youngs_modulus: 2e10")
    path = tmp_path / "deck.yaml"
    path.write_text(text)
    deck = load_deck(path)
    assert deck.solver.steps == 1000 and isinstance(deck.solver.steps, int)
    assert deck.output.history_every == 10 and deck.material.youngs_modulus == 2e10
    with pytest.raises(DeckError, match="fractional part") as info:
        load_deck(path, ["solver.steps=1.5e0"])
    assert info.value.errors[0][0] == "solver.steps"
    assert load_deck(path, ["solver.steps=2.0e3"]).solver.steps == 2000


# ------------------------------------------------------------- 13. smaller
def test_examples_copy_without_a_name_lists_them(capsys) -> None:
    assert main(["examples", "copy"]) == 2
    err = capsys.readouterr().err
    assert "None" not in err and "give the NAME" in err and "bar_wave_1d" in err


def test_examples_copy_of_a_sub_deck_copies_its_folder(tmp_path, capsys) -> None:
    assert main(["examples", "copy", "plate_tension_2d/adr", str(tmp_path)]) == 0
    assert (tmp_path / "plate_tension_2d" / "adr.yaml").is_file()
    assert (tmp_path / "plate_tension_2d" / "deck.yaml").is_file()
    assert "adr.yaml" in capsys.readouterr().out


def test_dispersion_advice_shows_the_material(capsys) -> None:
    assert main(["dispersion", "--frequency", "1e5"]) == 0
    out = capsys.readouterr().out
    assert "E = 2e+10 Pa" in out and "rho = 2620 kg/m^3" in out and "--youngs-modulus" in out
    assert main(["dispersion", "--frequency", "1e5", "--density", "-1"]) == 2


def test_ensemble_of_one_says_n_a_and_prints_units(tmp_path, capsys) -> None:
    deck = {
        "name": "ens",
        "geometry": {"type": "rectangle", "size": [0.01, 0.004], "thickness": 1e-3},
        "discretisation": {"spacing": 5e-4, "horizon_factor": 3.015},
        "material": {"youngs_modulus": 70e9, "density": 2700.0},
        "damage": {"critical_stretch": 0.01, "weibull": {"shape": 10}},
        "node_sets": {"top": {"edge": {"normal": [0, 1]}}, "bottom": {"edge": {"normal": [0, -1]}}},
        "boundary_conditions": [
            {"type": "fixed", "set": "bottom"},
            {"type": "velocity", "set": "top", "components": {"y": -0.1}},
        ],
        "solver": {"steps": 3},
        "output": {
            "plot": "none",
            "stress_strain": {"set": "top", "direction": [0, -1], "area": 1e-5, "length": 0.004},
        },
    }
    path = tmp_path / "deck.yaml"
    path.write_text(yaml.safe_dump(deck))
    assert main(["ensemble", str(path), "--n", "1", "--out", str(tmp_path / "e")]) == 0
    out = capsys.readouterr().out
    assert " Pa" in out and "std n/a (n = 1)" in out
    rep = json.loads((tmp_path / "e" / "ensemble.json").read_text())
    assert rep["peak_stress_Pa"]["std"] is None and rep["peak_stress_Pa"]["cv"] is None


def test_mesh_errors_carry_meshio_reason_not_its_exit_status(tmp_path) -> None:
    (tmp_path / "bad.vtu").write_text("this is not a mesh")
    data = copy.deepcopy(yaml.safe_load(BAR.read_text()))
    data["geometry"] = {"type": "mesh", "file": "bad.vtu"}
    data["node_sets"], data["boundary_conditions"] = {}, []
    data["output"] = {}
    (tmp_path / "d.yaml").write_text(yaml.safe_dump(data))
    with pytest.raises(DeckError) as info:
        load_deck(tmp_path / "d.yaml")
    path, msg = info.value.errors[0]
    assert path == "geometry.file" and "Couldn't read file" in msg
    assert not msg.endswith(": 1")


def test_unknown_keys_point_to_the_help_command(capsys) -> None:
    with pytest.raises(DeckError) as info:
        load_deck(BAR, ["geometry.thikness=1"])
    assert "`peridynamics help deck.geometry`" in info.value.errors[0][1]
    assert main(["help", "deck", "geometry"]) == 0
    out = capsys.readouterr().out
    assert "nodes_on_boundary: true/false" in out and "thickness: number" in out
    assert main(["help", "deck", "nosuch"]) == 2


def test_progress_rate_is_an_average() -> None:
    from peridynamics.app.run_progress import _RateColumn

    col = _RateColumn(start=100)
    assert col.text(100, 1000) == "-- steps/s"
    col.t0 -= 2.0  # two seconds ago
    text = col.text(300, 1000)
    assert text.startswith("100 steps/s") and "ETA 0:00:07" in text
