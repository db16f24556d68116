"""Bond-based peridynamic heat conduction kernels (Bobaru & Duangpanya (2010,
2012)).

Every Numba kernel here has a NumPy twin in :mod:`peridynamics.kernels.reference_heat`
that the tests compare against. They gather over each point's family in the directed
CSR bond list (both (i, j) and (j, i) stored), so each point is written by one thread
only: no atomics.

* heat rate density   h_i = sum_k G_k mu_k (T_j - T_i)              (W/m^3)
* row sum             r_i = sum_k G_k mu_k                          (W/(m^3 K))

where ``G_k = kappa(|xi_k|) * lambda_k * beta_k V_j / |xi_k|`` is the bond conductance
(micro-conductivity times surface correction times partial volume over the bond
length, W/(m^3 K)) and ``mu_k`` is 1 for an intact bond: a broken bond conducts no heat.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

_exact = njit(parallel=True, fastmath=False, cache=True)


@_exact
def heat_rate(temperature, offsets, bond_j, conductance, intact, out):
    """``out[i] = sum_k conductance[k] * intact[k] * (T[j_k] - T[i])``.

    Parameters
    ----------
    temperature : (n,) float64, K.
    offsets : (n + 1,) int64, CSR offsets of the directed bond list.
    bond_j : (n_bonds,) int32, neighbour of each bond.
    conductance : (n_bonds,) float64, bond conductance G_k (W/(m^3 K)).
    intact : (n_bonds,) uint8, 1 for a conducting bond.
    out : (n,) float64, heat rate density (W/m^3), overwritten.
    """
    n = len(offsets) - 1
    for i in prange(n):
        ti = temperature[i]
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k]:
                acc += conductance[k] * (temperature[bond_j[k]] - ti)
        out[i] = acc


@_exact
def conductance_row_sum(offsets, conductance, intact, out):
    """``out[i] = sum_k conductance[k] * intact[k]`` (W/(m^3 K)), the diagonal of the
    conduction operator and, by Gershgorin, half the radius bound of its spectrum.

    Parameters
    ----------
    offsets : (n + 1,) int64.
    conductance : (n_bonds,) float64, W/(m^3 K).
    intact : (n_bonds,) uint8.
    out : (n,) float64, overwritten.
    """
    n = len(offsets) - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k]:
                acc += conductance[k]
        out[i] = acc


@_exact
def euler_update(temperature, rate, source, inv_capacity, dt, out):
    """Forward Euler: ``out[i] = T[i] + dt * (rate[i] + source[i]) * inv_capacity[i]``.

    Parameters
    ----------
    temperature, rate, source, inv_capacity : (n,) float64 (K, W/m^3, W/m^3,
        m^3 K/J = 1 / (rho c_v)).
    dt : float, s.
    out : (n,) float64, K (may be ``temperature``).
    """
    for i in prange(len(temperature)):
        out[i] = temperature[i] + dt * (rate[i] + source[i]) * inv_capacity[i]


def warm_up() -> None:
    """Compile (or load from the cache) the kernels on tiny arrays of the run's types."""
    t = np.zeros(2)
    off = np.array([0, 1, 2], dtype=np.int64)
    bj = np.array([1, 0], dtype=np.int32)
    g = np.ones(2)
    mu = np.ones(2, dtype=np.uint8)
    heat_rate(t, off, bj, g, mu, np.empty(2))
    conductance_row_sum(off, g, mu, np.empty(2))
    euler_update(t, t, t, g, 0.0, np.empty(2))
