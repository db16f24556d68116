"""The two Numba loops of adaptive dynamic relaxation (Kilic & Madenci (2010); the
equations (ADR-1)...(ADR-6) and the solver are in :mod:`peridynamics.solvers.adr`): the
residual, reaction and damping sums of one iteration and the velocity and displacement
update, on flat dof arrays.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

__all__ = ["adr_norms", "adr_update"]

#: fixed number of partial sums of the reductions: the same bits for any thread count
_CHUNKS = 256

_kernel = njit(parallel=True, fastmath=False, cache=True)


@_kernel
def adr_norms(u, v, force, force_prev, body, volume, inv_lambda, free, dt, out):
    """Residual, reaction and damping sums of one ADR iteration (flat dof arrays).

    Parameters
    ----------
    u, v : (m,) displacement (m) and fictitious velocity U'^{n-1/2} (m/s), m = n dim.
    force, force_prev : (m,) internal force density F^n and F^{n-1} (N/m^3).
    body : (m,) external force density (N/m^3).
    volume : (m,) point volume of each dof (m^3).
    inv_lambda : (m,) 1 / lambda_ii.
    free : (m,) uint8, 1 for a free dof, 0 for a constrained one.
    dt : float, fictitious time step.
    out : (4,) output: sum over free dofs of (V (f + b))^2 (N^2), the same over
        constrained dofs (the reactions), sum_free U_i^2 1K_ii U_i (ADR-4) and
        sum_free U_i^2 (m^2).

    Chunked partial sums in a fixed order give the same bits for any thread count.
    """
    m = u.shape[0]
    chunks = min(m, _CHUNKS) if m > 0 else 1
    part = np.empty((chunks, 4))  # every entry written below (np.zeros: one more parfor)
    for c in prange(chunks):
        lo = c * m // chunks
        hi = (c + 1) * m // chunks
        r_free = 0.0
        r_fixed = 0.0
        ku = 0.0
        uu = 0.0
        for i in range(lo, hi):
            r = volume[i] * (force[i] + body[i])
            if free[i]:
                r_free += r * r
                ui = u[i]
                uu += ui * ui
                vi = v[i]
                if vi != 0.0:
                    k = -(force[i] - force_prev[i]) * inv_lambda[i] / (dt * vi)
                    ku += ui * ui * k
            else:
                r_fixed += r * r
        part[c, 0] = r_free
        part[c, 1] = r_fixed
        part[c, 2] = ku
        part[c, 3] = uu
    for q in range(4):
        s = 0.0
        for c in range(chunks):
            s += part[c, q]
        out[q] = s


@_kernel
def adr_update(u, v, force, body, inv_lambda, free, target, c, dt, first):
    """The ADR velocity and displacement update (ADR-5, or ADR-6 when ``first``) in place.

    Parameters
    ----------
    u, v : (m,) displacement U^n -> U^{n+1} (m), fictitious velocity U'^{n-1/2} ->
        U'^{n+1/2} (m/s).
    force, body : (m,) internal and external force density at U^n (N/m^3).
    inv_lambda : (m,) 1 / lambda_ii.
    free : (m,) uint8; constrained dofs are set to ``target`` (m) with U' = 0.
    c : float, damping coefficient c^n (1/s); dt : float, fictitious time step (s).
    first : bool, use U'^{1/2} = dt F^0 / (2 lambda).
    """
    m = u.shape[0]
    keep = (2.0 - c * dt) / (2.0 + c * dt)
    push = 2.0 * dt / (2.0 + c * dt)
    for i in prange(m):
        if free[i]:
            a = (force[i] + body[i]) * inv_lambda[i]
            if first:
                vn = 0.5 * dt * a
            else:
                vn = keep * v[i] + push * a
            v[i] = vn
            u[i] += dt * vn
        else:
            v[i] = 0.0
            u[i] = target[i]
