"""Viscous bond forces (seed 003 eqs 45-56), added to the elastic bond forces.

Each bond carries a force along its *deformed* direction n = (xi + eta) / |xi + eta|,
so linear and angular momentum are conserved (seed 003 eqs 45-48):

* bond strain rate      zeta_k = (eta_dot_k . n_k) / |xi_k|                (eq. 52)
* bond viscous force    f_k = lin * zeta_k + quad * zeta_k * |zeta_k|       (eqs 53, 55, 56)
* force density         F_i += sum_k weight_k * mu_k * f_k * n_k            (N/m^3)

with ``lin = b1 * alpha_p`` and ``quad = b2**2 * alpha_q`` (see
:class:`peridynamics.materials.viscosity.BondViscosity`), ``weight_k = beta_k V_j`` and
mu_k = 0 for a broken bond. Since f_k zeta_k >= 0 the viscous power
sum_i V_i F_i . v_i = -1/2 sum_k V_i weight_k f_k zeta_k |xi_k| is never positive.

The NumPy twin is :func:`peridynamics.kernels.reference.viscous_force`.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange


@njit(parallel=True, fastmath=False, cache=True)
def add_viscous_force(
    x, u, v, offsets, bond_j, inv_length, weight, intact, lin, quad, force
):  # pragma: no cover - compiled
    """Add the viscous force density of every intact bond to ``force`` (n, dim).

    ``v`` (n, dim) is the velocity the rates are taken from (the half-step velocity in
    the explicit solvers). Bonds whose deformed length is zero carry no force.
    """
    n, d = x.shape
    for i in prange(n):
        acc = np.zeros(d)
        e = np.empty(d)
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k] == 0:
                continue
            j = bond_j[k]
            r2 = 0.0
            for c in range(d):
                e[c] = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                r2 += e[c] * e[c]
            if r2 == 0.0:
                continue
            inv_r = 1.0 / np.sqrt(r2)
            rate = 0.0
            for c in range(d):
                rate += (v[j, c] - v[i, c]) * e[c]
            zeta = rate * inv_r * inv_length[k]
            f = weight[k] * (lin * zeta + quad * zeta * abs(zeta)) * inv_r
            for c in range(d):
                acc[c] += f * e[c]
        for c in range(d):
            force[i, c] += acc[c]
