"""Bond-based force pass in float32 with the cancellation-free stretch
(``solver.precision: float32``).

The reference positions are centred and stored in float32, the displacements cast to
float32 each evaluation, the per-bond stiffness stored in float32 (4 bytes instead of
8). With x ~ 0.1 m and u ~ 1e-6 m the float32 sum ``x + u`` keeps about one
significant digit of ``u``, and ``|xi + eta| - |xi|`` cancels: here the stretch never
forms ``xi + eta`` first but uses::

    |xi + eta|^2 - |xi|^2 = 2 xi . eta + eta . eta  =: q,
    s = q / (|xi| (|xi + eta| + |xi|)),

where every term is of the size of the result (no cancellation: the usual
rearrangement of a difference of square roots). The force is ``stiffness * mu * s *
(xi + eta) / |xi + eta|`` as in :mod:`peridynamics.kernels.bond_based`, whose float64
kernels are the oracle. Bond (i, j) and (j, i) see the same q (xi and eta are exact
differences, negated), so both directions break together.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from peridynamics.kernels.bond_based import total_count

_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)

_NEVER = np.float32(1.0e30)
_ZERO = np.float32(0.0)
_TWO = np.float32(2.0)
_HALF = np.float32(0.5)


@njit(inline="always")
def _stretch(i, j, x, u):
    """Cancellation-free stretch of bond (i, j), float32, components summed in order."""
    d = x.shape[1]
    q = _ZERO
    l2 = _ZERO
    for c in range(d):
        xi = x[j, c] - x[i, c]
        eta = u[j, c] - u[i, c]
        l2 += xi * xi
        q += (_TWO * xi + eta) * eta
    length = np.sqrt(l2)
    r = np.sqrt(l2 + q)
    return q / (length * (r + length))


@njit(fastmath=False)
def _break_family(i, x, u, offsets, bond_j, intact, s0):
    """Break the bonds of point ``i`` whose float32 stretch reaches (s0_i + s0_j) / 2
    (``i`` unsigned, the type of prange's index in the parallel loop: compiled once)."""
    broken = 0
    for k in range(offsets[i], offsets[i + 1]):
        j = bond_j[k]
        if intact[k] and _stretch(i, j, x, u) >= _HALF * (s0[i] + s0[j]):
            intact[k] = 0
            broken += 1
    return broken


@njit(inline="always")
def _family_1d(i, x, u, offsets, bond_j, stiffness, intact, level):
    """Force of point ``i``'s family and the filter sum (> 0 iff some intact bond's
    stretch exceeds ``level``), 1-D."""
    f0 = _ZERO
    over = _ZERO
    for k in range(offsets[i], offsets[i + 1]):
        q_k = np.uint64(k)
        j = np.uint64(bond_j[q_k])
        a0 = x[j, 0] - x[i, 0]
        b0 = u[j, 0] - u[i, 0]
        l2 = a0 * a0
        q = (_TWO * a0 + b0) * b0
        length = np.sqrt(l2)
        r = np.sqrt(l2 + q)
        s = q / (length * (r + length))
        m = np.float32(intact[q_k])
        g = stiffness[q_k] * m * s / r
        f0 += g * (a0 + b0)
        t = (s - level) * m
        over += t + np.abs(t)
    return f0, over


@njit(inline="always")
def _family_2d(i, x, u, offsets, bond_j, stiffness, intact, level):
    """Force of point ``i``'s family and the filter sum (> 0 iff some intact bond's
    stretch exceeds ``level``), 2-D."""
    f0 = _ZERO
    f1 = _ZERO
    over = _ZERO
    for k in range(offsets[i], offsets[i + 1]):
        q_k = np.uint64(k)
        j = np.uint64(bond_j[q_k])
        a0 = x[j, 0] - x[i, 0]
        b0 = u[j, 0] - u[i, 0]
        a1 = x[j, 1] - x[i, 1]
        b1 = u[j, 1] - u[i, 1]
        l2 = a0 * a0 + a1 * a1
        q = (_TWO * a0 + b0) * b0 + (_TWO * a1 + b1) * b1
        length = np.sqrt(l2)
        r = np.sqrt(l2 + q)
        s = q / (length * (r + length))
        m = np.float32(intact[q_k])
        g = stiffness[q_k] * m * s / r
        f0 += g * (a0 + b0)
        f1 += g * (a1 + b1)
        t = (s - level) * m
        over += t + np.abs(t)
    return f0, f1, over


@njit(inline="always")
def _family_3d(i, x, u, offsets, bond_j, stiffness, intact, level):
    """Force of point ``i``'s family and the filter sum (> 0 iff some intact bond's
    stretch exceeds ``level``), 3-D."""
    f0 = _ZERO
    f1 = _ZERO
    f2 = _ZERO
    over = _ZERO
    for k in range(offsets[i], offsets[i + 1]):
        q_k = np.uint64(k)
        j = np.uint64(bond_j[q_k])
        a0 = x[j, 0] - x[i, 0]
        b0 = u[j, 0] - u[i, 0]
        a1 = x[j, 1] - x[i, 1]
        b1 = u[j, 1] - u[i, 1]
        a2 = x[j, 2] - x[i, 2]
        b2 = u[j, 2] - u[i, 2]
        l2 = a0 * a0 + a1 * a1 + a2 * a2
        q = (_TWO * a0 + b0) * b0 + (_TWO * a1 + b1) * b1 + (_TWO * a2 + b2) * b2
        length = np.sqrt(l2)
        r = np.sqrt(l2 + q)
        s = q / (length * (r + length))
        m = np.float32(intact[q_k])
        g = stiffness[q_k] * m * s / r
        f0 += g * (a0 + b0)
        f1 += g * (a1 + b1)
        f2 += g * (a2 + b2)
        t = (s - level) * m
        over += t + np.abs(t)
    return f0, f1, f2, over


@_hot
def force_f32_1d(x, u, offsets, bond_j, stiffness, intact, s0, s0_min, force, nbroken):
    """1-D float32 bond force density (N/m^3) with bond breaking; see :func:`force_f32`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        level = min(s0_min[i], _NEVER) * np.float32(1.0 - 1e-6)
        f0, over = _family_1d(i, x, u, offsets, bond_j, stiffness, intact, level)
        nbroken[i] = 0
        if over > _ZERO:
            nb = _break_family(np.uint64(i), x, u, offsets, bond_j, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, over = _family_1d(i, x, u, offsets, bond_j, stiffness, intact, level)
        force[i, 0] = f0
    return total_count(nbroken)


@_hot
def force_f32_2d(x, u, offsets, bond_j, stiffness, intact, s0, s0_min, force, nbroken):
    """2-D float32 bond force density (N/m^3) with bond breaking; see :func:`force_f32`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        level = min(s0_min[i], _NEVER) * np.float32(1.0 - 1e-6)
        f0, f1, over = _family_2d(i, x, u, offsets, bond_j, stiffness, intact, level)
        nbroken[i] = 0
        if over > _ZERO:
            nb = _break_family(np.uint64(i), x, u, offsets, bond_j, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, f1, over = _family_2d(i, x, u, offsets, bond_j, stiffness, intact, level)
        force[i, 0] = f0
        force[i, 1] = f1
    return total_count(nbroken)


@_hot
def force_f32_3d(x, u, offsets, bond_j, stiffness, intact, s0, s0_min, force, nbroken):
    """3-D float32 bond force density (N/m^3) with bond breaking; see :func:`force_f32`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        level = min(s0_min[i], _NEVER) * np.float32(1.0 - 1e-6)
        f0, f1, f2, over = _family_3d(i, x, u, offsets, bond_j, stiffness, intact, level)
        nbroken[i] = 0
        if over > _ZERO:
            nb = _break_family(np.uint64(i), x, u, offsets, bond_j, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, f1, f2, over = _family_3d(i, x, u, offsets, bond_j, stiffness, intact, level)
        force[i, 0] = f0
        force[i, 1] = f1
        force[i, 2] = f2
    return total_count(nbroken)


_KERNELS = {1: force_f32_1d, 2: force_f32_2d, 3: force_f32_3d}


def force_f32(x, u, offsets, bond_j, stiffness, intact, s0, s0_min, force, nbroken):
    """Bond force density (N/m^3, float32) with bond breaking, any dimension.

    Parameters
    ----------
    x : (n, dim) float32 reference positions, centred (m).
    u : (n, dim) float32 displacements (m).
    offsets : (n + 1,) int64; bond_j (int32), stiffness (float32), intact (uint8):
        (n_bonds,).
    s0, s0_min : (n,) float32 point critical stretch and smallest bond threshold of the
        family (``inf`` = never fails).
    force : (n, dim) float32 output; nbroken : (n,) int64 scratch output.

    Returns
    -------
    int : number of directed bonds broken by this call.
    """
    return _KERNELS[x.shape[1]](
        x, u, offsets, bond_j, stiffness, intact, s0, s0_min, force, nbroken
    )
