"""Micropolar bond-based force and energy kernels (2-D, small deformation).

Every kernel has a NumPy twin in :mod:`peridynamics.kernels.reference_micropolar`.
Bond k = (i, j) with unit vectors n = xi/|xi|, n_perp = (-n_y, n_x), weight
``w_k = G_k beta_k V_j`` (surface correction times partial volume, m^3) and the springs
k_n, k_t, k_phi (N/m^6) of :mod:`peridynamics.families.micropolar.material`:

    l = (u_j - u_i).n / xi,   gamma = (u_j - u_i).n_perp / xi - (theta_i + theta_j)/2,
    phi = theta_j - theta_i,
    f_i = sum_k w_k (k_n l n + k_t gamma n_perp)                     (N/m^3)
    m_i = sum_k w_k xi (k_t gamma / 2 + k_phi phi)                   (N m/m^3)
    W_i = 1/4 sum_k w_k xi (k_n l^2 + k_t gamma^2 + k_phi phi^2)     (J/m^3)

so that V_i f_i = -dE/du_i and V_i m_i = -dE/dtheta_i for E = sum_i W_i V_i when
V_i w_ij = V_j w_ji (Zhou, Zhu & Li (n.d.), eqs 7-12; Diana & Casolo 2019).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
_exact = njit(parallel=True, fastmath=False, cache=True)


@_hot
def force_2d(
    x, u, theta, offsets, bond_j, inv_length, weight, intact, kn, kt, kphi, force, moment,
    max_stretch,
):  # fmt: skip
    """Force density (N/m^3) into ``force`` (n, 2), moment density (N m/m^3) into
    ``moment`` (n, 1) and the largest axial stretch of an intact bond into
    ``max_stretch`` (n,); ``theta`` is (n, 1) (rad)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        xi0, xi1, ui0, ui1, ti = x[i, 0], x[i, 1], u[i, 0], u[i, 1], theta[i, 0]
        f0 = 0.0
        f1 = 0.0
        m = 0.0
        smax = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k] == 0:
                continue
            j = bond_j[k]
            il = inv_length[k]
            n0 = (x[j, 0] - xi0) * il
            n1 = (x[j, 1] - xi1) * il
            d0 = u[j, 0] - ui0
            d1 = u[j, 1] - ui1
            tj = theta[j, 0]
            stretch = (d0 * n0 + d1 * n1) * il
            gamma = (d1 * n0 - d0 * n1) * il - 0.5 * (ti + tj)
            w = weight[k]
            fn = w * kn * stretch
            ft = w * kt * gamma
            f0 += fn * n0 - ft * n1
            f1 += fn * n1 + ft * n0
            m += w * (0.5 * kt * gamma + kphi * (tj - ti)) / il
            smax = max(smax, stretch)
        force[i, 0] = f0
        force[i, 1] = f1
        moment[i, 0] = m
        max_stretch[i] = smax


@_exact
def energy_density_2d(x, u, theta, offsets, bond_j, inv_length, weight, intact, kn, kt, kphi, out):
    """W_i (J/m^3) into ``out`` (n,)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k] == 0:
                continue
            j = bond_j[k]
            il = inv_length[k]
            n0 = (x[j, 0] - x[i, 0]) * il
            n1 = (x[j, 1] - x[i, 1]) * il
            d0 = u[j, 0] - u[i, 0]
            d1 = u[j, 1] - u[i, 1]
            stretch = (d0 * n0 + d1 * n1) * il
            gamma = (d1 * n0 - d0 * n1) * il - 0.5 * (theta[i, 0] + theta[j, 0])
            phi = theta[j, 0] - theta[i, 0]
            acc += weight[k] * (kn * stretch**2 + kt * gamma**2 + kphi * phi**2) / il
        out[i] = 0.25 * acc


@_exact
def axial_stretch_2d(x, u, offsets, bond_j, inv_length, out):
    """Linearised axial stretch l of every directed bond into ``out`` (n_bonds,)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            il = inv_length[k]
            out[k] = (
                (u[j, 0] - u[i, 0]) * (x[j, 0] - x[i, 0])
                + (u[j, 1] - u[i, 1]) * (x[j, 1] - x[i, 1])
            ) * (il * il)


@_exact
def pair_stretch_2d(x, u, bond_i, bond_j, inv_length, index, out):
    """Linearised axial stretch l of the directed bonds ``index`` (m,) into ``out``
    (m,): the same numbers as :func:`axial_stretch_2d` at those bonds."""
    for c in prange(index.shape[0]):
        k = index[c]
        i = bond_i[k]
        j = bond_j[k]
        il = inv_length[k]
        out[c] = (
            (u[j, 0] - u[i, 0]) * (x[j, 0] - x[i, 0]) + (u[j, 1] - u[i, 1]) * (x[j, 1] - x[i, 1])
        ) * (il * il)


@njit(fastmath=False, cache=True)
def _block_sum(buf, q, lo, n):
    """NumPy's ``pairwise_sum`` of ``buf[lo:lo + n, q]`` for n <= 128: sequential
    below 8 terms, else 8 interleaved partial sums combined as a tree."""
    if n < 8:
        res = 0.0
        for t in range(lo, lo + n):
            res += buf[t, q]
        return res
    r0, r1, r2, r3 = buf[lo, q], buf[lo + 1, q], buf[lo + 2, q], buf[lo + 3, q]
    r4, r5, r6, r7 = buf[lo + 4, q], buf[lo + 5, q], buf[lo + 6, q], buf[lo + 7, q]
    t = 8
    while t < n - (n % 8):
        b = lo + t
        r0 += buf[b, q]
        r1 += buf[b + 1, q]
        r2 += buf[b + 2, q]
        r3 += buf[b + 3, q]
        r4 += buf[b + 4, q]
        r5 += buf[b + 5, q]
        r6 += buf[b + 6, q]
        r7 += buf[b + 7, q]
        t += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while t < n:
        res += buf[lo + t, q]
        t += 1
    return res


@njit(fastmath=False, cache=True)
def _pairwise(buf, q, lo, n):
    """Sum of ``buf[lo:lo + n, q]`` in NumPy's pairwise order (its ``pairwise_sum``:
    blocks of at most 128 terms by :func:`_block_sum`, longer ranges split in halves
    (a multiple of 8 first) and the halves added), so that a kernel's family sum has
    the bits of ``np.add.reduceat``. The halving is walked with an explicit stack."""
    if n <= 128:
        return _block_sum(buf, q, lo, n)
    los = np.empty(64, dtype=np.int64)
    ns = np.empty(64, dtype=np.int64)
    stage = np.zeros(64, dtype=np.int64)  # 0: split next, 1: left half pending
    left = np.empty(64)
    sp = 0
    los[0] = lo
    ns[0] = n
    ret = 0.0
    done = False  # ret holds the sum of the range just finished
    while True:
        if done:
            if sp < 0:
                return ret
            if stage[sp] == 1:  # the left half is done: walk the right one
                left[sp] = ret
                stage[sp] = 2
                half = ns[sp] // 2
                half -= half % 8
                los[sp + 1] = los[sp] + half
                ns[sp + 1] = ns[sp] - half
                stage[sp + 1] = 0
                sp += 1
                done = False
            else:  # both halves done
                ret = left[sp] + ret
                sp -= 1
            continue
        if ns[sp] <= 128:
            ret = _block_sum(buf, q, los[sp], ns[sp])
            sp -= 1
            done = True
            continue
        half = ns[sp] // 2
        half -= half % 8
        stage[sp] = 1
        los[sp + 1] = los[sp]
        ns[sp + 1] = half
        stage[sp + 1] = 0
        sp += 1


@_exact
def tangent_csr_2d(
    x, volume, offsets, bond_j, inv_length, weight, intact, kn, kt, kphi, keep, indptr,
    indices, data,
):  # fmt: skip
    """The tangent (N/m, N, N m) as CSR arrays with sorted column indices, dof order
    [u_x, u_y, theta] per point: block row i holds the diagonal block (the family sum
    of the (i, i) parts of the pair stiffnesses k_ij) and the (i, j) parts of its bonds
    with ``keep`` (bool, n_bonds), in the order of j; ``indptr`` (3n + 1,) is given
    (3 (1 + kept bonds) entries a row), ``indices`` and ``data`` are filled.

    The same numbers, in the same order of operations, as the NumPy
    :meth:`peridynamics.families.micropolar.force.MicropolarForceModel.bond_blocks`
    (the 6 x 6 blocks), their family sum by ``np.add.reduceat`` (the first block plus
    the pairwise sum of the others, ``_pairwise``) and
    :func:`peridynamics.families.assembly.block_csr` with sorted indices."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        lo = offsets[i]
        m = offsets[i + 1] - lo
        buf = np.empty((m, 9))  # the (i, i) parts of the family's blocks
        blocks = np.empty((m + 1, 3, 3))  # [diagonal, the (i, j) parts]
        cols = np.empty(m + 1, dtype=np.int64)
        cols[0] = i
        bl = np.zeros(6)
        bg = np.zeros(6)
        kept = 0
        for t in range(m):
            k = lo + t
            j = bond_j[k]
            il = inv_length[k]
            n0 = (x[j, 0] - x[i, 0]) * il
            n1 = (x[j, 1] - x[i, 1]) * il
            bl[0] = -n0 * il
            bl[1] = -n1 * il
            bl[3] = n0 * il
            bl[4] = n1 * il
            p0 = -n1 * il
            p1 = n0 * il
            bg[0] = -p0
            bg[1] = -p1
            bg[2] = -0.5
            bg[3] = p0
            bg[4] = p1
            bg[5] = -0.5
            scale = weight[k] * np.float64(intact[k]) * volume[i] / il
            sl = kn * scale
            sg = kt * scale
            kp = kphi * scale
            if keep[k]:
                kept += 1
                cols[kept] = j
            for a in range(3):
                for c in range(6):
                    v = sl * bl[a] * bl[c] + sg * bg[a] * bg[c]
                    if a == 2 and c == 2:
                        v += kp
                    elif a == 2 and c == 5:
                        v -= kp
                    if c < 3:
                        buf[t, 3 * a + c] = v
                    elif keep[k]:
                        blocks[kept, a, c - 3] = v
        for q in range(9):
            blocks[0, q // 3, q % 3] = buf[0, q] + _pairwise(buf, q, 1, m - 1) if m else 0.0
        order = np.argsort(cols[: kept + 1])
        for a in range(3):
            pos = indptr[3 * i + a]
            for b in order:
                for c in range(3):
                    indices[pos] = 3 * cols[b] + c
                    data[pos] = blocks[b, a, c]
                    pos += 1
