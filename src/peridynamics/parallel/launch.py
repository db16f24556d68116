"""Commands spread over the ranks of ``mpiexec -n N`` (``peridynamics sweep``,
``peridynamics ensemble``): the communicator of the launch, the ranks sharing a machine,
the threads each process may use.

Each rank runs whole, ordinary one-process runs (no domain decomposition here); the
ranks only divide the work and gather the results on rank 0.
"""

from __future__ import annotations

import os
from typing import Any


class LaunchError(ValueError):
    """An MPI launch that cannot work (``str(exc)`` names the fix; exit 2)."""


def mpi_comm() -> Any:
    """COMM_WORLD when started by ``mpiexec -n N`` (N > 1) with mpi4py, else ``None``.

    mpi4py is imported only when the environment shows an MPI launch, so a plain command
    never initialises MPI. Raises LaunchError when launched on several ranks without
    mpi4py (each rank would do all of the work).
    """
    if not any(k.startswith(("PMI_", "PMIX_", "OMPI_COMM_WORLD_")) for k in os.environ):
        return None
    ranks = os.environ.get("PMI_SIZE") or os.environ.get("OMPI_COMM_WORLD_SIZE") or "1"
    try:
        from mpi4py import MPI
    except ImportError:
        if ranks.isdigit() and int(ranks) > 1:
            raise LaunchError(
                f"started on {ranks} MPI ranks but mpi4py is not installed: "
                "pip install 'peridynamics[mpi]' (or run without mpiexec)"
            ) from None
        return None
    comm = MPI.COMM_WORLD
    if comm.Get_size() == 1 and ranks.isdigit() and int(ranks) > 1:
        raise LaunchError(
            f"mpiexec started {ranks} ranks but mpi4py sees one: mpi4py uses another MPI "
            "library than this mpiexec (use the mpiexec of the MPI that mpi4py was built "
            "with, e.g. the one installed with peridynamics[mpi])"
        )
    return comm if comm.Get_size() > 1 else None


def node_ranks(comm: Any) -> int:
    """Ranks sharing this machine (they share its cores)."""
    if comm is None:
        return 1
    from mpi4py import MPI

    return int(comm.Split_type(MPI.COMM_TYPE_SHARED).Get_size())


def threads_per_process(jobs: int, node_ranks: int) -> int:
    """Threads for each of ``jobs`` processes per rank when ``node_ranks`` ranks share
    this machine: its cores (those this process may use) divided among them, at least 1."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cores = os.cpu_count() or 1
    return max(1, cores // (jobs * node_ranks))


def share_cores(comm: Any) -> int:
    """Give this rank its share of the machine's cores as Numba threads,
    max(1, cores / ranks on this machine), unless ``NUMBA_NUM_THREADS`` is set (the user's
    count stays); returns the Numba threads now in use. Collective under MPI: every rank
    of ``comm`` must call it. Without MPI (``comm`` is ``None``) nothing changes."""
    import numba

    if comm is None:
        return int(numba.get_num_threads())
    threads = threads_per_process(1, node_ranks(comm))
    if "NUMBA_NUM_THREADS" not in os.environ:
        most = int(getattr(numba.config, "NUMBA_NUM_THREADS", threads))  # the pool's size
        numba.set_num_threads(max(1, min(threads, most)))
    return int(numba.get_num_threads())
