"""Resuming a run from its checkpoint (``--resume``): the state, the records and the
checks that the checkpoint belongs to this deck and that the run has not finished."""

from __future__ import annotations

import json
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

from peridynamics.build.errors import SetupError
from peridynamics.io.checkpoint import CheckpointWarning, NoUsableCheckpoint, read_usable
from peridynamics.solvers.base import Solver
from peridynamics.state import State

#: how a refusal for want of a usable checkpoint ends
_START_AGAIN = ": start a new run with --out"


def read_resume(session: Any, out: Path) -> tuple[State, dict[str, Any], dict[str, Any], str]:
    """(state, records, meta, fingerprint) of the checkpoint to resume (``session``: a
    decomposed run's, whose every rank reads its own part).

    The newest checkpoint is used when it reads back intact, else the previous one,
    with a warning ``checkpoint ... is damaged (...); resuming from the previous one
    ...``; under MPI every rank takes the same generation. Raises SetupError
    (``--resume``) naming each file and its reason when none is usable, and
    FileNotFoundError when there is no checkpoint (serial runs)."""
    if session is None:
        try:
            ck, problem = read_usable(out)
        except NoUsableCheckpoint as exc:
            raise SetupError("--resume", f"{exc}{_START_AGAIN}") from None
        except FileNotFoundError:
            _refuse_decomposed(out)
            raise
        note = None if problem is None else f"{problem}; resuming from the previous one {ck.path}"
        _warn(note)
        return ck.state, ck.records, ck.meta, ck.fingerprint
    from peridynamics.io.rank_checkpoints import ResumeError, read_rank_checkpoint

    try:
        state, records, meta, fp, note = read_rank_checkpoint(session, out)
    except NoUsableCheckpoint as exc:
        raise SetupError("--resume", f"{exc}{_START_AGAIN}") from None
    except ResumeError as exc:
        raise SetupError("--resume", str(exc)) from None
    if session.root:  # rank 0 speaks for every rank
        _warn(note)
    return state, records, meta, fp


def _refuse_decomposed(out: Path) -> None:
    """SetupError (``--resume``) when ``out`` holds the checkpoint of a decomposed run
    (its marker) but no serial one: a one-process run cannot read per-rank files."""
    from peridynamics.io.rank_checkpoints import MARKER

    if (out / MARKER).is_file():
        raise SetupError(
            "--resume",
            f"the checkpoint in {str(out)!r} was written by a decomposed run ({MARKER}, "
            "one file per rank); resume it with mpiexec -n 2 or more (any rank count: "
            "the checkpoint is repartitioned), a one-process run reads checkpoint.npz",
        )


def _completed(out: Path) -> bool:
    """Whether ``out/summary.json`` says the run completed (False when it cannot be
    read)."""
    try:
        summary = json.loads((out / "summary.json").read_text())
    except (OSError, ValueError):
        return False
    return isinstance(summary, dict) and summary.get("status") == "completed"


def _warn(note: str | None) -> None:
    """Warn that the newest checkpoint was passed over (``warning: ...`` on the command
    line), when it was."""
    if note is not None:
        warnings.warn(note, CheckpointWarning, stacklevel=3)


def resume_point(
    solver: Solver,
    session: Any,
    fingerprint: Callable[[], str],
    out: Path,
    checkpoint_every: int | None,
    say: bool,
) -> tuple[State, dict[str, Any], bool, int | None]:
    """The state and records to resume from ``out``, whether the run had finished, and
    the checkpoint interval (the original run's when ``checkpoint_every`` is None); the
    solver is set to continue from the state. Raises SetupError (``--resume``) for a
    checkpoint of another deck or of a run whose outputs are written (its checkpoint is
    marked finished, or ``summary.json`` says completed: the final checkpoint may have
    been damaged and an earlier one chosen). ``say``: print where the run resumes."""
    state, records, meta, fp = read_resume(session, out)
    if fp != fingerprint():
        raise SetupError(
            "--resume",
            f"the checkpoint in {str(out)!r} was written by "
            "a different deck; resume with the same deck and overrides",
        )
    finished = meta.get("finished", False) or solver.done(state)
    if finished and (out / "summary.json").exists():
        raise SetupError(
            "--resume",
            f"the run in {str(out)!r} has already finished "
            f"({state.step} steps, t = {state.t:.6g} s); nothing to resume "
            "(start a new run with --out)",
        )
    if not finished and _completed(out):  # its final checkpoint was damaged or not written
        raise SetupError(
            "--resume",
            f"the run in {str(out)!r} has already finished (summary.json says completed); "
            "nothing to resume (start a new run with --out)",
        )
    try:
        solver.resume(state)
    except ValueError as exc:
        raise SetupError("--resume", str(exc)) from None
    if checkpoint_every is None:  # keep the interval of the original run
        checkpoint_every = int(records.get("checkpoint_every", 0))
    if say:
        print(f"resuming from step {state.step} (t = {state.t:.6g} s) in {out}")
    return state, records, finished, checkpoint_every
