"""Checkpoints of a decomposed run: one file per rank, one marker that names the step.

Each rank writes its own State (owned and ghost rows, its bond flags) to
``ranks/rankNNNN/checkpoint_<step>.npz`` (atomically, as a serial checkpoint); after a
barrier rank 0 writes ``checkpoint_mpi.json`` (``step``, ``ranks``, ``finished``)
atomically, and after a second barrier every rank deletes its older files. Whenever
one rank is killed, the marker names a step whose files every rank has written, so
``mpiexec -n N peridynamics run deck --resume`` continues from a consistent state.

Resuming on another number of ranks is refused with a clear error: the partition, the
ghosts and the per-rank bond lists depend on the rank count (a repartition from the
per-rank files is not built; a serial checkpoint is not written by MPI runs either).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from peridynamics.io.checkpoint import read_checkpoint, write_checkpoint
from peridynamics.parallel.session import Session, rank_dir
from peridynamics.state import State

MARKER = "checkpoint_mpi.json"


class ResumeError(ValueError):
    """The checkpoint of a decomposed run cannot be resumed (the run loop reports it as
    a set-up error of ``--resume``)."""


def _name(step: int) -> str:
    return f"checkpoint_{step:09d}.npz"


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
    folder = rank_dir(Path(out), comm.rank)
    folder.mkdir(parents=True, exist_ok=True)
    name = _name(s.step)
    write_checkpoint(folder, s, records if session.root else {}, fingerprint, meta, name=name)
    comm.barrier()  # every rank's file of this step exists
    marker = Path(out) / MARKER
    if session.root:
        tmp = marker.with_suffix(".json.tmp")
        info = {"step": s.step, "t": s.t, "ranks": comm.size, **(meta or {})}
        tmp.write_text(json.dumps(info))
        os.replace(tmp, marker)
    comm.barrier()  # the marker names this step: older files can go
    for old in folder.glob("checkpoint_*.npz"):
        if old.name != name:
            old.unlink(missing_ok=True)
    return marker


def read_rank_checkpoint(
    session: Session, out: Path
) -> tuple[State, dict[str, Any], dict[str, Any], str]:
    """Every rank: (state, records, meta, fingerprint) of the step the marker names.
    Raises ResumeError (on every rank) when there is no marker, when it was written by
    another number of ranks, or when a rank's file is missing."""
    comm = session.comm
    info: Any = None
    if session.root:
        marker = Path(out) / MARKER
        try:
            info = json.loads(marker.read_text())
        except FileNotFoundError:
            info = f"no checkpoint of an MPI run in {str(out)!r} (expected {MARKER})"
    info = comm.bcast(info)
    if isinstance(info, str):
        raise ResumeError(info)
    if int(info["ranks"]) != comm.size:
        raise ResumeError(
            f"the checkpoint in {str(out)!r} was written by {info['ranks']} MPI ranks; "
            f"resume with mpiexec -n {info['ranks']} (the partition depends on the rank "
            "count; resuming on another count is not supported)",
        )
    problem = None
    try:
        state, records, fp = read_checkpoint(rank_dir(out, comm.rank), _name(int(info["step"])))
    except (FileNotFoundError, OSError, ValueError, KeyError) as exc:
        problem = f"rank {comm.rank}: {exc}"
    problems = [p for p in comm.gather_objects(problem) if p]
    if problems:
        raise ResumeError("; ".join(problems))
    records = comm.bcast(records if session.root else None)
    meta = {k: v for k, v in info.items() if k not in ("step", "t", "ranks")}
    return state, records, meta, fp
