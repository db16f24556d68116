"""Short-range repulsive contact: cell-list / Verlet-list search and force kernels.

Used by :class:`peridynamics.evaluation.short_range_contact.ShortRangeContact`, which
documents the physics.
Every pair (i, j) closer than the contact distance ``d_c`` in the CURRENT configuration
``y = x + u`` and not joined by an intact bond repels with the pair force density
(N/m^6, per volume squared)

    f_ij = -c_s (d_c - r) / d_c * e_ij,      r = |y_j - y_i|,  e_ij = (y_j - y_i) / r

so that the force density on point i is ``F_i = sum_j f_ij V_j`` (N/m^3). It derives
from the pair potential ``phi_ij = V_i V_j c_s (d_c - r)^2 / (2 d_c)`` (J), summed once
per unordered pair.

Neighbour search (standard molecular-dynamics practice, e.g. Allen & Tildesley,
*Computer Simulation of Liquids*: cell lists and Verlet lists): the current positions
are binned into cells of side >= ``d_c + skin`` identified by a linear cell key; the
points are sorted by key, so the points of a run of 3 cells along the last axis form one
contiguous slice, read from a dense table of cell starts (or, when the grid would be
huge because some point flew far away, found by two binary searches in the sorted
keys). Every pair closer than ``d_c + skin`` goes into a directed CSR Verlet list (both
(i, j) and (j, i) stored, each row sorted by j), with the index of bond (i, j) in row i
and of bond (j, i) in row j (-1 if not bonded), so the force pass reads ``intact``
directly. The force pass gathers over row i only (prange over points, no atomics).

The last two functions, :func:`contact_force_reference` and
:func:`contact_energy_reference`, are brute-force O(n^2) NumPy twins for the tests.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange
from numpy.typing import NDArray

#: the force pass is hot: fast-math as in :mod:`peridynamics.kernels.bond_based`
_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
#: list building and diagnostics: exact IEEE arithmetic, so every point takes the same
#: decision for the pair (i, j) as for (j, i)
_exact = njit(parallel=True, fastmath=False, cache=True)


@_exact
def max_displacement_sq(u, u_ref):
    """Largest squared displacement ``max_i |u_i - u_ref_i|^2`` (m^2) since the last build."""
    n, d = u.shape
    m = 0.0
    for i in prange(n):
        s = 0.0
        for c in range(d):
            a = u[i, c] - u_ref[i, c]
            s += a * a
        m = max(m, s)
    return m


@njit(cache=True)
def bounding_box(x, u, lo, hi):
    """Lower and upper corners of the current positions ``x + u`` into ``lo``, ``hi``
    (dim,); returns False if a position is not finite."""
    n, d = x.shape
    for c in range(d):
        lo[c] = np.inf
        hi[c] = -np.inf
    ok = True
    for i in range(n):
        for c in range(d):
            y = x[i, c] + u[i, c]
            if not np.isfinite(y):
                ok = False
            lo[c] = min(lo[c], y)
            hi[c] = max(hi[c], y)
    return ok


@njit(cache=True)
def cell_table(sorted_keys, cell_start):
    """Dense table: points of cell k are ``sorted_keys`` slots
    ``cell_start[k]:cell_start[k + 1]``; ``cell_start`` has n_cells + 1 entries."""
    n_cells = cell_start.shape[0] - 1
    s = 0
    for k in range(n_cells + 1):
        while s < sorted_keys.shape[0] and sorted_keys[s] < k:
            s += 1
        cell_start[k] = s


@_exact
def cell_keys(x, u, lo, inv_side, ncell, stride, coords, keys):
    """Integer cell coordinates ``coords`` (n, dim) and linear keys ``keys`` (n,) of the
    current positions ``x + u``; ``lo`` is the lower corner of their bounding box,
    ``ncell`` (dim,) the number of cells per axis and ``stride`` the key strides (last
    axis fastest, stride 1)."""
    n, d = x.shape
    for i in prange(n):
        key = 0
        for c in range(d):
            t = int(((x[i, c] + u[i, c]) - lo[c]) * inv_side)
            t = min(max(t, 0), ncell[c] - 1)
            coords[i, c] = t
            key += t * stride[c]
        keys[i] = key


@njit(inline="always")
def _lower_bound(a, lo, hi, v):
    """First index in ``a[lo:hi]`` (sorted) whose value is >= v (``hi`` if none)."""
    while lo < hi:
        mid = (lo + hi) >> 1
        if a[mid] < v:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(inline="always")
def _row_slice(i, r, coords, ncell, stride, sorted_keys, cell_start):
    """Slice of the key-sorted points lying in row ``r`` of the 3^dim cells around the
    cell of point i: the axes before the last are offset by the base-3 digits of r (each
    -1, 0 or +1), the last axis spans the 3 cells around i's. Empty if out of the grid.

    With a dense table ``cell_start`` (n_cells + 1,) the slice is read from it; with an
    empty table (sparse grid) it is found by two binary searches in ``sorted_keys``.
    """
    d = coords.shape[1]
    base = 0
    t = r
    for c in range(d - 1):
        cc = coords[i, c] + (t % 3) - 1
        t //= 3
        if cc < 0 or cc >= ncell[c]:
            return 0, 0
        base += cc * stride[c]
    cl = coords[i, d - 1]
    k0 = base + max(cl - 1, 0)
    k1 = base + min(cl + 1, ncell[d - 1] - 1) + 1
    if cell_start.shape[0] > 0:
        return cell_start[k0], cell_start[k1]
    n = sorted_keys.shape[0]
    a = _lower_bound(sorted_keys, 0, n, k0)
    b = _lower_bound(sorted_keys, a, n, k1)
    return a, b


@njit(inline="always")
def _dist_sq(i, j, x, u):
    d = x.shape[1]
    s = 0.0
    for c in range(d):
        e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
        s += e * e
    return s


@_exact
def count_candidates(
    x, u, coords, ncell, stride, order, sorted_keys, cell_start, cutoff_sq, counts
):
    """Number of points j != i with ``|y_j - y_i|^2 <= cutoff_sq`` per point, (n,)."""
    n, d = x.shape
    n_rows = 3 ** (d - 1)
    for i in prange(n):
        cnt = 0
        for r in range(n_rows):
            a, b = _row_slice(i, r, coords, ncell, stride, sorted_keys, cell_start)
            for s in range(a, b):
                j = order[s]
                if j != i and _dist_sq(i, j, x, u) <= cutoff_sq:
                    cnt += 1
        counts[i] = cnt


@njit(inline="always")
def _insertion_sort(a, key, lo, hi):
    """Sort ``a[lo:hi]`` in place by ``key[a]`` (short rows: insertion sort beats a
    general sort)."""
    for k in range(lo + 1, hi):
        v = a[k]
        m = k - 1
        while m >= lo and key[a[m]] > key[v]:
            a[m + 1] = a[m]
            m -= 1
        a[m + 1] = v


@njit(inline="always")
def _find_bond(offsets, bond_j, key, i, j):
    """Index of bond (i, j) in the CSR bond list (rows sorted by ``key[j]``), or -1."""
    lo = offsets[i]
    hi = offsets[i + 1]
    target = key[j]
    while lo < hi:  # lower bound of key[j] in key[bond_j[lo:hi]]
        mid = (lo + hi) // 2
        if key[bond_j[mid]] < target:
            lo = mid + 1
        else:
            hi = mid
    if lo < offsets[i + 1] and bond_j[lo] == j:
        return lo
    return -1


@_exact
def fill_candidates(
    x,
    u,
    coords,
    ncell,
    stride,
    order,
    sorted_keys,
    cell_start,
    cutoff_sq,
    pair_offsets,
    offsets,
    bond_j,
    pair_j,
    pair_bond_ij,
    pair_bond_ji,
    key,
):
    """Fill the Verlet list counted by :func:`count_candidates`: partner ``pair_j``
    (sorted within each row by ``key``, the global point id: a rank of a decomposed run
    sums a point's contact forces in the serial order), index of bond (i, j)
    ``pair_bond_ij`` and of bond (j, i) ``pair_bond_ji`` in the bond list (families
    sorted by ``key`` too; -1 when the two points are not bonded)."""
    n, d = x.shape
    n_rows = 3 ** (d - 1)
    for i in prange(n):
        p = pair_offsets[i]
        for r in range(n_rows):
            a, b = _row_slice(i, r, coords, ncell, stride, sorted_keys, cell_start)
            for s in range(a, b):
                j = order[s]
                if j != i and _dist_sq(i, j, x, u) <= cutoff_sq:
                    pair_j[p] = j
                    p += 1
        _insertion_sort(pair_j, key, pair_offsets[i], pair_offsets[i + 1])
        for k in range(pair_offsets[i], pair_offsets[i + 1]):
            j = pair_j[k]
            pair_bond_ij[k] = _find_bond(offsets, bond_j, key, i, j)
            pair_bond_ji[k] = _find_bond(offsets, bond_j, key, j, i)


@njit(inline="always")
def _excluded(k, pair_bond_ij, pair_bond_ji, intact):
    """True when the pair is joined by an intact bond (in either direction)."""
    b = pair_bond_ij[k]
    if b >= 0 and intact[b] != 0:
        return True
    b = pair_bond_ji[k]
    return b >= 0 and intact[b] != 0


@_hot
def add_contact_force(
    x, u, volume, pair_offsets, pair_j, pair_bond_ij, pair_bond_ji, intact, d_c, c_s, force
):
    """ADD the contact force density (N/m^3) to ``force`` (n, dim).

    F_i += -sum_j c_s (d_c - r) / d_c * (y_j - y_i) / r * V_j over the Verlet row of i,
    for r < d_c and no intact bond between i and j. Coincident points (r = 0) have no
    direction and are skipped.
    """
    n, d = x.shape
    dc_sq = d_c * d_c
    scale = c_s / d_c
    for i in prange(n):
        for k in range(pair_offsets[i], pair_offsets[i + 1]):
            j = pair_j[k]
            r2 = _dist_sq(i, j, x, u)
            if r2 >= dc_sq or r2 == 0.0:
                continue
            if _excluded(k, pair_bond_ij, pair_bond_ji, intact):
                continue
            r = np.sqrt(r2)
            g = scale * (d_c - r) / r * volume[j]
            for c in range(d):
                force[i, c] -= g * ((x[j, c] - x[i, c]) + (u[j, c] - u[i, c]))


@_exact
def contact_energy_density(
    x, u, volume, pair_offsets, pair_j, pair_bond_ij, pair_bond_ji, intact, d_c, c_s, w, count
):
    """Point share of the contact energy ``w_i = c_s / (4 d_c) sum_j V_j (d_c - r)^2``
    (J/m^3), so that the energy is ``sum_i V_i w_i``, and the number of contacts of each
    point ``count`` (n,)."""
    n = x.shape[0]
    dc_sq = d_c * d_c
    for i in prange(n):
        acc = 0.0
        cnt = 0
        for k in range(pair_offsets[i], pair_offsets[i + 1]):
            j = pair_j[k]
            r2 = _dist_sq(i, j, x, u)
            if r2 >= dc_sq or _excluded(k, pair_bond_ij, pair_bond_ji, intact):
                continue
            g = d_c - np.sqrt(r2)
            acc += volume[j] * g * g
            cnt += 1
        w[i] = 0.25 * c_s / d_c * acc
        count[i] = cnt


# -- brute-force NumPy twins (tests) -----------------------------------------------------


def _reference_pairs(
    x: NDArray, u: NDArray, offsets: NDArray, bond_j: NDArray, intact: NDArray, d_c: float
) -> tuple[NDArray, NDArray, NDArray]:
    """All-pairs (n, n, dim) deformed vectors, distances and the contact mask."""
    n = x.shape[0]
    e = (x[None, :, :] - x[:, None, :]) + (u[None, :, :] - u[:, None, :])
    r = np.sqrt(np.sum(e * e, axis=-1))
    bonded = np.zeros((n, n), dtype=bool)
    bond_i = np.repeat(np.arange(n), np.diff(offsets))
    on = np.asarray(intact) != 0
    bonded[bond_i[on], bond_j[on]] = True
    bonded |= bonded.T  # an intact bond in either direction excludes the pair
    mask = (r < d_c) & ~bonded
    np.fill_diagonal(mask, False)
    return e, r, mask


def contact_force_reference(
    x: NDArray,
    u: NDArray,
    volume: NDArray,
    offsets: NDArray,
    bond_j: NDArray,
    intact: NDArray,
    d_c: float,
    c_s: float,
) -> NDArray[np.float64]:
    """Brute-force O(n^2) NumPy contact force density (N/m^3), shape (n, dim)."""
    e, r, mask = _reference_pairs(x, u, offsets, bond_j, intact, d_c)
    mask &= r > 0
    g = np.zeros_like(r)
    g[mask] = c_s * (d_c - r[mask]) / (d_c * r[mask])
    g *= volume[None, :]
    return -np.einsum("ij,ijc->ic", g, e)


def contact_energy_reference(
    x: NDArray,
    u: NDArray,
    volume: NDArray,
    offsets: NDArray,
    bond_j: NDArray,
    intact: NDArray,
    d_c: float,
    c_s: float,
) -> float:
    """Brute-force contact energy sum over unordered pairs V_i V_j c_s (d_c - r)^2 / (2 d_c)
    (J)."""
    _, r, mask = _reference_pairs(x, u, offsets, bond_j, intact, d_c)
    phi = np.where(mask, (d_c - r) ** 2, 0.0) * np.outer(volume, volume)
    return float(0.5 * c_s / (2.0 * d_c) * np.sum(phi))
