"""The communicator: the one object every global reduction and exchange goes through.

Points are numbered [owned | ghost]; kernels loop over the owned points (the points
that own a bond family, ``len(offsets) - 1``) and read ghosts. Today's package runs on
one process, so :class:`SerialCommunicator` owns every point, has no ghost, and its
reductions are plain NumPy; an MPI communicator (planned, issue "Scale out with MPI")
implements the same methods with ``MPI.Allreduce`` and halo exchanges, so solvers,
observers and the stable step need no change to run distributed.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from numpy.typing import NDArray


class Communicator(Protocol):
    """Global reductions and halo exchanges of one run."""

    rank: int
    size: int

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


class SerialCommunicator:
    """One process owns every point: reductions are identities, exchanges no-ops."""

    rank = 0
    size = 1

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


#: the communicator of serial runs
SERIAL = SerialCommunicator()
