"""Resuming a run from its checkpoint (``--resume``): the state, the records and the
checks that the checkpoint belongs to this deck and that the run has not finished."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from peridynamics.build.errors import SetupError
from peridynamics.io.checkpoint import read_checkpoint, read_checkpoint_meta
from peridynamics.solvers.base import Solver
from peridynamics.state import State


def read_resume(session: Any, out: Path) -> tuple[State, dict[str, Any], dict[str, Any], str]:
    """(state, records, meta, fingerprint) of the checkpoint to resume (``session``: a
    decomposed run's, whose every rank reads its own part)."""
    if session is None:
        state, records, fp = read_checkpoint(out)
        return state, records, read_checkpoint_meta(out), fp
    from peridynamics.io.rank_checkpoints import ResumeError, read_rank_checkpoint

    try:
        return read_rank_checkpoint(session, out)
    except ResumeError as exc:
        raise SetupError("--resume", str(exc)) from None


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
    checkpoint of another deck or of a run whose outputs are written. ``say``: print
    where the run resumes."""
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
    try:
        solver.resume(state)
    except ValueError as exc:
        raise SetupError("--resume", str(exc)) from None
    if checkpoint_every is None:  # keep the interval of the original run
        checkpoint_every = int(records.get("checkpoint_every", 0))
    if say:
        print(f"resuming from step {state.step} (t = {state.t:.6g} s) in {out}")
    return state, records, finished, checkpoint_every
