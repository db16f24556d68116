"""Correspondence (non-ordinary state-based) kernels, 2-D and 3-D.

Every Numba kernel here has a NumPy twin in
:mod:`peridynamics.kernels.reference_correspondence` that the tests compare against. The
kernels gather over each point's family in the directed CSR bond list and each point
writes only its own rows (no atomics); per-point inputs (``amat``, ``fgrad``,
``stab``) are read at the far end of a bond too and must be valid for every row
(ghosts included).

Notation (per directed bond k = (i, j)): reference bond ``xi = bond_xi[k]`` (m), its
length ``L``, deformed bond ``y = xi + u_j - u_i``, weight ``w_k = mu_k beta_k V_j``
(m^3: the influence function omega = mu_k, 1 intact / 0 broken, times the partial
volume). Equations (PD zero-energy modes (n.d.), eqs 3, 5, 6, 16, 23-25):

* shape tensor      K_i = sum_k w_k xi (x) xi                           (m^5)
* deformation grad. F_i = (sum_k w_k y (x) xi) K_i^-1
* non-uniform part  z_ik = y_k - F_i xi_k
* force state       T_i<xi> = A_i xi + (stabilisation), A_i = (P_i - sigma^s_i) K_i^-1
* force density     f_i = sum_k w_k (T_i<xi_k> - T_j<-xi_k>)             (N/m^3)

Stabilisation (``mode``; per-point coefficient ``stab_i``, 0 on a degenerate point):

* 0 none: ``T_i<xi> = A_i xi``;
* 1 Silling (2017): ``+ stab_i z_ik`` with ``stab_i = G C / omega_0,i`` (N/m^9);
* 2 LBSCMM: ``+ stab_i (xi . z_ik) xi / L^3`` with ``stab_i = c / 2`` (N/m^6) and
  ``sigma^s_i = stab_i sum_k w_k (xi . z_ik) xi (x) xi / L^3`` (Pa).

In the pair form ``T_i<xi> - T_j<-xi> = (A_i + A_j) xi + stab_i z_i + stab_j z_j``
(Silling) or ``+ (stab_i xi.z_i + stab_j xi.z_j) xi / L^3`` (LBSCMM), with ``z_j = y -
F_j xi`` the deviation of the same bond from the far point's deformation. The force
pass is :mod:`peridynamics.kernels.correspondence_force` (specialised by dimension and
mode).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from peridynamics.kernels.correspondence_points import (  # re-exported: one kernel module
    LAW_LINEAR,
    LAW_SVK,
    force_tensor,
    invert_in_place,
    shape_determinant,
)
from peridynamics.kernels.correspondence_sums import (
    lbscmm_matrix_3d,
    motion_sums_2d,
    motion_sums_3d,
    shape_sums_2d,
    shape_sums_3d,
)

#: hot loops: fast-math lets LLVM vectorise the family sums
_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
#: diagnostics: no fast-math, reproducible bits
_exact = njit(parallel=True, fastmath=False, cache=True)

MODE_NONE = 0
MODE_SILLING = 1
MODE_LBSCMM = 2

__all__ = [
    "LAW_LINEAR", "LAW_SVK", "MODE_LBSCMM", "MODE_NONE", "MODE_SILLING", "force_tensor",
    "invert_in_place", "prepass", "shape_determinant", "stabilization_energy",
]  # fmt: skip


@_hot
def prepass(
    bond_xi, length, u, offsets, bond_j, wv, intact, det_ref, degenerate_ratio, mode, stab,
    kinv, fgrad, sigma_s, omega0, active, scratch, reuse=False,
):  # fmt: skip
    """Shape tensor inverse, deformation gradient and (LBSCMM) sigma^s of every point,
    in one pass over each family.

    ``F = I + (sum_k w_k eta (x) xi) K^-1`` (eta = u_j - u_i, no cancellation at small
    strain) and, for LBSCMM, with ``xi . z = xi . eta - xi^T (F - I) xi``,

        sigma^s = stab_i [ sum_k w_k (xi . eta) xi (x) xi / L^3
                           - sum_k (w_k / L^3) (xi^T (F - I) xi) xi (x) xi ],

    the second sum through the symmetric matrix ``M_mn = sum_k (w_k / L^3) p_m p_n`` of
    the products ``p = (xi_a xi_b)_{a <= b}``.

    Parameters
    ----------
    bond_xi : (n_bonds, d) reference bonds (m); length : (n_bonds,) |xi| (m).
    u : (n_all, d) displacement (m).
    offsets : (n + 1,) CSR offsets; bond_j, wv (m^3), intact : (n_bonds,).
    det_ref : (n,) det K_i of the reference family.
    degenerate_ratio : float
        A family with ``det K_i <= degenerate_ratio * det_ref_i`` (or det K_i <= 0) is
        degenerate: K^-1 = 0, F = I, ``active_i = 0``.
    mode : int, 0 none, 1 Silling, 2 LBSCMM.
    stab : (n,) stabilisation coefficient of every point (read for mode 2).
    kinv, fgrad, sigma_s : (n_all, d, d) outputs K_i^-1 (1/m^5), F_i, sigma^s_i (Pa;
        zero unless mode 2); rows ``0..n-1`` are written.
    omega0 : (n_all,) output sum_k w_k (m^3).
    active : (n_all,) output 1.0 for a regular family, 0.0 for a degenerate one.
    scratch : (n_all, >= 3 m + m m) work rows, m = d (d + 1) / 2.
    reuse : bool
        True: no bond changed since the last call with these ``kinv``, ``omega0``,
        ``active`` and ``scratch`` (the caller checks): K^-1, omega0, the degenerate
        flags and LBSCMM's M are kept, only the sums that depend on ``u`` are made.
    """
    n = offsets.shape[0] - 1
    d = u.shape[1]
    m = 3 if d == 2 else 6
    # symmetric index pairs (a, b), a <= b: 2-D xx, yy, xy; 3-D xx, yy, zz, xy, xz, yz
    for i in prange(n):
        # the helpers' index unsigned, as prange's in the parallel loop: one compile each
        q = np.uint64(i)
        acc = scratch[i]
        for a in range(d):
            for b in range(d):
                sigma_s[i, a, b] = 0.0
        if reuse:
            _motion(q, bond_xi, length, u, offsets, bond_j, wv, intact, mode, fgrad, acc)
            if active[i] == 0.0:
                for a in range(d):
                    for b in range(d):
                        fgrad[i, a, b] = 1.0 if a == b else 0.0
                continue
        else:
            for c in range(3 * m + m * m):
                acc[c] = 0.0
            for a in range(d):
                for b in range(d):
                    kinv[i, a, b] = 0.0
                    fgrad[i, a, b] = 0.0
            if not _geometry(
                q, bond_xi, length, u, offsets, bond_j, wv, intact, det_ref,
                degenerate_ratio, mode, kinv, fgrad, omega0, active, acc,
            ):  # fmt: skip
                continue
            _motion(q, bond_xi, length, u, offsets, bond_j, wv, intact, mode, fgrad, acc)
        active[i] = 1.0
        _finish(q, d, mode, stab, kinv, fgrad, sigma_s, acc)


@njit
def _motion(i, bond_xi, length, u, offsets, bond_j, wv, intact, mode, fgrad, acc):
    """The sums that depend on ``u`` into ``fgrad[i]`` (N) and ``acc`` (LBSCMM's q)."""
    d = u.shape[1]
    if d == 2:
        if mode == 2:
            t = motion_sums_2d(i, bond_xi, length, u, offsets, bond_j, wv, intact, 2)
        else:
            t = motion_sums_2d(i, bond_xi, length, u, offsets, bond_j, wv, intact, 0)
        fgrad[i, 0, 0], fgrad[i, 0, 1], fgrad[i, 1, 0], fgrad[i, 1, 1] = t[0], t[1], t[2], t[3]
        acc[3], acc[4], acc[5] = t[4], t[5], t[6]
        return
    if mode == 2:
        t3 = motion_sums_3d(i, bond_xi, length, u, offsets, bond_j, wv, intact, 2)
    else:
        t3 = motion_sums_3d(i, bond_xi, length, u, offsets, bond_j, wv, intact, 0)
    for a in range(3):
        for b in range(3):
            fgrad[i, a, b] = t3[3 * a + b]
    for c in range(6):
        acc[6 + c] = t3[9 + c]


@njit
def _geometry(
    i, bond_xi, length, u, offsets, bond_j, wv, intact, det_ref, degenerate_ratio, mode,
    kinv, fgrad, omega0, active, acc,
):  # fmt: skip
    """The sums of point i that depend on the bonds alone (omega0, K, LBSCMM's M), K^-1
    and the degenerate test: False (and F = I, K^-1 = 0) for a degenerate family."""
    d = u.shape[1]
    m = 3 if d == 2 else 6
    if d == 2:
        if mode == 2:
            t = shape_sums_2d(i, bond_xi, length, offsets, wv, intact, 2)
        else:
            t = shape_sums_2d(i, bond_xi, length, offsets, wv, intact, 0)
        om = t[0]
        acc[0], acc[1], acc[2] = t[1], t[2], t[3]
        acc[9], acc[10], acc[11] = t[4], t[5], t[6]
        acc[13], acc[14], acc[17] = t[7], t[8], t[9]
    else:
        t3 = shape_sums_3d(i, bond_xi, offsets, wv, intact)
        om = t3[0]
        for c in range(6):
            acc[c] = t3[1 + c]
        if mode == 2:
            lbscmm_matrix_3d(i, bond_xi, length, offsets, wv, intact, acc, 3 * m)
    omega0[i] = om
    # K from its symmetric components, inverted in place
    for a in range(d):
        kinv[i, a, a] = acc[a]
    kinv[i, 0, 1] = acc[d]
    kinv[i, 1, 0] = acc[d]
    if d == 3:
        kinv[i, 0, 2] = acc[4]
        kinv[i, 2, 0] = acc[4]
        kinv[i, 1, 2] = acc[5]
        kinv[i, 2, 1] = acc[5]
    det = invert_in_place(kinv, i, d)
    if not (det > degenerate_ratio * det_ref[i]) or not (det > 0.0):
        active[i] = 0.0
        for a in range(d):
            for b in range(d):
                kinv[i, a, b] = 0.0
                fgrad[i, a, b] = 1.0 if a == b else 0.0
        return False
    return True


@njit
def _finish(i, d, mode, stab, kinv, fgrad, sigma_s, acc):
    """F = I + N K^-1 and (LBSCMM) sigma^s of point i from its sums."""
    m = 3 if d == 2 else 6
    # H = N' K^-1 row by row, then F = I + H (the sym. part of H kept for sigma^s)
    for a in range(d):
        r0 = fgrad[i, a, 0]
        r1 = fgrad[i, a, 1]
        r2 = fgrad[i, a, 2] if d == 3 else 0.0
        for b in range(d):
            v = r0 * kinv[i, 0, b] + r1 * kinv[i, 1, b]
            if d == 3:
                v += r2 * kinv[i, 2, b]
            fgrad[i, a, b] = v
    if mode == 2:
        s = stab[i]
        # xi^T H xi = sum_m h_m p_m with h = (H_aa, H_ab + H_ba for a < b)
        if d == 2:
            h0 = fgrad[i, 0, 0]
            h1 = fgrad[i, 1, 1]
            h2 = fgrad[i, 0, 1] + fgrad[i, 1, 0]
            m00, m01, m02 = acc[9], acc[10], acc[11]
            m11, m12, m22 = acc[13], acc[14], acc[17]
            t0 = acc[3] - (m00 * h0 + m01 * h1 + m02 * h2)
            t1 = acc[4] - (m01 * h0 + m11 * h1 + m12 * h2)
            t2 = acc[5] - (m02 * h0 + m12 * h1 + m22 * h2)
            sigma_s[i, 0, 0] = s * t0
            sigma_s[i, 1, 1] = s * t1
            sigma_s[i, 0, 1] = s * t2
            sigma_s[i, 1, 0] = s * t2
        else:
            base = 3 * m
            for r in range(6):
                t = acc[6 + r]
                for c in range(6):
                    mm = acc[base + r * 6 + c] if c >= r else acc[base + c * 6 + r]
                    if c < 3:
                        hc = fgrad[i, c, c]
                    elif c == 3:
                        hc = fgrad[i, 0, 1] + fgrad[i, 1, 0]
                    elif c == 4:
                        hc = fgrad[i, 0, 2] + fgrad[i, 2, 0]
                    else:
                        hc = fgrad[i, 1, 2] + fgrad[i, 2, 1]
                    t -= mm * hc
                if r < 3:
                    sigma_s[i, r, r] = s * t
                elif r == 3:
                    sigma_s[i, 0, 1] = s * t
                    sigma_s[i, 1, 0] = s * t
                elif r == 4:
                    sigma_s[i, 0, 2] = s * t
                    sigma_s[i, 2, 0] = s * t
                else:
                    sigma_s[i, 1, 2] = s * t
                    sigma_s[i, 2, 1] = s * t
    for a in range(d):
        fgrad[i, a, a] += 1.0


@_exact
def stabilization_energy(bond_xi, length, u, offsets, bond_j, wv, intact, fgrad, stab, mode, out):
    """Energy density of the stabilisation of every point (J/m^3), shape (n,):
    Silling ``stab_i / 2 sum_k w_k |z_ik|^2``, LBSCMM ``stab_i / 2 sum_k w_k
    (xi . z_ik)^2 / L^3``; 0 for mode 0. Arguments as
    :func:`peridynamics.kernels.correspondence_force.force_2d`."""
    n = offsets.shape[0] - 1
    d = u.shape[1]
    for i in prange(n):
        acc = 0.0
        if mode != 0:
            for k in range(offsets[i], offsets[i + 1]):
                w = wv[k] * intact[k]
                if w == 0.0:
                    continue
                j = bond_j[k]
                zz = 0.0
                xz = 0.0
                for a in range(d):
                    za = bond_xi[k, a] + u[j, a] - u[i, a]
                    for b in range(d):
                        za -= fgrad[i, a, b] * bond_xi[k, b]
                    zz += za * za
                    xz += bond_xi[k, a] * za
                if mode == 1:
                    acc += w * zz
                else:
                    lk = length[k]
                    acc += w * xz * xz / (lk * lk * lk)
        out[i] = 0.5 * stab[i] * acc
