"""What a run does with its output folder and with the whole decomposed body at its
end: hold the folder (:class:`~peridynamics.io.run_lock.RunLock`), gather the bond
flags and the memory of every rank."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.build.errors import SetupError
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


def gather_intact(session: Any) -> NDArray[np.bool_] | None:
    """Every rank: send the flags of its owned bonds to rank 0, which returns them in
    the order of a serial run's bonds (by global point id, then neighbour id)."""
    m, s = session.model, session.state
    b, end = m.bonds, int(m.owned_bonds)
    gid = np.asarray(m.cloud.global_ids, dtype=np.int64)
    rows = np.repeat(np.arange(len(b.offsets) - 1), np.diff(np.asarray(b.offsets)))[:end]
    n = np.int64(session.global_cloud.n_points)
    key = gid[rows] * n + gid[np.asarray(b.bond_j[:end])]
    mine = (key, np.asarray(s.intact[:end], dtype=bool))
    parts = session.comm.gather_root(mine)  # to rank 0 only, counted (to_root)
    if not session.root:
        return None
    keys = np.concatenate([k for k, _ in parts])
    flags = np.concatenate([f for _, f in parts])
    return flags[np.argsort(keys, kind="stable")]
