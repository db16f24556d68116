"""Plain NumPy twins of the heat-conduction kernels of :mod:`peridynamics.kernels.heat`
(the test oracles). No Python loop over points or bonds."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F = NDArray[np.float64]


def heat_rate(
    temperature: F, bond_i: NDArray, bond_j: NDArray, conductance: F, intact: NDArray
) -> F:
    """h_i = sum_k G_k mu_k (T_j - T_i) (W/m^3), shape (n,)."""
    w = conductance * intact * (temperature[bond_j] - temperature[bond_i])
    return np.asarray(np.bincount(bond_i, w, minlength=len(temperature)), dtype=np.float64)


def conductance_row_sum(n: int, bond_i: NDArray, conductance: F, intact: NDArray) -> F:
    """r_i = sum_k G_k mu_k (W/(m^3 K)), shape (n,)."""
    return np.asarray(np.bincount(bond_i, conductance * intact, minlength=n), dtype=np.float64)
