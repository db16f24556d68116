"""The family sums of the correspondence pre-pass, one point at a time, in local
accumulators (so that the family loop keeps no store and LLVM can vectorise it): those
that depend on the bonds alone (the shape tensor, omega0, LBSCMM's M; remade only when a
bond changed) and those that depend on the displacement (N, LBSCMM's q; every call),
each made by one function whichever path asks, so a kept and a remade shape tensor give
the same bits.

For point i and its bonds k (weight ``w = wv_k mu_k``, reference bond ``xi``,
``eta = u_j - u_i``; PD zero-energy modes (n.d.), eqs 3, 5, 24-25):

* ``omega0 = sum w`` (m^3);
* the shape tensor ``K = sum w xi (x) xi`` (its symmetric components);
* ``N = sum w eta (x) xi`` (F = I + N K^-1);
* LBSCMM only (``mode == 2``): ``q = sum (w / L^3) (xi . eta) p`` and the symmetric
  matrix ``M = sum (w / L^3) p (x) p`` of the products ``p = (xi_a xi_b)_{a <= b}``.

The functions are called from :func:`peridynamics.kernels.correspondence.prepass` with
``mode`` a constant, so a run without LBSCMM does not compute its sums.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit
def shape_sums_2d(i, bond_xi, length, offsets, wv, intact, mode):
    """2-D sums of point i that depend on the bonds alone: (omega0, K00, K11, K01, M00,
    M01, M02, M11, M12, M22) with the components of p ordered xx, yy, xy (M zero unless
    ``mode == 2``)."""
    om = 0.0
    k00 = k11 = k01 = 0.0
    m00 = m01 = m02 = m11 = m12 = m22 = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        c = np.uint64(k)
        w = wv[c] * np.float64(intact[c])
        x0 = bond_xi[c, 0]
        x1 = bond_xi[c, 1]
        om += w
        k00 += w * x0 * x0
        k11 += w * x1 * x1
        k01 += w * x0 * x1
        if mode == 2:
            lk = length[c]
            wl = w / (lk * lk * lk)
            p0 = x0 * x0
            p1 = x1 * x1
            p2 = x0 * x1
            m00 += wl * p0 * p0
            m01 += wl * p0 * p1
            m02 += wl * p0 * p2
            m11 += wl * p1 * p1
            m12 += wl * p1 * p2
            m22 += wl * p2 * p2
    return om, k00, k11, k01, m00, m01, m02, m11, m12, m22


@njit
def shape_sums_3d(i, bond_xi, offsets, wv, intact):
    """3-D sums of point i that depend on the bonds alone, without M: (omega0, K00, K11,
    K22, K01, K02, K12)."""
    om = 0.0
    k00 = k11 = k22 = k01 = k02 = k12 = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        c = np.uint64(k)
        w = wv[c] * np.float64(intact[c])
        x0 = bond_xi[c, 0]
        x1 = bond_xi[c, 1]
        x2 = bond_xi[c, 2]
        om += w
        k00 += w * x0 * x0
        k11 += w * x1 * x1
        k22 += w * x2 * x2
        k01 += w * x0 * x1
        k02 += w * x0 * x2
        k12 += w * x1 * x2
    return om, k00, k11, k22, k01, k02, k12


@njit
def lbscmm_matrix_3d(i, bond_xi, length, offsets, wv, intact, acc, base):
    """3-D LBSCMM matrix M (6 x 6, symmetric) of point i: its upper triangle into
    ``acc[base + r * 6 + c]``, c >= r."""
    m0 = m1 = m2 = m3 = m4 = m5 = m6 = m7 = m8 = m9 = m10 = 0.0
    m11 = m12 = m13 = m14 = m15 = m16 = m17 = m18 = m19 = m20 = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        c = np.uint64(k)
        w = wv[c] * np.float64(intact[c])
        x0 = bond_xi[c, 0]
        x1 = bond_xi[c, 1]
        x2 = bond_xi[c, 2]
        lk = length[c]
        wl = w / (lk * lk * lk)
        p0 = x0 * x0
        p1 = x1 * x1
        p2 = x2 * x2
        p3 = x0 * x1
        p4 = x0 * x2
        p5 = x1 * x2
        g0 = wl * p0
        g1 = wl * p1
        g2 = wl * p2
        g3 = wl * p3
        g4 = wl * p4
        m0 += g0 * p0
        m1 += g0 * p1
        m2 += g0 * p2
        m3 += g0 * p3
        m4 += g0 * p4
        m5 += g0 * p5
        m6 += g1 * p1
        m7 += g1 * p2
        m8 += g1 * p3
        m9 += g1 * p4
        m10 += g1 * p5
        m11 += g2 * p2
        m12 += g2 * p3
        m13 += g2 * p4
        m14 += g2 * p5
        m15 += g3 * p3
        m16 += g3 * p4
        m17 += g3 * p5
        m18 += g4 * p4
        m19 += g4 * p5
        m20 += wl * p5 * p5
    upper = (m0, m1, m2, m3, m4, m5, m6, m7, m8, m9, m10, m11, m12, m13, m14, m15, m16,
             m17, m18, m19, m20)  # fmt: skip
    t = 0
    for r in range(6):
        for c in range(r, 6):
            acc[base + r * 6 + c] = upper[t]
            t += 1


@njit
def motion_sums_2d(i, bond_xi, length, u, offsets, bond_j, wv, intact, mode):
    """2-D sums of point i that depend on the displacement: (N00, N01, N10, N11, q0, q1,
    q2) (q zero unless ``mode == 2``)."""
    n00 = n01 = n10 = n11 = 0.0
    q0 = q1 = q2 = 0.0
    u0, u1 = u[i, 0], u[i, 1]
    for k in range(offsets[i], offsets[i + 1]):
        c = np.uint64(k)
        j = np.uint64(bond_j[c])
        w = wv[c] * np.float64(intact[c])
        x0 = bond_xi[c, 0]
        x1 = bond_xi[c, 1]
        e0 = u[j, 0] - u0
        e1 = u[j, 1] - u1
        n00 += w * e0 * x0
        n01 += w * e0 * x1
        n10 += w * e1 * x0
        n11 += w * e1 * x1
        if mode == 2:
            lk = length[c]
            qq = w / (lk * lk * lk) * (x0 * e0 + x1 * e1)
            q0 += qq * (x0 * x0)
            q1 += qq * (x1 * x1)
            q2 += qq * (x0 * x1)
    return n00, n01, n10, n11, q0, q1, q2


@njit
def motion_sums_3d(i, bond_xi, length, u, offsets, bond_j, wv, intact, mode):
    """3-D sums of point i that depend on the displacement: (N00 .. N22, q0 .. q5) (q
    zero unless ``mode == 2``)."""
    n00 = n01 = n02 = n10 = n11 = n12 = n20 = n21 = n22 = 0.0
    q0 = q1 = q2 = q3 = q4 = q5 = 0.0
    u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
    for k in range(offsets[i], offsets[i + 1]):
        c = np.uint64(k)
        j = np.uint64(bond_j[c])
        w = wv[c] * np.float64(intact[c])
        x0 = bond_xi[c, 0]
        x1 = bond_xi[c, 1]
        x2 = bond_xi[c, 2]
        d0 = u[j, 0] - u0
        d1 = u[j, 1] - u1
        d2 = u[j, 2] - u2
        e0 = w * d0
        e1 = w * d1
        e2 = w * d2
        n00 += e0 * x0
        n01 += e0 * x1
        n02 += e0 * x2
        n10 += e1 * x0
        n11 += e1 * x1
        n12 += e1 * x2
        n20 += e2 * x0
        n21 += e2 * x1
        n22 += e2 * x2
        if mode == 2:
            lk = length[c]
            qq = w / (lk * lk * lk) * (x0 * d0 + x1 * d1 + x2 * d2)
            q0 += qq * (x0 * x0)
            q1 += qq * (x1 * x1)
            q2 += qq * (x2 * x2)
            q3 += qq * (x0 * x1)
            q4 += qq * (x0 * x2)
            q5 += qq * (x1 * x2)
    return (n00, n01, n02, n10, n11, n12, n20, n21, n22,
            q0, q1, q2, q3, q4, q5)  # fmt: skip
