"""Checkpoints of a decomposed run: one file per rank, one marker that names the step.

Each rank writes its own State (owned and ghost rows, its bond flags) to
``ranks/rankNNNN/checkpoint_<step>.npz`` (atomically and with a checksum, as a serial
checkpoint); after a barrier rank 0 writes ``checkpoint_mpi.json`` (``step``, ``t``,
``ranks``, ``finished`` and ``previous``: the step before, ``{"step": ..., "t": ...}``
or ``null``) atomically, and after a second barrier every rank deletes its files of
other steps. The previous step is the one the old marker named when every rank's file
of it reads back intact (else the old marker's own previous one, likewise checked).
Whenever one rank is killed, the marker names a step whose files every rank has
written, and its previous step's files are still there, so ``mpiexec -n N peridynamics
run deck --resume`` continues from a consistent state; when a file of the newest step
is damaged every rank takes the previous step (they agree through an allgather).

Resuming on another number of ranks is refused with a clear error: the partition, the
ghosts and the per-rank bond lists depend on the rank count (a repartition from the
per-rank files is not built; a serial checkpoint is not written by MPI runs either).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from peridynamics.io.atomic import atomic_path
from peridynamics.io.checkpoint import (
    Checkpoint,
    DamagedCheckpoint,
    NoUsableCheckpoint,
    load_checkpoint,
    write_checkpoint,
)
from peridynamics.parallel.session import Session, rank_dir
from peridynamics.state import State

MARKER = "checkpoint_mpi.json"
#: the marker's keys that are not the run's meta
_OWN = ("step", "t", "ranks", "previous")


class ResumeError(ValueError):
    """The checkpoint of a decomposed run cannot be resumed (the run loop reports it as
    a set-up error of ``--resume``)."""


def _name(step: int) -> str:
    return f"checkpoint_{step:09d}.npz"


def _read_marker(out: Path) -> dict[str, Any] | str:
    """Rank 0: the marker's mapping, or why there is none to use."""
    marker = out / MARKER
    try:
        info = json.loads(marker.read_text())
        if not isinstance(info, dict):
            raise ValueError("not a mapping")
        int(info["step"]), int(info["ranks"])
        previous = info.get("previous")
        if previous is not None:
            int(previous["step"])
    except FileNotFoundError:
        return f"no checkpoint of an MPI run in {str(out)!r} (expected {MARKER})"
    except (OSError, ValueError, KeyError, TypeError) as exc:
        return (
            f"the checkpoint marker {marker} is damaged ({type(exc).__name__}: {exc}); "
            f"no usable checkpoint in {str(out)!r}: start a new run with --out"
        )
    return info


def _generations(info: dict[str, Any]) -> list[dict[str, Any]]:
    """The steps a marker names, newest first: ``{"step", "t"}`` each."""
    newest = {"step": int(info["step"]), "t": info.get("t")}
    previous = info.get("previous")
    return [newest] + ([previous] if previous else [])


def _load_everywhere(
    session: Session, out: Path, step: int, fingerprint: str | None = None
) -> tuple[Checkpoint | None, list[tuple[int, str]]]:
    """Every rank: its checkpoint of ``step`` (``None`` where unusable) and every rank's
    (rank, problem) in rank order, the same list on every rank. ``fingerprint``: also
    a problem when a file was written for another deck."""
    comm = session.comm
    path = rank_dir(out, comm.rank) / _name(step)
    ck, problem = None, None
    try:
        ck = load_checkpoint(path)
    except FileNotFoundError:
        problem = f"checkpoint {path} is missing"
    except DamagedCheckpoint as exc:
        problem = str(exc)
    if ck is not None and fingerprint is not None and ck.fingerprint != fingerprint:
        problem = f"checkpoint {path} was written by another deck"
    every = comm.gather_objects(problem)
    return ck, [(rank, p) for rank, p in enumerate(every) if p]


def _previous(session: Session, out: Path, old: Any, step: int, fp: str) -> dict | None:
    """Every rank: the step of the old marker ``old`` to keep beside ``step`` (the first
    of its steps before ``step`` whose files every rank holds intact), or None."""
    if not isinstance(old, dict) or int(old["ranks"]) != session.comm.size:
        return None
    for gen in _generations(old):
        if int(gen["step"]) < step and not _load_everywhere(session, out, int(gen["step"]), fp)[1]:
            return {"step": int(gen["step"]), "t": gen.get("t")}
    return None


def write_rank_checkpoints(
    session: Session,
    out: str,
    records: dict[str, Any],
    fingerprint: str,
    meta: dict[str, Any] | None,
) -> Path:
    """Every rank: write its checkpoint of ``session.state``; the marker path."""
    comm, s = session.comm, session.state
    assert s is not None
    base = Path(out)
    folder = rank_dir(base, comm.rank)
    folder.mkdir(parents=True, exist_ok=True)
    name = _name(s.step)
    old = comm.bcast(_read_marker(base) if session.root else None)
    previous = _previous(session, base, old, s.step, fingerprint)
    write_checkpoint(folder, s, records if session.root else {}, fingerprint, meta, name=name)
    comm.barrier()  # every rank's file of this step exists
    marker = base / MARKER
    if session.root:
        info = {"step": s.step, "t": s.t, "ranks": comm.size, **(meta or {})}
        info["previous"] = previous
        with atomic_path(marker) as tmp:
            tmp.write_text(json.dumps(info))
    comm.barrier()  # the marker names this step and the previous one: others can go
    keep = {name} | ({_name(previous["step"])} if previous else set())
    for stale in folder.glob("checkpoint_*.npz"):
        if stale.name not in keep:
            stale.unlink(missing_ok=True)
    return marker


def read_rank_checkpoint(
    session: Session, out: Path
) -> tuple[State, dict[str, Any], dict[str, Any], str, str | None]:
    """Every rank: (state, records, meta, fingerprint, note) of the newest step the
    marker names whose files every rank reads back intact; ``note`` (the same on every
    rank) says why the newest was passed over (``None`` when it was not).

    Raises ResumeError (on every rank) when there is no usable marker or it was written
    by another number of ranks, and NoUsableCheckpoint (naming each rank's file and its
    reason) when no step it names is intact on every rank."""
    comm, out = session.comm, Path(out)
    info: Any = comm.bcast(_read_marker(out) if session.root else None)
    if isinstance(info, str):
        raise ResumeError(info)
    if int(info["ranks"]) != comm.size:
        raise ResumeError(
            f"the checkpoint in {str(out)!r} was written by {info['ranks']} MPI ranks; "
            f"resume with mpiexec -n {info['ranks']} (the partition depends on the rank "
            "count; resuming on another count is not supported)",
        )
    problems: list[tuple[int, str]] = []
    for gen in _generations(info):
        step = int(gen["step"])
        ck, bad = _load_everywhere(session, out, step)
        if bad:
            problems += bad
            continue
        assert ck is not None
        note = None
        if problems:
            rank, why = problems[0]
            note = f"{why}; resuming from the previous one {rank_dir(out, rank) / _name(step)}"
        records = comm.bcast(ck.records if session.root else None)
        return ck.state, records, ck.meta, ck.fingerprint, note
    text = "; ".join(p for _, p in problems)
    raise NoUsableCheckpoint(f"{text}; no usable checkpoint in {str(out)!r}")
