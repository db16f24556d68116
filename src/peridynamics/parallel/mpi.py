"""The MPI communicator: reductions with ``Allreduce``, halo exchanges with non-blocking
point-to-point messages (mpi4py over the MPI of the ``mpich`` wheel, extra ``[mpi]``).

A rank holds its points as ``[owned | ghost]`` (:class:`~peridynamics.parallel.decompose.Layout`).
:meth:`MPICommunicator.exchange` copies the owned rows other ranks hold as ghosts into
contiguous buffers, posts every ``Isend``/``Irecv`` and waits for all, then scatters the
received rows into the ghost rows: one message per neighbour rank and field.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.parallel.decompose import Layout

_TAG_HALO = 7


class MPICommunicator:
    """Reductions and halo exchanges of one decomposed run.

    Parameters
    ----------
    comm : mpi4py communicator (``MPI.COMM_WORLD``).
    layout : what this rank owns and holds as ghosts.

    Attributes
    ----------
    rank, size : this rank, number of ranks.
    owned : slice of the owned rows of every per-point array.
    n_owned, n_global : owned points here, points of the whole body.
    exchange_s : wall time spent in :meth:`exchange` (s), for the communication share.
    to_root_bytes : rank 0: bytes of the arrays gathered onto it by :meth:`gather_points_root`
        and :meth:`gather_root`, by label (the request being served, ``to_root_label``;
        the whole gathered array, rank 0's own rows included).
    """

    def __init__(self, comm: Any, layout: Layout) -> None:
        from mpi4py import MPI

        self._mpi = MPI
        self.comm = comm
        self.layout = layout
        self.rank = int(comm.Get_rank())
        self.size = int(comm.Get_size())
        self.n_owned = layout.n_owned
        self.owned = slice(0, layout.n_owned)
        self.n_global = int(layout.n_global)
        self.exchange_s = 0.0
        self.exchanges = 0
        self.to_root_bytes: dict[str, int] = {}
        self.to_root_label = "other"
        counts = np.array(comm.allgather(int(layout.n_owned)), dtype=np.int64)
        self._counts = counts
        self._displs = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        # rank 0: global ids of the rank-by-rank concatenation of owned points (made at
        # the first gather: no rank holds a per-point array of the whole body before)
        self._order: NDArray[np.int64] | None = None
        self._order_gathered = False

    # -- reductions --------------------------------------------------------------------
    def _reduce(self, value: float, op: Any) -> float:
        buf = np.array([value], dtype=np.float64)
        out = np.empty(1)
        self.comm.Allreduce(buf, out, op=op)
        return float(out[0])

    def sum(self, value: float) -> float:
        """Sum of ``value`` over all ranks."""
        return self._reduce(float(value), self._mpi.SUM)

    def min(self, value: float) -> float:
        """Minimum of ``value`` over all ranks."""
        return self._reduce(float(value), self._mpi.MIN)

    def max(self, value: float) -> float:
        """Maximum of ``value`` over all ranks."""
        return self._reduce(float(value), self._mpi.MAX)

    def sum_array(self, values: NDArray) -> NDArray:
        """Element-wise sum of an array over all ranks (same shape on every rank)."""
        a = np.ascontiguousarray(values, dtype=np.float64)
        out = np.empty_like(a)
        self.comm.Allreduce(a, out, op=self._mpi.SUM)
        return out

    def any(self, flag: bool) -> bool:
        """True when ``flag`` is true on some rank."""
        return self.max(1.0 if flag else 0.0) > 0.0

    def bcast(self, obj: Any) -> Any:
        """``obj`` of rank 0 on every rank."""
        return self.comm.bcast(obj, root=0)

    def barrier(self) -> None:
        """Wait for every rank."""
        self.comm.Barrier()

    # -- halo ---------------------------------------------------------------------------
    def exchange(self, field: NDArray) -> None:
        """Fill the ghost rows of a per-point ``field`` (first axis = local points) from
        their owners, in place."""
        self.exchange_fields([field])

    def exchange_fields(self, fields: list[NDArray]) -> None:
        """:meth:`exchange` of several per-point fields of one dtype in one message per
        neighbour rank (their columns side by side)."""
        lay = self.layout
        if not lay.recv and not lay.send:
            return
        t0 = time.perf_counter()
        flat = [f.reshape(f.shape[0], -1) for f in fields]
        if any(not a.flags.c_contiguous for a in flat):
            raise ValueError("exchange needs C-contiguous per-point arrays")
        widths = [a.shape[1] for a in flat]
        cuts = np.cumsum([0, *widths])
        dtype = np.result_type(*[a.dtype for a in flat])
        requests = []
        recv_bufs = {}
        for q, rows in lay.recv.items():
            buf = np.empty((len(rows), int(cuts[-1])), dtype=dtype)
            recv_bufs[q] = buf
            requests.append(self.comm.Irecv(buf, source=q, tag=_TAG_HALO))
        send_bufs = []
        for q, rows in lay.send.items():
            buf = (
                np.concatenate([a[rows] for a in flat], axis=1)
                if len(flat) > 1
                else (np.ascontiguousarray(flat[0][rows]))
            )
            send_bufs.append(buf)
            requests.append(self.comm.Isend(buf, dest=q, tag=_TAG_HALO))
        self._mpi.Request.Waitall(requests)
        for q, rows in lay.recv.items():
            for k, a in enumerate(flat):
                a[rows] = recv_bufs[q][:, cuts[k] : cuts[k + 1]]
        self.exchange_s += time.perf_counter() - t0
        self.exchanges += 1

    # -- gathers -------------------------------------------------------------------------
    def gather_points_root(self, field: NDArray) -> NDArray | None:
        """The owned rows of a per-point ``field`` of every rank, in global point order,
        on rank 0: shape (n_global, ...) (``Gatherv``; observers read whole fields);
        ``None`` elsewhere."""
        own = np.ascontiguousarray(field[: self.n_owned])
        tail = own.shape[1:]
        width = int(np.prod(tail)) if tail else 1
        order = self._gather_order()
        if self.rank != 0:
            self.comm.Gatherv(own.reshape(-1), None, root=0)
            return None
        out = np.empty(self.n_global * width, dtype=own.dtype)
        self.comm.Gatherv(
            own.reshape(-1), [out, self._counts * width, self._displs * width, None], root=0
        )
        self._count_to_root(out.nbytes)
        by_rank = out.reshape((self.n_global, *tail))
        glob = np.empty_like(by_rank)
        assert order is not None
        glob[order] = by_rank
        return glob

    def _gather_order(self) -> NDArray[np.int64] | None:
        """Rank 0: the global ids of every rank's owned points, rank by rank (gathered
        once, collectively); ``None`` elsewhere."""
        if self._order_gathered:
            return self._order
        self._order_gathered = True
        ids = np.ascontiguousarray(self.layout.owned_ids, dtype=np.int64)
        if self.rank != 0:
            self.comm.Gatherv(ids, None, root=0)
            return None
        out = np.empty(self.n_global, dtype=np.int64)
        self.comm.Gatherv(ids, [out, self._counts, self._displs, None], root=0)
        self._order = out
        return out

    def gather_root(self, obj: Any) -> list[Any] | None:
        """``obj`` of every rank, in rank order, on rank 0 (pickled); ``None`` elsewhere.
        The bytes of the numpy arrays received are counted in ``to_root_bytes``."""
        parts = self.comm.gather(obj, root=0)
        if parts is None:
            return None
        self._count_to_root(sum(_nbytes(p) for p in parts))
        return list(parts)

    def _count_to_root(self, n: int) -> None:
        label = self.to_root_label
        self.to_root_bytes[label] = self.to_root_bytes.get(label, 0) + int(n)

    def gather_objects(self, obj: Any) -> list[Any]:
        """``obj`` of every rank, in rank order, on every rank (pickled; small data)."""
        return list(self.comm.allgather(obj))


def _nbytes(obj: Any) -> int:
    """Bytes of the numpy arrays in ``obj`` (an array, or tuples and lists of them)."""
    if isinstance(obj, np.ndarray):
        return int(obj.nbytes)
    if isinstance(obj, (tuple, list)):
        return sum(_nbytes(o) for o in obj)
    return 0


def build_exchange_lists(
    comm: Any, owners: NDArray[np.int32], owned: NDArray[np.intp], ghosts: NDArray[np.intp]
) -> tuple[dict[int, NDArray[np.intp]], dict[int, NDArray[np.intp]]]:
    """The receive and send lists of a rank (local indices), agreed with one
    ``alltoall`` of the ghost ids each rank needs from each owner.

    Parameters
    ----------
    comm : mpi4py communicator.
    owners : (n_ghost,) owner rank of every ghost.
    owned, ghosts : sorted global ids of the owned points and of the ghosts (in their
        local order).
    """
    from peridynamics.parallel.decompose import find_sorted, receive_lists

    size = int(comm.Get_size())
    n_owned = len(owned)
    recv = receive_lists(owners, n_owned)
    requests: list[Any] = [None] * size
    for q, rows in recv.items():
        requests[q] = ghosts[rows - n_owned]
    wanted = comm.alltoall(requests)
    send: dict[int, NDArray[np.intp]] = {}
    for q, gids in enumerate(wanted):
        if gids is None or len(gids) == 0:
            continue
        local, held = find_sorted(owned, gids)
        if not held.all():
            raise RuntimeError(f"rank {q} asked for points this rank does not own")
        send[q] = local.astype(np.intp)
    return recv, send
