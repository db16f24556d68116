"""NumPy twin of :mod:`peridynamics.kernels.viscoelastic` (the test oracle): the same
Maxwell force of the viscoelastic LPS, vectorised over the bond list."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]


def viscous_force(
    x: F64, u: F64, bond_i: NDArray, bond_j: NDArray, length: F64, wv: F64, wvf: F64,
    intact: NDArray, theta: F64, a: F64, reverse: NDArray, fraction: float, decay: float,
    beta: float, eb: F64, edn: F64,
) -> tuple[F64, F64, F64]:  # fmt: skip
    """(Maxwell force density (n, 3) (N/m^3), trial eb, trial ed (n_bonds,)); arguments as
    :func:`peridynamics.kernels.viscoelastic.viscous_force_3d` with the owner ``bond_i``
    of every bond."""
    y = x[bond_j] - x[bond_i] + u[bond_j] - u[bond_i]
    r = np.sqrt(np.einsum("ij,ij->i", y, y))
    e = r - length
    ed = e - theta[bond_i] * length / 3.0
    ebt = edn * (1.0 - decay) + eb * decay + beta * (ed - edn)
    g = -fraction * intact * (wv * a[bond_i] * ebt + wvf * a[bond_j] * ebt[reverse]) / r
    force = np.zeros((len(a), 3))
    np.add.at(force, bond_i, g[:, None] * y)
    return force, ebt, ed
