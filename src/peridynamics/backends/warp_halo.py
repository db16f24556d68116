"""The Warp backend in a run decomposed over MPI ranks (``mpiexec -n N``, one device
per rank).

A rank holds its points as ``[owned | first ghost layer | second layer]``
(:mod:`peridynamics.parallel.local`); the device arrays hold all of them. Before each
force evaluation on the device, :class:`DeviceHalo` fills the ghost rows of u and v
from their owners, as :meth:`~peridynamics.evaluation.evaluator.Evaluator.exchange_dofs`
does on the host: the rows other ranks hold as ghosts are packed on the device into one
contiguous buffer (a gather kernel), copied to the host, exchanged through the run's
communicator (``model.comm.exchange_fields``: one message per neighbour rank), and the
received ghost rows are copied back and scattered on the device (a kernel). Only the
halo rows cross between device and host, never a whole field.

The exchange goes through the existing
:class:`~peridynamics.communicator.Communicator` method on a host staging array of the
local points (written only in its halo rows) rather than through a new method that
exchanges packed buffers: the protocol and the MPI communicator stay as they are, the
messages, their order and the halo timing (``exchange_s``) are those of the Numba
backend, and the price is two host copies of the halo rows per step (O(halo), not
O(points)).

The reductions of the solver count owned rows only (:func:`owned_rows`): the bonds
broken (per-point counts of the owned families), the stability check (its mean
displacement over every rank's owned points, the verdict agreed with ``comm.any``).
In a serial run none of this is used and the step is unchanged.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.backends.warp_device import DeviceModel, DeviceState

try:
    from peridynamics.backends._warp_halo_dsl import pack_rows, unpack_rows
except ImportError:  # pragma: no cover - warp-lang absent: importable, not runnable
    pack_rows = unpack_rows = None


def decomposed(model: Any) -> bool:
    """True when ``model`` is one rank's part of a decomposed run."""
    return int(model.comm.size) > 1


def owned_rows(model: Any, n: int) -> int:
    """Rows the reductions of the solver count: the owned points (the first
    ``comm.n_owned`` rows) in a decomposed run, all ``n`` rows in a serial one."""
    n_own = model.comm.n_owned
    return int(n) if n_own is None else int(n_own)


def mean_shift(comm: Any, total: NDArray[np.float64], rows: int) -> NDArray[np.float64]:
    """The mean displacement (m), shape (dim,), of the stability check from the column
    sums ``total`` (m) of this rank's ``rows`` owned points: over every rank's owned
    points when decomposed (the host check's reduction), else ``total / rows`` as the
    serial device check has always computed it."""
    if comm.size == 1:
        return np.asarray(total * (1.0 / rows), dtype=np.float64)
    out: NDArray[np.float64] = comm.sum_array(total) / comm.sum(float(rows))
    return out


def devices_per_rank(comm: Any, device: str) -> list[str]:
    """The Warp device of every rank, in rank order (one collective ``allgather`` of
    the names when decomposed; ``[device]`` when serial or when the communicator has no
    gather of objects)."""
    gather = getattr(comm, "gather_objects", None)
    if comm.size == 1 or gather is None:
        return [device]
    return [str(d) for d in gather(device)]


class DeviceHalo:
    """The halo exchange of u and v between the devices of a decomposed run.

    Parameters
    ----------
    comm : the run's communicator; ``comm.layout`` holds ``send`` (rank ->
        local rows of owned points that rank holds as ghosts) and ``recv`` (rank ->
        local rows of the ghosts it owns).
    dm : DeviceModel
        This rank's device arrays (``dm.n`` local points, ``dm.dim`` components).

    Attributes
    ----------
    send_rows, recv_rows : NDArray[np.int32]
        The distinct owned rows other ranks hold (sorted) and the ghost rows received.
    staging : NDArray[np.float64] (n, 2 dim)
        Host rows ``[u | v]`` of the local points, written and read only in the halo
        rows: what ``comm.exchange_fields`` sends from and receives into.
    """

    def __init__(self, comm: Any, dm: DeviceModel) -> None:
        layout = comm.layout
        self.comm = comm
        self.dm = dm
        w = dm.wp
        width = 2 * dm.dim
        send = [np.asarray(r, dtype=np.int64) for r in layout.send.values()]
        recv = [np.asarray(r, dtype=np.int64) for r in layout.recv.values()]
        empty = np.zeros(0, dtype=np.int64)
        self.send_rows = np.unique(np.concatenate([empty, *send])).astype(np.int32)
        self.recv_rows = np.concatenate([empty, *recv]).astype(np.int32)
        self.staging = np.zeros((dm.n, width), dtype=np.float64)
        pinned = dm.device.startswith("cuda")
        self._send_rows_d = dm.upload("halo_send_rows", self.send_rows)
        self._recv_rows_d = dm.upload("halo_recv_rows", self.recv_rows)
        ns, nr = len(self.send_rows), len(self.recv_rows)
        self._send_d = dm.zeros((ns, width), w.float64)
        self._recv_d = dm.zeros((nr, width), w.float64)
        self._send_h = w.zeros((ns, width), dtype=w.float64, device="cpu", pinned=pinned)
        self._recv_h = w.zeros((nr, width), dtype=w.float64, device="cpu", pinned=pinned)
        #: halo rows moved between device and host so far (bytes, both ways)
        self.moved_bytes = 0

    def exchange(self, ds: DeviceState) -> None:
        """Fill the ghost rows of ``ds.u`` and ``ds.v`` (m, m/s) from their owners'
        device arrays (collective: every rank calls it at the same point of the step)."""
        dm, w = self.dm, self.dm.wp
        ns, nr = len(self.send_rows), len(self.recv_rows)
        if ns:
            dm.launch(pack_rows, ns, [self._send_rows_d, ds.u, ds.v, self._send_d])
            w.copy(self._send_h, self._send_d)
            if dm.device.startswith("cuda"):
                w.synchronize_device(dm.device)  # the host buffer is complete
            self.staging[self.send_rows] = self._send_h.numpy()
        self.comm.exchange_fields([self.staging])
        if nr:
            self._recv_h.numpy()[...] = self.staging[self.recv_rows]
            w.copy(self._recv_d, self._recv_h)
            dm.launch(unpack_rows, nr, [self._recv_rows_d, self._recv_d, ds.u, ds.v])
        self.moved_bytes += (ns + nr) * self.staging.shape[1] * 8


def halo_for(model: Any, dm: DeviceModel) -> DeviceHalo | None:
    """The halo exchange of ``model``'s rank (None in a serial run)."""
    if not decomposed(model):
        return None
    if getattr(model.comm, "layout", None) is None:
        raise ValueError(
            "solver.backend: warp under mpiexec needs the run's MPI communicator with its "
            "halo layout"
        )
    return DeviceHalo(model.comm, dm)
