"""The communicator: the one object every global reduction and exchange goes through.

Points are numbered [owned | ghost]; kernels loop over the owned points (the points
that own a bond family, ``len(offsets) - 1``) and read ghosts. Today's package runs on
one process, so :class:`SerialCommunicator` owns every point, has no ghost, and its
reductions are plain NumPy; :class:`peridynamics.parallel.mpi.MPICommunicator`
implements the same methods with ``MPI.Allreduce`` and halo exchanges, so solvers and
the stable step need no change to run distributed. Sums over points go over
``arr[comm.owned]`` (ghost rows are copies of other ranks' points).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Protocol

import numpy as np
from numpy.typing import NDArray


class Communicator(Protocol):
    """Global reductions and halo exchanges of one run."""

    rank: int
    size: int

    @property
    def owned(self) -> slice:
        """The owned rows of a per-point array."""
        ...

    @property
    def n_owned(self) -> int | None:
        """The number of owned points (``None`` in a serial run: every point)."""
        ...

    @property
    def exchange_s(self) -> float:
        """Wall time spent in halo exchanges (s)."""
        ...

    def sum(self, value: float) -> float:
        """Sum of ``value`` over all ranks."""
        ...

    def min(self, value: float) -> float:
        """Minimum of ``value`` over all ranks."""
        ...

    def max(self, value: float) -> float:
        """Maximum of ``value`` over all ranks."""
        ...

    def sum_array(self, values: NDArray) -> NDArray:
        """Element-wise sum of an array over all ranks (same shape on every rank)."""
        ...

    def exchange(self, field: NDArray) -> None:
        """Fill the ghost rows of a per-point ``field`` from their owners (in place)."""
        ...

    def exchange_fields(self, fields: list[NDArray]) -> None:
        """:meth:`exchange` of several per-point fields in one message per neighbour."""
        ...

    def any(self, flag: bool) -> bool:
        """True when ``flag`` is true on some rank."""
        ...


class SerialCommunicator:
    """One process owns every point: reductions are identities, exchanges no-ops."""

    rank = 0
    size = 1

    @property
    def owned(self) -> slice:
        return slice(None)

    @property
    def n_owned(self) -> int | None:
        return None

    @property
    def exchange_s(self) -> float:
        return 0.0

    def sum(self, value: float) -> float:
        return float(value)

    def min(self, value: float) -> float:
        return float(value)

    def max(self, value: float) -> float:
        return float(value)

    def sum_array(self, values: NDArray) -> NDArray:
        return np.asarray(values)

    def exchange(self, field: NDArray) -> None:
        return None

    def exchange_fields(self, fields: list[NDArray]) -> None:
        return None

    def any(self, flag: bool) -> bool:
        return bool(flag)


#: the communicator of serial runs
SERIAL: Communicator = SerialCommunicator()


_ACTIVE: list[Communicator] = []


def active_comm() -> Communicator:
    """The communicator of the run being built (:func:`using`), else :data:`SERIAL`:
    the default of every :class:`~peridynamics.evaluation.evaluator.Evaluator` and of the set-up
    steps
    that exchange per-point reference quantities (surface-correction ratios)."""
    if _ACTIVE:
        return _ACTIVE[-1]
    return SERIAL


@contextmanager
def using(comm: Communicator) -> Iterator[Communicator]:
    """Build a distributed run's objects with ``comm`` as :func:`active_comm`."""
    _ACTIVE.append(comm)
    try:
        yield comm
    finally:
        _ACTIVE.pop()
