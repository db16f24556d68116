"""A prototype, measured and not adopted (see ``benchmarks/locality.py`` and
docs/performance.md): the 3-D bond-based force pass over bond pairs, each pair (i, j),
i < j, evaluated once and its force applied to both ends (Newton's third law).

The pairs are the tails of the rows of the directed CSR bond list (rows sorted by
neighbour, so the bonds (i, j) with j > i of point i are ``half_start[i]:offsets[i+1]``):
no second copy of the topology. Per pair the pass reads the neighbour index, the intact
flag of the tail entry and the pair stiffness; the mirrored (j, i) entry's flag is
written only when the pair breaks.

Races: point i's row writes the force of i and of its partners j > i. Rows are cut into
blocks of consecutive points at least as long as the largest index distance of a pair
(the bandwidth), so the rows of block b write into blocks b and b + 1 only; even blocks
run in parallel, then odd blocks. The block bounds depend on the bond list alone, so
the summation order, and the bits, do not depend on the number of threads.

Equations as :mod:`peridynamics.kernels.bond_based` (Silling & Askari (2005), eqs 1-3):
the force density on i from the pair is ``k_ij g (xi + eta)`` with
``g = mu (1/|xi| - 1/|xi + eta|)``, on j ``-k_ji g (xi + eta)``, where
``k_ij = c beta V_j lambda`` is the directed stiffness of :class:`PMBForceModel`.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from peridynamics.kernels.bond_based import _filter, _stretch_of

_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
_exact = njit(cache=True)


@_exact
def half_starts(offsets, bond_j):
    """First bond of each row whose neighbour is above the row's point, shape (n,) int64,
    and -1 when some row is not sorted by neighbour (the pair pass needs sorted rows)."""
    n = offsets.shape[0] - 1
    out = np.empty(n, dtype=np.int64)
    for i in range(n):
        a, b = offsets[i], offsets[i + 1]
        for k in range(a + 1, b):
            if bond_j[k] <= bond_j[k - 1]:
                out[0] = -1
                return out
        k = a
        while k < b and bond_j[k] < i:
            k += 1
        out[i] = k
    return out


@_exact
def row_blocks(offsets, half_start, bond_j):
    """Block bounds (n_blocks + 1,) int64: consecutive rows, each block at least as long
    as the bandwidth max(j - i) of the pairs, so that a block's rows write into it and
    the next block only."""
    n = offsets.shape[0] - 1
    width = 1
    for i in range(n):
        if offsets[i + 1] > half_start[i]:
            width = max(width, bond_j[offsets[i + 1] - 1] - i)
    count = max((n + width - 1) // width, 1)
    out = np.empty(count + 1, dtype=np.int64)
    for b in range(count):
        out[b] = b * width
    out[count] = n
    return out


@_exact
def _mirror_break(offsets, half_start, bond_j, intact, i, j):
    """Clear the flag of the mirrored bond (j, i) in the head of row j."""
    for k in range(offsets[j], half_start[j]):
        if bond_j[k] == i:
            intact[k] = 0
            return


@njit(inline="always")
def _pair_3d(x, u, i, j):
    return _pair_3d_at(x, u, j, x[i, 0], x[i, 1], x[i, 2], u[i, 0], u[i, 1], u[i, 2])


@njit(inline="always")
def _pair_3d_at(x, u, j, x0, x1, x2, u0, u1, u2):
    d0 = x[j, 0] - x0
    d1 = x[j, 1] - x1
    d2 = x[j, 2] - x2
    e0 = d0 + (u[j, 0] - u0)
    e1 = d1 + (u[j, 1] - u1)
    e2 = d2 + (u[j, 2] - u2)
    inv_l = 1.0 / np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
    return e0, e1, e2, inv_l, r


@njit(inline="always")
def _row_3d(i, x, u, offsets, hs, bond_j, p0, k_ij, k_ji, intact, level, force, w):
    """Row i's pairs: their forces on i (returned) and on j (added to ``force``). The
    first loop has no scattered store (it vectorises): the forces on the partners go to
    the row scratch ``w`` (4, row length), the second loop scatters them."""
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    over = 0.0
    a0 = hs[i]
    x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
    u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
    for k in range(a0, offsets[i + 1]):
        q = np.uint64(k)
        p = np.uint64(p0 + k)
        s = np.uint64(k - a0)
        j = np.uint64(bond_j[q])
        e0, e1, e2, inv_l, r = _pair_3d_at(x, u, j, x0, x1, x2, u0, u1, u2)
        m = np.float64(intact[q])
        g = m * (inv_l - 1.0 / r)
        a = k_ij[p] * g
        f0 += a * e0
        f1 += a * e1
        f2 += a * e2
        c = k_ji[p] * g
        w[0, s] = c * e0
        w[1, s] = c * e1
        w[2, s] = c * e2
        t = (r * inv_l - level) * m
        over += t + np.abs(t)
    for k in range(a0, offsets[i + 1]):
        s = k - a0
        j = bond_j[k]
        force[j, 0] -= w[0, s]
        force[j, 1] -= w[1, s]
        force[j, 2] -= w[2, s]
    return f0, f1, f2, over


@njit(fastmath=False)
def _break_row_3d(i, x, u, offsets, hs, bond_j, p0, k_ij, k_ji, intact, s0, force, nbroken):
    """Break row i's pairs whose stretch reaches (s0_i + s0_j)/2 (the same bits as
    :func:`peridynamics.kernels.bond_based.break_trial`); returns the force the broken
    pairs had put on i, after taking theirs off each j."""
    b0 = 0.0
    b1 = 0.0
    b2 = 0.0
    for k in range(hs[i], offsets[i + 1]):
        j = bond_j[k]
        if intact[k] and _stretch_of(i, j, x, u) >= 0.5 * (s0[i] + s0[j]):
            intact[k] = 0
            _mirror_break(offsets, hs, bond_j, intact, i, j)
            nbroken[i] += 1
            nbroken[j] += 1
            e0, e1, e2, inv_l, r = _pair_3d(x, u, i, j)
            g = inv_l - 1.0 / r
            a = k_ij[p0 + k] * g
            c = k_ji[p0 + k] * g
            b0 += a * e0
            b1 += a * e1
            b2 += a * e2
            force[j, 0] += c * e0
            force[j, 1] += c * e1
            force[j, 2] += c * e2
    return b0, b1, b2


@_hot
def pair_force_3d(x, u, offsets, hs, pair_of, bond_j, k_ij, k_ji, intact, s0, s0_min,
                  blocks, force, nbroken):  # fmt: skip
    """3-D bond force density (N/m^3) with bond breaking, each pair once.

    Parameters
    ----------
    x, u : (n, 3) reference positions and displacements (m).
    offsets : (n + 1,) int64 directed CSR offsets, rows sorted by neighbour;
        hs : (n,) int64 first bond of row i with j > i (:func:`half_starts`).
    pair_of : (n,) int64: pair index of bond k of row i's tail is ``pair_of[i] + k``.
    bond_j : (n_bonds,) int32; intact : (n_bonds,) uint8 (both entries of a pair are
        cleared when it breaks).
    k_ij, k_ji : (n_pairs,) float64 pair stiffness on the lower and on the upper end
        (N/m^6 m^3); the same array when the stiffness is symmetric.
    s0, s0_min : (n,) point critical stretch and smallest in each family (``inf``: never).
    blocks : (n_blocks + 1,) int64 (:func:`row_blocks`).
    force : (n, 3) output; nbroken : (n,) int64 output, bonds broken per point.

    Returns
    -------
    int : number of directed bonds broken (two per pair).
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        force[i, 0] = 0.0
        force[i, 1] = 0.0
        force[i, 2] = 0.0
        nbroken[i] = 0
    n_blocks = blocks.shape[0] - 1
    longest = 1
    for i in range(n):
        longest = max(longest, offsets[i + 1] - hs[i])
    for phase in range(2):
        for bb in prange((n_blocks - phase + 1) // 2):
            b = 2 * bb + phase
            w = np.empty((3, longest))
            for i in range(blocks[b], blocks[b + 1]):
                level = _filter(s0_min[i])
                p0 = pair_of[i]
                f0, f1, f2, over = _row_3d(
                    i, x, u, offsets, hs, bond_j, p0, k_ij, k_ji, intact, level, force, w
                )
                if over > 0.0:
                    b0, b1, b2 = _break_row_3d(
                        i, x, u, offsets, hs, bond_j, p0, k_ij, k_ji, intact, s0, force, nbroken
                    )
                    f0 -= b0
                    f1 -= b1
                    f2 -= b2
                force[i, 0] += f0
                force[i, 1] += f1
                force[i, 2] += f2
    return nbroken.sum()
