"""Viscous bond forces (PD wave dispersion (n.d.), eqs 45-56), added to the elastic bond forces.

Each bond carries a force along its *deformed* direction n = (xi + eta) / |xi + eta|,
so linear and angular momentum are conserved (PD wave dispersion (n.d.), eqs 45-48):

* bond strain rate      zeta_k = (eta_dot_k . n_k) / |xi_k|                (eq. 52)
* bond viscous force    f_k = lin * zeta_k + quad * zeta_k * |zeta_k|       (eqs 53, 55, 56)
* force density         F_i += sum_k weight_k * mu_k * f_k * n_k            (N/m^3)

with ``lin = b1 * alpha_p`` and ``quad = b2**2 * alpha_q`` (see
:class:`peridynamics.families.viscosity.BondViscosity`), ``weight_k = beta_k V_j`` and
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
    n, d = offsets.shape[0] - 1, x.shape[1]
    for i in prange(n):  # scalars only: no allocation inside the parallel loop
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k] == 0:
                continue
            j = bond_j[k]
            e0 = (x[j, 0] - x[i, 0]) + (u[j, 0] - u[i, 0])
            e1 = 0.0
            e2 = 0.0
            r2 = e0 * e0
            rate = (v[j, 0] - v[i, 0]) * e0
            if d > 1:
                e1 = (x[j, 1] - x[i, 1]) + (u[j, 1] - u[i, 1])
                r2 += e1 * e1
            if d > 2:
                e2 = (x[j, 2] - x[i, 2]) + (u[j, 2] - u[i, 2])
                r2 += e2 * e2
            if r2 == 0.0:
                continue
            inv_r = 1.0 / np.sqrt(r2)
            if d > 1:
                rate += (v[j, 1] - v[i, 1]) * e1
            if d > 2:
                rate += (v[j, 2] - v[i, 2]) * e2
            zeta = rate * inv_r * inv_length[k]
            f = weight[k] * (lin * zeta + quad * zeta * abs(zeta)) * inv_r
            a0 += f * e0
            a1 += f * e1
            a2 += f * e2
        force[i, 0] += a0
        if d > 1:
            force[i, 1] += a1
        if d > 2:
            force[i, 2] += a2
