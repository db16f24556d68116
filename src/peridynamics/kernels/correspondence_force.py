"""Correspondence force pass, specialised by dimension and stabilisation so that the
family loop vectorises.

f_i = sum_k w_k (T_i<xi_k> - T_j<-xi_k>) (N/m^3) in the pair form of
:mod:`peridynamics.kernels.correspondence` (PD zero-energy modes (n.d.), eqs 5, 16,
23-25): ``(A_i + A_j) xi`` plus the stabilisation ``stab_i z_i + stab_j z_j`` (Silling
(2017)) or ``(stab_i xi.z_i + stab_j xi.z_j) xi / L^3`` (LBSCMM), with ``z = y - F xi``.

The row functions are called from the point loop with the stabilisation mode as a
constant (plain ``njit`` functions, which LLVM inlines; Numba-level inlining made the
cold compile of the 2-D passes 30.7 s against 22.9 s), so LLVM removes its branches
from the family loop; indices are unsigned (plain loads of the per-bond streams) and
the loop keeps no max reduction and no early exit, so it vectorises. The largest
stretch is a pass of its own (:func:`peridynamics.kernels.bond_based.largest_stretch`).
Every call gives the force of
:func:`peridynamics.kernels.reference_correspondence.force` (the NumPy twin).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)


@njit
def _row_2d(i, bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, mode):
    """(f0, f1): the force density on point i from its family, 2-D."""
    f0 = 0.0
    f1 = 0.0
    si = stab[i]
    u0, u1 = u[i, 0], u[i, 1]
    a00, a01, a10, a11 = amat[i, 0, 0], amat[i, 0, 1], amat[i, 1, 0], amat[i, 1, 1]
    g00, g01, g10, g11 = fgrad[i, 0, 0], fgrad[i, 0, 1], fgrad[i, 1, 0], fgrad[i, 1, 1]
    for k in range(offsets[i], offsets[i + 1]):
        q = np.uint64(k)
        j = np.uint64(bond_j[q])
        w = wv[q] * np.float64(intact[q])
        x0 = bond_xi[q, 0]
        x1 = bond_xi[q, 1]
        t0 = (a00 + amat[j, 0, 0]) * x0 + (a01 + amat[j, 0, 1]) * x1
        t1 = (a10 + amat[j, 1, 0]) * x0 + (a11 + amat[j, 1, 1]) * x1
        if mode != 0:
            y0 = x0 + (u[j, 0] - u0)
            y1 = x1 + (u[j, 1] - u1)
            sj = stab[j]
            zi0 = y0 - g00 * x0 - g01 * x1
            zi1 = y1 - g10 * x0 - g11 * x1
            zj0 = y0 - fgrad[j, 0, 0] * x0 - fgrad[j, 0, 1] * x1
            zj1 = y1 - fgrad[j, 1, 0] * x0 - fgrad[j, 1, 1] * x1
            if mode == 1:
                t0 += si * zi0 + sj * zj0
                t1 += si * zi1 + sj * zj1
            else:
                lk = length[q]
                g = (si * (x0 * zi0 + x1 * zi1) + sj * (x0 * zj0 + x1 * zj1)) / (lk * lk * lk)
                t0 += g * x0
                t1 += g * x1
        f0 += w * t0
        f1 += w * t1
    return f0, f1


@njit
def _row_3d(i, bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, mode):
    """(f0, f1, f2): the force density on point i from its family, 3-D."""
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    si = stab[i]
    u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
    for k in range(offsets[i], offsets[i + 1]):
        q = np.uint64(k)
        j = np.uint64(bond_j[q])
        w = wv[q] * np.float64(intact[q])
        x0 = bond_xi[q, 0]
        x1 = bond_xi[q, 1]
        x2 = bond_xi[q, 2]
        t0 = (
            (amat[i, 0, 0] + amat[j, 0, 0]) * x0
            + (amat[i, 0, 1] + amat[j, 0, 1]) * x1
            + (amat[i, 0, 2] + amat[j, 0, 2]) * x2
        )
        t1 = (
            (amat[i, 1, 0] + amat[j, 1, 0]) * x0
            + (amat[i, 1, 1] + amat[j, 1, 1]) * x1
            + (amat[i, 1, 2] + amat[j, 1, 2]) * x2
        )
        t2 = (
            (amat[i, 2, 0] + amat[j, 2, 0]) * x0
            + (amat[i, 2, 1] + amat[j, 2, 1]) * x1
            + (amat[i, 2, 2] + amat[j, 2, 2]) * x2
        )
        if mode != 0:
            y0 = x0 + (u[j, 0] - u0)
            y1 = x1 + (u[j, 1] - u1)
            y2 = x2 + (u[j, 2] - u2)
            sj = stab[j]
            zi0 = y0 - fgrad[i, 0, 0] * x0 - fgrad[i, 0, 1] * x1 - fgrad[i, 0, 2] * x2
            zi1 = y1 - fgrad[i, 1, 0] * x0 - fgrad[i, 1, 1] * x1 - fgrad[i, 1, 2] * x2
            zi2 = y2 - fgrad[i, 2, 0] * x0 - fgrad[i, 2, 1] * x1 - fgrad[i, 2, 2] * x2
            zj0 = y0 - fgrad[j, 0, 0] * x0 - fgrad[j, 0, 1] * x1 - fgrad[j, 0, 2] * x2
            zj1 = y1 - fgrad[j, 1, 0] * x0 - fgrad[j, 1, 1] * x1 - fgrad[j, 1, 2] * x2
            zj2 = y2 - fgrad[j, 2, 0] * x0 - fgrad[j, 2, 1] * x1 - fgrad[j, 2, 2] * x2
            if mode == 1:
                t0 += si * zi0 + sj * zj0
                t1 += si * zi1 + sj * zj1
                t2 += si * zi2 + sj * zj2
            else:
                lk = length[q]
                g = (
                    si * (x0 * zi0 + x1 * zi1 + x2 * zi2) + sj * (x0 * zj0 + x1 * zj1 + x2 * zj2)
                ) / (lk * lk * lk)
                t0 += g * x0
                t1 += g * x1
                t2 += g * x2
        f0 += w * t0
        f1 += w * t1
        f2 += w * t2
    return f0, f1, f2


@_hot
def force_2d(bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, mode, out):
    """2-D correspondence force density (N/m^3).

    Parameters
    ----------
    bond_xi : (n_bonds, 2) reference bond vectors (m); length : (n_bonds,) |xi| (m).
    u : (n_all, 2) displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j (int32), wv (m^3), intact (uint8): (n_bonds,).
    amat : (n_all, 2, 2) A_i = (P_i - sigma^s_i) K_i^-1 (Pa/m^5).
    fgrad : (n_all, 2, 2) deformation gradients.
    stab : (n_all,) stabilisation coefficients (0 on degenerate points).
    mode : int, 0 none, 1 Silling, 2 LBSCMM.
    out : (n_all, 2) output; rows ``0..n-1`` are written.
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        q = np.uint64(i)  # the rows' index unsigned, as prange's: one compile each
        if mode == 2:
            f0, f1 = _row_2d(
                q, bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, 2
            )
        elif mode == 1:
            f0, f1 = _row_2d(
                q, bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, 1
            )
        else:
            f0, f1 = _row_2d(
                q, bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, 0
            )
        out[i, 0] = f0
        out[i, 1] = f1


@_hot
def force_3d(bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, mode, out):
    """3-D correspondence force density (N/m^3); arguments as :func:`force_2d`, dim 3."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        q = np.uint64(i)  # the rows' index unsigned, as prange's: one compile each
        if mode == 2:
            f0, f1, f2 = _row_3d(
                q, bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, 2
            )
        elif mode == 1:
            f0, f1, f2 = _row_3d(
                q, bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, 1
            )
        else:
            f0, f1, f2 = _row_3d(
                q, bond_xi, length, u, offsets, bond_j, wv, intact, amat, fgrad, stab, 0
            )
        out[i, 0] = f0
        out[i, 1] = f1
        out[i, 2] = f2


FORCE_KERNELS = {2: force_2d, 3: force_3d}
