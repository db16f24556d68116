"""Nothing lost: a batch system's stop signals end a run as Ctrl-C does, a run owns its
output folder, and Ctrl-C or SIGTERM during start-up ends without a traceback.

These tests need real signals and a second process, so they start ``python -m
peridynamics`` as a subprocess (the resumed and the reference runs are in-process)."""

from __future__ import annotations

import json
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from peridynamics.io.run_lock import LOCK_NAME
from tests.helpers import EXAMPLES, cli, mpiexec, same_final_fields, subprocess_env

BAR = EXAMPLES / "bar_wave_1d" / "deck.yaml"
#: 3000 steps of the 1-D bar: a few seconds, long enough to be signalled mid-run
SETS = ["solver.end_time=null", "solver.steps=3000", "output.history_every=100"]
SETS += ["output.plot=none", "output.vtk_every=0"]
SET_ARGS = [a for s in SETS for a in ("--set", s)]
FIELDS = ("u", "v", "damage", "intact", "t", "step")


#: the decomposed runs' deck (a 1-D bar is not decomposed): 1000 points, 3000 steps
PLATE = EXAMPLES / "plate_tension_2d" / "deck.yaml"
PLATE_ARGS = [*SET_ARGS, "--set", "discretisation.spacing=1.0e-3", "--set", "output.probes=[]"]


def _start(out: Path, *extra: str, ranks: int = 1) -> subprocess.Popen:
    launch = [str(mpiexec()[0]), "-n", str(ranks)] if ranks > 1 else []
    deck, sets = (PLATE, PLATE_ARGS) if ranks > 1 else (BAR, SET_ARGS)
    args = [*launch, sys.executable, "-m", "peridynamics", "run", str(deck), "--out", str(out)]
    return subprocess.Popen(
        [*args, *sets, "--quiet", *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=subprocess_env(),
    )


def _wait_for(path: Path, proc: subprocess.Popen, limit: float = 120.0) -> None:
    deadline = time.time() + limit
    while not path.exists() and proc.poll() is None and time.time() < deadline:
        time.sleep(0.02)
    assert proc.poll() is None, "the run ended before it could be signalled"


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The uninterrupted run."""
    out = tmp_path_factory.mktemp("reference") / "run"
    cli("run", BAR, "--out", out, "--quiet", *SET_ARGS, check=True)
    return out


def _same_fields(a: Path, b: Path) -> None:
    same_final_fields(a, b, FIELDS)


def _signal_then_resume(out: Path, sig: signal.Signals, ranks: int = 1) -> None:
    proc = _start(out, "--checkpoint-every", "50", ranks=ranks)
    _wait_for(out / "checkpoint.npz" if ranks == 1 else out / "checkpoint_mpi.json", proc)
    proc.send_signal(sig)
    _, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, stderr
    assert "Traceback" not in stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted" and summary["stop_signal"] == sig.name
    assert 0 < summary["results"]["steps"] < 3000
    assert f"--resume {out}" in stderr
    deck, sets = (PLATE, PLATE_ARGS) if ranks > 1 else (BAR, SET_ARGS)
    resumed = cli("run", deck, "--resume", out, "--quiet", *sets, ranks=ranks)
    assert resumed.returncode == 0, resumed.stderr
    assert json.loads((out / "summary.json").read_text())["status"] == "completed"


def test_sigterm_mid_run_then_resume_equals_an_uninterrupted_run(
    tmp_path: Path, reference: Path
) -> None:
    out = tmp_path / "run"
    _signal_then_resume(out, signal.SIGTERM)
    _same_fields(out, reference)


@pytest.mark.long
@pytest.mark.parametrize("sig", [signal.SIGHUP, signal.SIGUSR1])
def test_sighup_and_sigusr1_stop_as_sigterm(
    tmp_path: Path, reference: Path, sig: signal.Signals
) -> None:
    out = tmp_path / "run"
    _signal_then_resume(out, sig)
    _same_fields(out, reference)


@pytest.mark.mpi
def test_sigterm_on_two_ranks_then_resume_equals_an_uninterrupted_run(tmp_path: Path) -> None:
    if mpiexec()[0] is None:
        pytest.skip(mpiexec()[1])
    whole = tmp_path / "whole"
    cli("run", PLATE, "--out", whole, "--quiet", *PLATE_ARGS, ranks=2, check=True)
    out = tmp_path / "run"
    _signal_then_resume(out, signal.SIGTERM, ranks=2)
    _same_fields(out, whole)


def test_a_second_run_on_a_held_folder_is_refused_and_the_first_is_intact(
    tmp_path: Path, reference: Path
) -> None:
    out = tmp_path / "run"
    first = _start(out)
    _wait_for(out / LOCK_NAME, first)
    second = cli("run", BAR, "--out", out, "--quiet", *SET_ARGS)
    assert second.returncode == 2
    assert "is in use" in second.stderr and f"process {first.pid}" in second.stderr
    _, stderr = first.communicate(timeout=120)
    assert first.returncode == 0, stderr
    assert json.loads((out / "summary.json").read_text())["status"] == "completed"
    _same_fields(out, reference)
    assert not (out / LOCK_NAME).exists()


def test_a_stale_lock_is_taken_over_and_another_hosts_lock_is_respected(tmp_path: Path) -> None:
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    out = tmp_path / "run"
    out.mkdir()
    lock = {"host": socket.gethostname(), "pid": dead.pid, "started": 0, "command": "x"}
    (out / LOCK_NAME).write_text(json.dumps(lock))
    quick = ["--set", "solver.steps=20"]
    proc = cli("run", BAR, "--out", out, "--quiet", *SET_ARGS, *quick)
    assert proc.returncode == 0, proc.stderr
    assert "taking over the folder" in proc.stderr
    assert not (out / LOCK_NAME).exists()
    lock["host"] = "another-host.example"
    (out / LOCK_NAME).write_text(json.dumps(lock))
    proc = cli("run", BAR, "--out", out, "--quiet", *SET_ARGS, *quick)
    assert proc.returncode == 2 and "another host" in proc.stderr
    assert (out / LOCK_NAME).exists()


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_during_start_up_ends_without_a_traceback(
    tmp_path: Path, sig: signal.Signals
) -> None:
    proc = _start(tmp_path / "run")
    time.sleep(0.4)  # importing NumPy, Numba and the models
    proc.send_signal(sig)
    _, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, stderr
    assert "Traceback" not in stderr and "interrupted" in stderr


@pytest.mark.long
def test_ctrl_c_at_any_moment_of_start_up_exits_130(tmp_path: Path) -> None:
    """Ctrl-C swept over the start-up (imports, compilation, set-up): the exit code is 130
    at every moment, also when the interrupt lands inside an import's C code (before,
    the interpreter then killed itself with SIGINT: return code -2 at about 0.13 s). The
    sweep starts at 0.1 s: before the package's first line runs (the interpreter's own
    start-up, about 50 ms here) Python's default handler is all there is."""
    for k in range(14):
        proc = _start(tmp_path / f"run{k}")
        time.sleep(0.1 + 0.04 * k)
        proc.send_signal(signal.SIGINT)
        _, stderr = proc.communicate(timeout=120)
        assert proc.returncode == 130, (k, stderr[-500:])
        assert "Traceback" not in stderr


def test_an_interrupt_wrapped_by_a_c_extension_is_still_an_interrupt() -> None:
    """pydantic-core wraps a KeyboardInterrupt raised while it builds a validator into a
    SchemaError naming it (seen in CI: Ctrl-C 0.22 s into start-up exited 1): the
    start-up handler finds the signal behind such an exception, and only there."""
    from peridynamics.cli import _wrapped_signal

    wrapped = ValueError('Error building "tagged-union" validator:\n  KeyboardInterrupt: ')
    assert _wrapped_signal(wrapped) == signal.SIGINT
    assert _wrapped_signal(ValueError("StopSignal: SIGTERM")) == signal.SIGTERM
    assert _wrapped_signal(ValueError("an unrelated error")) is None
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise RuntimeError("chained") from exc
    except RuntimeError as chained:
        assert _wrapped_signal(chained) == signal.SIGINT


def test_the_command_line_starts_without_numba() -> None:
    """Parsing the command line imports the deck but no model family: Numba (and its
    0.5 s of imports, during which a signal once went astray in CI) loads only when a
    command builds a model. A deck module that imports the family registry at its top
    (``deck/thermal_coupling.py`` did) breaks this."""
    code = (
        "import sys\n"
        "from peridynamics.cli.entry import run_command\n"
        "heavy = sorted(m for m in sys.modules if m == 'numba' or "
        "m.startswith('peridynamics.families'))\n"
        "print(','.join(heavy))\n"
    )
    got = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=subprocess_env(),
        timeout=120,
    )  # fmt: skip
    assert got.returncode == 0, got.stderr
    assert got.stdout.strip() == "", got.stdout


def test_a_start_up_signal_that_was_wrapped_still_ends_with_its_exit_code(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """SciPy's pybind11 modules turn a KeyboardInterrupt during their initialisation
    into ``ImportError: initialization failed`` (seen here 1.0-1.3 s into start-up: exit
    1 with a traceback): the signal recorded by the start-up handler decides the exit."""
    import peridynamics.cli.entry as entry
    from peridynamics.app.run_progress import note_startup_stop
    from peridynamics.cli import main

    def wrapped(argv: list[str] | None) -> int:
        note_startup_stop(signal.SIGTERM)
        raise ImportError("initialization failed")

    monkeypatch.setattr(entry, "run_command", wrapped)
    assert main(["check", str(BAR)]) == 128 + signal.SIGTERM
    monkeypatch.setattr(entry, "run_command", lambda argv: int(1 / 0))
    with pytest.raises(ZeroDivisionError):  # no signal: an error stays an error
        main(["check", str(BAR)])


def test_a_start_up_signal_that_was_swallowed_stops_the_run_before_its_first_step(
    tmp_path: Path,
) -> None:
    """A signal whose KeyboardInterrupt some C code cleared (seen in CI: Ctrl-C 0.42 s
    into start-up, then the whole run and exit 0) still stops the run: the run loop's
    stop request starts as requested, so the run ends interrupted at step 0."""
    from peridynamics.api.deck import Deck
    from peridynamics.api.simulation import Simulation
    from peridynamics.app.run import RunInterrupted
    from peridynamics.app.run_progress import note_startup_stop, startup_stop

    sim = Simulation(Deck.from_file(BAR, SETS), out=tmp_path / "run")
    note_startup_stop(signal.SIGINT)
    with pytest.raises(RunInterrupted) as stopped:
        sim.run(quiet=True)
    assert stopped.value.step == 0
    assert startup_stop() is None  # acted on once
