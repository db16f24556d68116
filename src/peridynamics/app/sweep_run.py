"""Running the cases of a sweep as processes (``peridynamics sweep``, docs/sweep.md).

Each case runs as ``python -m peridynamics run DECK --out DIR/<case> --quiet --set ...``
with its output in ``<case>/run.log``; ``<case>/case.json`` records its fingerprint and
outcome, which decide on a rerun whether it is skipped (done), resumed from its
checkpoint or run again.
"""

from __future__ import annotations

import contextlib
import json
import os
import shlex
import signal
import subprocess
import sys
import time
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

from peridynamics.app.checks import err
from peridynamics.app.exit_codes import EXIT_INVALID
from peridynamics.app.sweep_cases import Case
from peridynamics.app.sweep_report import flatten_scalars, write_json

#: lines of a case's run.log kept in sweep.json when it did not complete
TAIL_LINES = 20
#: environment variables of an MPI launch that a case's process must not inherit
_MPI_ENV = ("PMI_", "PMIX_", "OMPI_COMM_WORLD_", "OMPI_UNIVERSE_", "HYDI_", "MPI_LOCAL")
_THREAD_VARS = ("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
_POLL_S = 0.05


# ------------------------------------------------------------------- one case's run
@dataclass
class Plan:
    """What every case's process needs."""

    deck: Path
    sets: list[str]
    out: Path
    env: dict[str, str]
    checkpoint_every: int | None
    allow_large: bool
    quiet: bool
    prefix: str = ""
    rank: int = 0
    preexec: Callable[[], None] | None = None


@dataclass
class Running:
    """A case's process."""

    case: Case
    proc: subprocess.Popen[bytes]
    log: IO[bytes]
    start: float
    resumed: bool


#: exit codes of a case stopped by Ctrl-C (130) or a batch system's signal (SIGHUP 129,
#: SIGUSR1 138, SIGTERM 143): 128 + the signal's number
INTERRUPTED_CODES = frozenset({129, 130, 138, 143})


def _read_json(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def child_env(threads: int) -> dict[str, str]:
    """The environment of a case's process: thread counts (unless the user set them),
    the package on PYTHONPATH when it runs from a source tree, no MPI launch variables."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(_MPI_ENV)}
    for var in _THREAD_VARS:
        env.setdefault(var, str(threads))
    import peridynamics

    root = str(Path(peridynamics.__file__).resolve().parents[1])
    if Path(root).name not in ("site-packages", "dist-packages"):
        path = env.get("PYTHONPATH", "")
        if root not in path.split(os.pathsep):
            env["PYTHONPATH"] = os.pathsep.join(filter(None, [root, path]))
    return env


def death_signal() -> Callable[[], None] | None:
    """Linux: a function for ``preexec_fn`` that makes a case get SIGINT (it stops
    cleanly, writing its outputs) if the sweep process dies; resolved here, in the
    parent, so that the forked child only calls it."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        import ctypes

        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    sig = int(signal.SIGINT)

    def preexec() -> None:  # pragma: no cover - runs in the child before exec
        prctl(1, sig)  # PR_SET_PDEATHSIG

    return preexec


def _done_before(case: Case, plan: Plan) -> dict[str, Any] | None:
    """The record of a case completed by an earlier sweep with the same fingerprint."""
    folder = plan.out / case.folder
    info = _read_json(folder / "case.json")
    summary = _read_json(folder / "summary.json")
    if info.get("fingerprint") != case.fingerprint or summary.get("status") != "completed":
        return None
    return record(case, "skipped-done", 0, info.get("wall_s"), info.get("resumed", False),
                   summary)  # fmt: skip


def _launch(case: Case, plan: Plan, fresh: bool = False) -> Running:
    """Start a case's process: ``--resume`` from its checkpoint when an earlier run of
    the same case left one (and ``fresh`` is false), else a new run."""
    folder = plan.out / case.folder
    folder.mkdir(parents=True, exist_ok=True)
    info = _read_json(folder / "case.json")
    resume = (
        not fresh
        and (folder / "checkpoint.npz").is_file()
        and info.get("fingerprint") == case.fingerprint
    )
    # first the old summary (a stale "completed" must never sit beside the new fingerprint)
    (folder / "summary.json").unlink(missing_ok=True)
    if not resume:  # a new run: old checkpoints are stale
        for name in ("checkpoint.npz", "checkpoint.prev.npz"):
            (folder / name).unlink(missing_ok=True)
    write_json(folder / "case.json", {**_case_info(case, plan), "status": "running"})
    cmd = [sys.executable, "-m", "peridynamics", "run", str(plan.deck)]
    cmd += ["--resume" if resume else "--out", str(folder), "--quiet"]
    for arg in [*plan.sets, *case.set_args]:
        cmd += ["--set", arg]
    if plan.checkpoint_every is not None:
        cmd += ["--checkpoint-every", str(plan.checkpoint_every)]
    if plan.allow_large:
        cmd.append("--allow-large")
    log = (folder / "run.log").open("ab" if resume or fresh else "wb")
    log.write(("$ " + shlex.join(cmd) + "\n").encode())
    log.flush()
    proc = subprocess.Popen(  # noqa: S603 - our own interpreter and arguments
        cmd,
        stdout=log,
        stderr=subprocess.STDOUT,
        stdin=subprocess.DEVNULL,
        env=plan.env,
        start_new_session=True,  # Ctrl-C reaches the sweep, which stops each case once
        preexec_fn=plan.preexec,  # noqa: PLW1509 - only a resolved prctl call
    )
    return Running(case, proc, log, time.perf_counter(), resume)


def _case_info(case: Case, plan: Plan) -> dict[str, Any]:
    return {
        "case": case.index,
        "folder": case.folder,
        "deck": str(plan.deck),
        "set": [*plan.sets, *case.set_args],
        "values": case.values,
        "fingerprint": case.fingerprint,
    }


def record(
    case: Case,
    status: str,
    code: int | None,
    wall: float | None,
    resumed: bool,
    summary: dict[str, Any],
    tail: list[str] | None = None,
) -> dict[str, Any]:
    """A case's record (one row of sweep.csv, one entry of sweep.json's ``cases``).

    Parameters
    ----------
    case
        The case.
    status
        One of :data:`peridynamics.app.sweep_report.STATUSES`.
    code
        Exit code of its process (negative: killed by that signal; ``None``: not run).
    wall
        Wall time of its process in s (start-up and set-up included).
    resumed
        Whether it continued from a checkpoint.
    summary
        Its summary.json (empty when there is none): ``results`` and ``timing`` are
        flattened into numeric scalars.
    tail
        The last lines of its run.log (kept for a case that did not complete).
    """
    rec: dict[str, Any] = {
        "case": case.index,
        "folder": case.folder,
        "status": status,
        "exit_code": code,
        "wall_s": wall,
        "resumed": resumed,
        "values": case.values,
        "set": case.set_args,
        "fingerprint": case.fingerprint,
        "results": flatten_scalars(summary.get("results") or {}),
        "timing": flatten_scalars(summary.get("timing") or {}, "timing."),
    }
    if tail is not None:
        rec["stderr_tail"] = tail
    return rec


def _finish(run: Running, code: int, plan: Plan, stopped: bool) -> dict[str, Any]:
    """The record of a finished process; updates its case.json."""
    wall = time.perf_counter() - run.start
    run.log.close()
    folder = plan.out / run.case.folder
    summary = _read_json(folder / "summary.json")
    if code == 0 and summary.get("status") == "completed":
        status = "completed"
    elif code == 3:
        status = "unstable"
    elif (
        code in INTERRUPTED_CODES
        or summary.get("status") == "interrupted"
        or (stopped and code != 0)
    ):
        status = "interrupted"
    else:
        status = "failed"
    tail = None
    if status != "completed":
        lines = (folder / "run.log").read_bytes().decode(errors="replace").splitlines()
        tail = lines[-TAIL_LINES:]
    rec = record(run.case, status, code, wall, run.resumed, summary, tail)
    info = {**_case_info(run.case, plan), "status": status, "exit_code": code}
    write_json(folder / "case.json", {**info, "wall_s": wall, "resumed": run.resumed})
    return rec


@contextlib.contextmanager
def sigterm_as_interrupt() -> Iterator[None]:
    """SIGTERM (a batch system's time limit) stops the sweep as Ctrl-C does."""

    def handler(signum: int, frame: Any) -> None:
        raise KeyboardInterrupt

    try:
        old = signal.signal(signal.SIGTERM, handler)
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)


def _stop(running: dict[int, Running], plan: Plan) -> dict[int, int]:
    """Ctrl-C: SIGINT to each case once (it stops after its step and writes its outputs
    and checkpoint), wait; a second Ctrl-C kills them. Returns index -> exit code."""
    if running and not plan.quiet:
        err(f"{plan.prefix}interrupted: stopping {len(running)} running case(s) (they write "
             "their outputs; Ctrl-C again to kill them)")  # fmt: skip
    for r in running.values():
        with contextlib.suppress(ProcessLookupError):
            r.proc.send_signal(signal.SIGINT)
    codes: dict[int, int] = {}
    try:
        for idx, r in running.items():
            codes[idx] = r.proc.wait()
    except KeyboardInterrupt:
        for r in running.values():
            with contextlib.suppress(ProcessLookupError):
                r.proc.kill()
        codes = {idx: r.proc.wait() for idx, r in running.items()}
    return codes


def run_cases(
    cases: list[Case], plan: Plan, jobs: int, on_done: Callable[[dict[str, Any]], None]
) -> tuple[list[dict[str, Any]], bool]:
    """Run cases, ``jobs`` at a time, largest first; skip those done before.

    Returns the records (in case order) and whether the sweep was interrupted (Ctrl-C or
    SIGTERM: running cases are stopped cleanly, the others are ``not-started``).
    """
    pending = deque(sorted(cases, key=lambda c: (-c.cost, c.index)))
    running: dict[int, Running] = {}
    records: dict[int, dict[str, Any]] = {}
    interrupted = False

    def done(rec: dict[str, Any]) -> None:
        rec["rank"] = plan.rank
        records[rec["case"]] = rec
        on_done(rec)

    with sigterm_as_interrupt():
        try:
            while pending or running:
                while pending and len(running) < jobs:
                    case = pending.popleft()
                    rec = _done_before(case, plan)
                    if rec is not None:
                        done(rec)
                    else:
                        running[case.index] = _launch(case, plan)
                for idx, run in list(running.items()):
                    code = run.proc.poll()
                    if code is None:
                        continue
                    del running[idx]
                    if run.resumed and code == EXIT_INVALID:  # a checkpoint it cannot use
                        with run.log:
                            run.log.write(b"# the resume failed: starting the case afresh\n")
                        running[idx] = _launch(run.case, plan, fresh=True)
                        continue
                    done(_finish(run, code, plan, stopped=False))
                time.sleep(_POLL_S)
        except KeyboardInterrupt:
            interrupted = True
            for idx, code in _stop(running, plan).items():
                done(_finish(running[idx], code, plan, stopped=True))
            for case in pending:
                done(record(case, "not-started", None, None, False, {}))
    return [records[k] for k in sorted(records)], interrupted
