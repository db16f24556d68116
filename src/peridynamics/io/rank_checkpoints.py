"""Checkpoints of a decomposed run: one file per rank, one marker that names the step.

Each rank writes its own State (owned and ghost rows, its bond flags) to
``ranks/rankNNNN/checkpoint_<step>.npz`` (atomically and with a checksum, as a serial
checkpoint) with its partition (``extra_*`` arrays: the global ids of its local rows,
its owned count, the CSR offsets and far ends of its owned bonds, the rank and rank
count; :func:`peridynamics.io.repartition.partition_arrays`); after a barrier rank 0
writes ``checkpoint_mpi.json`` (``step``, ``t``, ``ranks``, ``owned_boxes``: every
rank's owned bounding box, ``finished`` and ``previous``: the step before, ``{"step":
..., "t": ...}`` or ``null``) atomically, and after a second barrier every rank deletes
its files of other steps (rank 0 also those of ranks beyond the count, left by a run
on more ranks). The previous step is the one the old marker named when every rank's
file of it reads back intact (else the old marker's own previous one, likewise
checked). Whenever one rank is killed, the marker names a step whose files every rank
has written, and its previous step's files are still there, so ``mpiexec -n N
peridynamics run deck --resume`` continues from a consistent state; when a file of the
newest step is damaged every rank takes the previous step (they agree through an
allgather).

Resuming on another number of ranks M repartitions (:mod:`peridynamics.io.repartition`):
every new rank reads the old files of the ranks whose owned box holds one of its points
and fills its State of the new partition from them. Refused with a :class:`ResumeError`
naming the rank count to use: checkpoints written before the partition was stored (no
``owned_boxes`` in the marker, no partition arrays in a file), and States with a field
of a kind that cannot be repartitioned (the interface bonds of several bodies,
rigid-body fields). A file of the step written by a run on another partition (a resumed
run on M ranks rewriting the step it resumed from) counts as damaged.
"""

from __future__ import annotations

import contextlib
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
from peridynamics.io.repartition import (
    PARTITION_KEYS,
    ResumeError,
    field_kinds,
    needed_ranks,
    owned_boxes,
    partition_arrays,
    rebuild_state,
    same_partition,
)
from peridynamics.parallel.session import Session, rank_dir
from peridynamics.state import State

MARKER = "checkpoint_mpi.json"
#: the marker's keys that are not the run's meta
_OWN = ("step", "t", "ranks", "owned_boxes", "previous")

__all__ = ["MARKER", "ResumeError", "read_rank_checkpoint", "write_rank_checkpoints"]


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


def _load(path: Path, rank: int, ranks: int) -> tuple[Checkpoint | None, str | None]:
    """The checkpoint file ``path`` of ``rank`` of a run on ``ranks`` ranks, or why it
    cannot be used (missing, damaged, written by a run on another partition)."""
    try:
        ck = load_checkpoint(path)
    except FileNotFoundError:
        return None, f"checkpoint {path} is missing"
    except DamagedCheckpoint as exc:
        return None, str(exc)
    e = ck.extra
    if "ranks" in e and (int(e["ranks"]), int(e["rank"])) != (ranks, rank):
        return None, (
            f"checkpoint {path} was written by rank {int(e['rank'])} of {int(e['ranks'])} "
            f"(not rank {rank} of {ranks}: a later run on another rank count)"
        )
    return ck, None


def _load_everywhere(
    session: Session, out: Path, step: int, fingerprint: str | None = None
) -> tuple[Checkpoint | None, list[tuple[int, str]]]:
    """Every rank: its checkpoint of ``step`` (``None`` where unusable) and every rank's
    (rank, problem) in rank order, the same list on every rank. ``fingerprint``: also
    a problem when a file was written for another deck."""
    comm = session.comm
    path = rank_dir(out, comm.rank) / _name(step)
    ck, problem = _load(path, comm.rank, comm.size)
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
    boxes = owned_boxes(session)  # collective the first time
    mine = records if session.root else {}
    extra = partition_arrays(session)
    write_checkpoint(folder, s, mine, fingerprint, meta, name=name, extra=extra)
    comm.barrier()  # every rank's file of this step exists
    marker = base / MARKER
    if session.root:
        info = {"step": s.step, "t": s.t, "ranks": comm.size, **(meta or {})}
        info["owned_boxes"] = boxes
        info["previous"] = previous
        with atomic_path(marker) as tmp:
            tmp.write_text(json.dumps(info))
    comm.barrier()  # the marker names this step and the previous one: others can go
    keep = {name} | ({_name(previous["step"])} if previous else set())
    for stale in folder.glob("checkpoint_*.npz"):
        if stale.name not in keep:
            stale.unlink(missing_ok=True)
    if session.root and isinstance(old, dict) and int(old["ranks"]) > comm.size:
        for rank in range(comm.size, int(old["ranks"])):  # a run on more ranks left them
            for stale in rank_dir(base, rank).glob("checkpoint_*.npz"):
                stale.unlink(missing_ok=True)
            # its bond list (an interrupted run's outputs): read_bonds joins every rank's
            (rank_dir(base, rank) / "bonds.npz").unlink(missing_ok=True)
            with contextlib.suppress(OSError):  # gone, or holding other files
                rank_dir(base, rank).rmdir()
    return marker


def read_rank_checkpoint(
    session: Session, out: Path
) -> tuple[State, dict[str, Any], dict[str, Any], str, str | None]:
    """Every rank: (state, records, meta, fingerprint, note) of the newest step the
    marker names whose files every rank reads back intact; ``note`` (the same on every
    rank) says why the newest was passed over (``None`` when it was not).

    A checkpoint of another number of ranks, or of as many ranks on another partition
    (its stored partition differs from this run's on some rank: another version's
    bisection), is repartitioned (``_read_repartitioned``). Raises ResumeError (on
    every rank) when there is no usable marker or the checkpoint cannot be
    repartitioned, and NoUsableCheckpoint (naming each rank's file and its reason) when
    no step it names is intact on every rank."""
    comm, out = session.comm, Path(out)
    info: Any = comm.bcast(_read_marker(out) if session.root else None)
    if isinstance(info, str):
        raise ResumeError(info)
    if int(info["ranks"]) != comm.size:
        return _read_repartitioned(session, out, info)
    problems: list[tuple[int, str]] = []
    for gen in _generations(info):
        step = int(gen["step"])
        ck, bad = _load_everywhere(session, out, step)
        if bad:
            problems += bad
            continue
        assert ck is not None
        moved = "global_ids" in ck.extra and not same_partition(ck.extra, partition_arrays(session))
        if any(comm.gather_objects(moved)):  # another partition of as many ranks
            return _read_repartitioned(session, out, info)
        note = None
        if problems:
            rank, why = problems[0]
            note = f"{why}; resuming from the previous one {rank_dir(out, rank) / _name(step)}"
        records = comm.bcast(ck.records if session.root else None)
        return ck.state, records, ck.meta, ck.fingerprint, note
    text = "; ".join(p for _, p in problems)
    raise NoUsableCheckpoint(f"{text}; no usable checkpoint in {str(out)!r}")


def _agree(session: Session, why: str | None) -> None:
    """Every rank: raise ResumeError with the first rank's reason when some rank has
    one (collective)."""
    every = [w for w in session.comm.gather_objects(why) if w]
    if every:
        raise ResumeError(every[0])


def _read_repartitioned(
    session: Session, out: Path, info: dict[str, Any]
) -> tuple[State, dict[str, Any], dict[str, Any], str, str | None]:
    """:func:`read_rank_checkpoint` of a checkpoint written by another number of ranks:
    every rank reads the old files it needs and fills a State of its own partition.

    Every rank reaches the same outcome: refusals and damaged files are agreed by an
    allgather; a damaged, missing or foreign file of the newest step makes every rank
    take the previous one. ``bonds_broken`` and the per-rank sums (``friction_work``)
    of every old rank go to the new rank 0 (the run reports their sum over ranks)."""
    comm, old = session.comm, int(info["ranks"])
    use = f"resume with mpiexec -n {old}"
    boxes = info.get("owned_boxes")
    if not isinstance(boxes, list) or len(boxes) != old:
        raise ResumeError(
            f"the checkpoint in {str(out)!r} was written by {old} MPI ranks without their "
            f"partition (a version that did not store it); {use}, or start a new run"
        )
    template = session.model.new_state()
    kinds, refused = field_kinds(session.model, template)
    if refused:  # the same model on every rank: the same answer, no message needed
        raise ResumeError(
            f"the checkpoint in {str(out)!r} was written by {old} MPI ranks and the State "
            f"holds fields that cannot be repartitioned: {', '.join(refused)}; {use}"
        )
    needed = needed_ranks(session.model.cloud.x, boxes, session.root)
    problems: list[str] = []
    for gen in _generations(info):
        step = int(gen["step"])
        cks: dict[int, Checkpoint] = {}
        here, refusal = [], None
        for r in needed:
            path = rank_dir(out, r) / _name(step)
            ck, problem = _load(path, r, old)
            if problem is not None:
                here.append(problem)
            elif ck is not None and not all(k in ck.extra for k in PARTITION_KEYS):
                refusal = f"checkpoint {path} holds no partition (an older version); {use}"
            elif ck is not None:
                cks[r] = ck
        sums = {r: _sums(ck.state, kinds) for r, ck in cks.items()}
        decks = {ck.fingerprint for ck in cks.values()}
        every = comm.gather_objects((here, refusal, sums, decks))
        refusal = next((f for _, f, _, _ in every if f), None)
        if refusal is None and len(set().union(*(d for *_, d in every))) > 1:
            refusal = f"the files of step {step} in {str(out)!r} were written by different decks"
        if refusal is not None:  # every rank has every rank's answer
            raise ResumeError(refusal)
        bad = [p for h, *_ in every for p in h]
        if bad:
            problems += bad
            continue
        why, state = None, template
        try:
            state = rebuild_state(template, kinds, session.model, comm.n_global, cks)
        except ResumeError as exc:
            why = f"the checkpoint in {str(out)!r} cannot be repartitioned: {exc}; {use}"
        _agree(session, why)
        _add_sums(state, kinds, every, session.root)
        note = None
        if problems:
            note = f"{problems[0]}; resuming from the previous one (step {step}, {_name(step)})"
        ck0 = cks[min(cks)]
        records = comm.bcast(cks[0].records if session.root else None)
        return state, records, ck0.meta, ck0.fingerprint, note
    text = "; ".join(dict.fromkeys(problems))
    raise NoUsableCheckpoint(f"{text}; no usable checkpoint in {str(out)!r}")


def _sums(s: State, kinds: dict[str, str]) -> tuple[int, dict[str, Any]]:
    """An old rank's share of the sums over ranks: bonds broken, summed fields."""
    return s.bonds_broken, {k: s[k] for k, kind in kinds.items() if kind == "sum" and k in s}


def _add_sums(state: State, kinds: dict[str, str], every: list[Any], root: bool) -> None:
    """Every old rank's ``bonds_broken`` and summed fields (each counted once, in old
    rank order) into the new rank 0's ``state``; zero elsewhere."""
    shares: dict[int, tuple[int, dict[str, Any]]] = {}
    for _, _, sums, _ in every:
        shares.update(sums)
    state.bonds_broken = sum(shares[r][0] for r in sorted(shares)) if root else 0
    for name, kind in kinds.items():
        if kind == "sum":
            state[name][...] = 0
            if root:
                for r in sorted(shares):
                    state[name] += shares[r][1].get(name, 0)
