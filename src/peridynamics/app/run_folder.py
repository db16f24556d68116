"""What a run does with its output folder and with the whole decomposed body at its
end: hold the folder (:class:`~peridynamics.io.run_lock.RunLock`), write the final
state by pieces, reduce its numbers, gather the memory of every rank."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from peridynamics.build.errors import SetupError
from peridynamics.io.final_state import write_index, write_piece
from peridynamics.io.run_lock import FolderLocked, RunLock


def hold_folder(out: Path, what: str, dist: Any) -> RunLock | None:
    """Hold ``out`` for this run (rank 0 of the decomposed run ``dist``, whose every
    rank learns whether the folder could be taken; ``dist`` is ``None`` when serial).
    Raises SetupError (key ``what``) naming the process that holds the folder."""
    lock, problem = None, ""
    if dist is None or dist.root:
        try:
            lock = RunLock(out, what).acquire()
        except FolderLocked as exc:
            problem = str(exc)
        except OSError as exc:
            problem = f"{str(out)!r}: cannot write there ({exc.strerror or exc})"
    if dist is not None and dist.comm.any(bool(problem)):
        problem = problem or "rank 0 could not take the output folder"
    if problem:
        raise SetupError(what, problem)
    return lock


def peak_rss_gib() -> float:
    """Peak resident memory of this process (GiB; Linux reports kB)."""
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def gather_rss(session: Any) -> list[float]:
    """Peak resident memory of every rank (GiB), in rank order."""
    return list(session.comm.gather_objects(peak_rss_gib()))


def write_final_pieces(session: Any, out: str) -> None:
    """Every rank: its piece of ``final_state.npz`` (its owned points' rows and their
    bonds' flags; :mod:`peridynamics.io.final_state`); rank 0 also the index."""
    m, s, comm = session.model, session.state, session.comm
    n = comm.n_owned
    fields = {
        "u": s.u[:n],
        "v": s.v[:n],
        "damage": session.local_damage()[:n],
        "x": m.cloud.x[:n],
    }
    try:  # the per-point random field (Weibull) a run drew, and no-fail points (inf)
        fields["critical_stretch"] = np.asarray(m.point_s0)[:n]
    except AttributeError:
        pass
    for group in m.force_model.dofs()[1:]:  # micropolar: theta (rad), moment (N m/m^3)
        fields[group.value] = s[group.value][:n]
        fields[group.force] = s[group.force][:n]
    gid = np.asarray(m.cloud.global_ids, dtype=np.int64)[:n]
    sizes = np.diff(np.asarray(m.bonds.offsets[: n + 1], dtype=np.int64)).astype(np.int64)
    write_piece(Path(out), comm.rank, gid, sizes, s.intact[: int(m.owned_bonds)], **fields)
    if session.root:
        write_index(Path(out), comm.size, comm.n_global, s.t, s.step)


def final_stats(session: Any) -> tuple[float, float, float]:
    """(largest point damage, largest displacement component (m), fraction of points
    with damage >= 0.3) of the whole body, reduced over the ranks (the serial values bit
    for bit: maxima and a count)."""
    s, comm = session.state, session.comm
    n = comm.n_owned
    damage = session.local_damage()[:n]
    u = np.abs(s.u[:n])
    return (
        comm.max(float(damage.max()) if n else 0.0),
        comm.max(float(u.max()) if u.size else 0.0),
        comm.sum(float(np.count_nonzero(damage >= 0.3))) / comm.n_global,
    )
