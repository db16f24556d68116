"""Horizon search: all point pairs closer than a radius, as a directed CSR list.

:func:`directed_bonds` builds the list the bond store uses: a cell-grid search
(:mod:`peridynamics.kernels.cell_search`) counts the neighbours of every point, the
final ``offsets`` / ``bond_i`` / ``bond_j`` are allocated once and filled row by row,
so the only memory beyond them is O(n_points). It gives the same arrays, bit for bit,
as :func:`directed_csr` of :func:`find_pairs` (``cKDTree.query_pairs``, then a global
sort of the doubled pair list), which stays as the test oracle: the distance test is
the same expression rounded the same way (see the kernel module), so pairs exactly at
the radius fall the same way.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

#: cells of the search grid: at most this many per point (sparse clouds get wider cells)
_CELLS_PER_POINT = 4
#: relative margin of the cell side over radius / _REACH: a pair within the radius is
#: never more than _REACH cells apart along an axis whatever the rounding of the keys
_CELL_MARGIN = 1e-6
#: cells of side radius / _REACH, scanned _REACH cells either way: fewer candidates per
#: point than cells of side radius (3: about 2.8 candidates per neighbour in 3-D)
_REACH = 3


def find_pairs(x: NDArray[np.float64], radius: float) -> NDArray[np.int64]:
    """Unordered pairs ``(i, j)``, ``i < j``, with ``|x_j - x_i| <= radius``; shape (n, 2)."""
    tree = cKDTree(x)
    pairs = tree.query_pairs(radius, output_type="ndarray")
    return np.asarray(pairs, dtype=np.int64).reshape(-1, 2)


def directed_csr(
    pairs: NDArray[np.int64], n_points: int
) -> tuple[NDArray[np.int64], NDArray[np.int32], NDArray[np.int32]]:
    """Turn unordered pairs into a full directed list sorted by (i, j).

    Returns
    -------
    offsets : (n_points + 1,) int64, bonds of point i are ``offsets[i]:offsets[i+1]``.
    bond_i, bond_j : (2 * n_pairs,) int32.
    """
    if n_points >= 2**31 - 1:
        raise ValueError("more than 2**31 points are not supported (int32 indices)")
    i = np.concatenate([pairs[:, 0], pairs[:, 1]])
    j = np.concatenate([pairs[:, 1], pairs[:, 0]])
    order = np.argsort(i * np.int64(n_points) + j, kind="stable")
    bond_i = i[order].astype(np.int32)
    bond_j = j[order].astype(np.int32)
    offsets = np.zeros(n_points + 1, dtype=np.int64)
    np.cumsum(np.bincount(bond_i, minlength=n_points), out=offsets[1:])
    return offsets, bond_i, bond_j


def directed_bonds(
    x: NDArray[np.float64], radius: float
) -> tuple[NDArray[np.int64], NDArray[np.int32], NDArray[np.int32]]:
    """Directed CSR list of every pair with ``|x_j - x_i| <= radius``, rows sorted by j.

    The same arrays as ``directed_csr(find_pairs(x, radius), len(x))`` (bit for bit,
    ties at the radius included), without the pair list or the global sort: peak memory
    is the three outputs plus O(n_points).

    Parameters
    ----------
    x : ndarray, shape (n_points, dim)
        Positions, ``dim`` in 1..3.
    radius : float
        Search radius (m); a pair at exactly ``radius`` is included.

    Returns
    -------
    offsets : ndarray, shape (n_points + 1,), int64
        Bonds of point i are ``offsets[i]:offsets[i + 1]``.
    bond_i, bond_j : ndarray, shape (n_bonds,), int32
        Owner and neighbour of every directed bond, sorted by (i, j).
    """
    from peridynamics.kernels.cell_search import count_neighbours, fill_neighbours

    x = np.ascontiguousarray(x, dtype=np.float64)
    n, dim = x.shape
    if n >= 2**31 - 1:
        raise ValueError("more than 2**31 points are not supported (int32 indices)")
    if n < 2 or not (np.isfinite(radius) and radius > 0) or not np.all(np.isfinite(x)):
        return directed_csr(find_pairs(x, radius), n)  # degenerate: the reference path
    x3, cell, xs, order, cell_start, shape, r2 = _cell_grid(x, radius)
    counts = np.empty(n, dtype=np.int64)
    count_neighbours(x3, cell, xs, order, cell_start, shape, r2, _REACH, counts)
    offsets = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    bond_i = np.empty(int(offsets[-1]), dtype=np.int32)
    bond_j = np.empty(int(offsets[-1]), dtype=np.int32)
    fill_neighbours(x3, cell, xs, order, cell_start, shape, r2, _REACH, offsets, bond_i, bond_j)
    return offsets, bond_i, bond_j


def _cell_grid(x: NDArray[np.float64], radius: float) -> tuple:
    """The cell grid of the search: padded positions (n, 3), cell keys, positions in
    cell order, that order, cell starts, cells per axis and the squared radius (the
    arguments of the count and fill kernels, in their order)."""
    n, dim = x.shape
    x3 = np.zeros((n, 3))
    x3[:, :dim] = x  # padded coordinates add +0.0 to the squared distance: no change
    cell, shape = _cell_keys(x3, radius)
    order = np.argsort(cell, kind="stable")  # each cell in increasing point index
    cell_start = np.zeros(int(np.prod(shape)) + 1, dtype=np.int64)
    np.cumsum(np.bincount(cell, minlength=len(cell_start) - 1), out=cell_start[1:])
    xs = np.ascontiguousarray(x3[order])
    r2 = float(radius) * float(radius)  # cKDTree's upper bound for p = 2
    return x3, cell, xs, order, cell_start, shape, r2


def neighbour_counts(x: NDArray[np.float64], radius: float) -> NDArray[np.int64]:
    """Number of points within ``radius`` of every point (itself excluded), shape
    (n_points,): the family sizes of :func:`directed_bonds` without building the list
    (O(n_points) memory; the domain decomposition balances ranks by it)."""
    from peridynamics.kernels.cell_search import count_neighbours

    x = np.ascontiguousarray(x, dtype=np.float64)
    n = x.shape[0]
    if n < 2:
        return np.zeros(n, dtype=np.int64)
    x3, cell, xs, order, cell_start, shape, r2 = _cell_grid(x, radius)
    counts = np.empty(n, dtype=np.int64)
    count_neighbours(x3, cell, xs, order, cell_start, shape, r2, _REACH, counts)
    return counts


def _cell_keys(
    x3: NDArray[np.float64], radius: float
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Cell key (last axis fastest) of every point and the cells per axis (3,); the cell
    side is at least ``radius / _REACH`` and the grid has at most ~4 cells per point."""
    n = x3.shape[0]
    lo = x3.min(axis=0)
    extent = x3.max(axis=0) - lo
    side = float(radius) / _REACH * (1.0 + _CELL_MARGIN)
    limit = max(_CELLS_PER_POINT * n, 64)
    while np.prod(np.floor(extent / side) + 1.0) > limit:  # sparse cloud: wider cells
        side *= 2.0
    shape = (np.floor(extent / side) + 1.0).astype(np.int64)
    key = np.zeros(n, dtype=np.int64)
    for k in range(3):  # three axes
        c = np.floor((x3[:, k] - lo[k]) / side).astype(np.int64)
        np.clip(c, 0, shape[k] - 1, out=c)
        key *= shape[k]
        key += c
    return key, shape


def bond_chunks(offsets: NDArray[np.int64], max_bonds: int) -> list[tuple[int, int]]:
    """Split the bonds ``0:offsets[-1]`` into ranges ``(a, b)`` of whole rows (a point's
    bonds never straddle two ranges) of at most ``max_bonds`` bonds each, or one row
    where a single row is longer. A per-point sum taken range by range then adds the
    same terms in the same order as over all bonds."""
    total = int(offsets[-1])
    step = max(int(max_bonds), 1)
    out: list[tuple[int, int]] = []
    a = 0
    while a < total:  # one step per range (hundreds at most), not per point
        b = int(offsets[np.searchsorted(offsets, a + step, side="right") - 1])
        if b <= a:  # one row longer than max_bonds
            b = int(offsets[np.searchsorted(offsets, a, side="right")])
        out.append((a, b))
        a = b
    return out


def brute_force_pairs(x: NDArray[np.float64], radius: float) -> NDArray[np.int64]:
    """O(n^2) reference for tests: all pairs i < j within ``radius``."""
    d2 = np.sum((x[:, None, :] - x[None, :, :]) ** 2, axis=-1)
    i, j = np.nonzero(np.triu(d2 <= radius * radius, k=1))
    return np.column_stack([i, j]).astype(np.int64)
