"""Fixed-radius neighbour search on a cell grid: Numba kernels of
:func:`peridynamics.bonds.search.directed_bonds`.

The points (padded to three coordinates with zeros) are bucketed into a dense grid of
cells of side ``>= radius / reach`` (keys with the last axis fastest; the points sorted
by key, stable, so each cell holds its points in increasing index;
``cell_start[k]:cell_start[k + 1]`` the slots of cell k). Per point i (prange, no
atomics) the ``(2 reach + 1)^2`` runs of ``2 reach + 1`` cells along the last axis
around its cell are scanned, and every other point j with

    d = (x_i0 - x_j0)^2 + (x_i1 - x_j1)^2 + (x_i2 - x_j2)^2 <= radius^2

(summed left to right, no fused multiply-add: the expression and the order of
``scipy.spatial.cKDTree.query_pairs``'s leaf test, so ties at the radius fall the same
way; a padded zero coordinate adds ``+0.0``, which changes no sum) is a neighbour. A
first pass counts, a second writes row i of the directed CSR list and sorts it by j
(often sorted already: each cell holds its points in increasing index).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange
from numpy.typing import NDArray

# strict floating point (no contraction to fused multiply-add): the distance must be
# rounded exactly as cKDTree rounds it
_search = njit(parallel=True, fastmath=False, error_model="numpy", cache=True)


@njit(inline="always")
def _sort_row(a: NDArray[np.int32], lo: int, hi: int) -> None:
    """Sort ``a[lo:hi]`` in place: nothing to do when sorted (a grid whose index runs
    like the cell keys), insertion sort for short rows (each cell's run is already
    sorted), quicksort for long ones."""
    for s in range(lo + 1, hi):
        if a[s - 1] > a[s]:
            break
    else:
        return
    if hi - lo > 64:
        a[lo:hi].sort()
        return
    for s in range(lo + 1, hi):
        v = a[s]
        t = s - 1
        while t >= lo and a[t] > v:
            a[t + 1] = a[t]
            t -= 1
        a[t + 1] = v


@_search
def count_neighbours(
    x: NDArray[np.float64],
    cell: NDArray[np.int64],
    xs: NDArray[np.float64],
    order: NDArray[np.int64],
    cell_start: NDArray[np.int64],
    shape: NDArray[np.int64],
    r2: float,
    reach: int,
    counts: NDArray[np.int64],
) -> None:
    """``counts[i]`` = number of points j != i with ``d(i, j) <= r2`` (see module).

    Parameters
    ----------
    x : (n, 3) positions, padded with zero columns.
    cell : (n,) cell key of every point.
    xs : (n, 3) positions sorted by cell key (``x[order]``).
    order : (n,) point index of every sorted slot.
    cell_start : (n_cells + 1,) first slot of every cell.
    shape : (3,) cells along each axis.
    r2 : squared radius (``radius * radius``).
    reach : cells scanned either way along each axis (cell side >= radius / reach).
    counts : (n,) output.
    """
    n1, n2 = shape[1], shape[2]
    n0 = shape[0]
    for i in prange(x.shape[0]):
        c = cell[i]
        c2 = c % n2
        c1 = (c // n2) % n1
        c0 = c // (n1 * n2)
        x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
        lo2, hi2 = max(c2 - reach, 0), min(c2 + reach, n2 - 1)
        k = 0
        for a in range(max(c0 - reach, 0), min(c0 + reach, n0 - 1) + 1):
            for b in range(max(c1 - reach, 0), min(c1 + reach, n1 - 1) + 1):
                base = (a * n1 + b) * n2
                for s in range(cell_start[base + lo2], cell_start[base + hi2 + 1]):
                    d0 = x0 - xs[s, 0]
                    d1 = x1 - xs[s, 1]
                    d2 = x2 - xs[s, 2]
                    if d0 * d0 + d1 * d1 + d2 * d2 <= r2 and order[s] != i:
                        k += 1
        counts[i] = k


@_search
def fill_neighbours(
    x: NDArray[np.float64],
    cell: NDArray[np.int64],
    xs: NDArray[np.float64],
    order: NDArray[np.int64],
    cell_start: NDArray[np.int64],
    shape: NDArray[np.int64],
    r2: float,
    reach: int,
    offsets: NDArray[np.int64],
    bond_i: NDArray[np.int32],
    bond_j: NDArray[np.int32],
) -> None:
    """Write the neighbours of point i, sorted, into ``bond_j[offsets[i]:offsets[i + 1]]``
    and i into the same slots of ``bond_i`` (the same test and arguments as
    :func:`count_neighbours`; ``offsets`` from its counts)."""
    n1, n2 = shape[1], shape[2]
    n0 = shape[0]
    for i in prange(x.shape[0]):
        c = cell[i]
        c2 = c % n2
        c1 = (c // n2) % n1
        c0 = c // (n1 * n2)
        x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
        lo2, hi2 = max(c2 - reach, 0), min(c2 + reach, n2 - 1)
        p = offsets[i]
        for a in range(max(c0 - reach, 0), min(c0 + reach, n0 - 1) + 1):
            for b in range(max(c1 - reach, 0), min(c1 + reach, n1 - 1) + 1):
                base = (a * n1 + b) * n2
                for s in range(cell_start[base + lo2], cell_start[base + hi2 + 1]):
                    d0 = x0 - xs[s, 0]
                    d1 = x1 - xs[s, 1]
                    d2 = x2 - xs[s, 2]
                    if d0 * d0 + d1 * d1 + d2 * d2 <= r2 and order[s] != i:
                        bond_j[p] = order[s]
                        p += 1
        _sort_row(bond_j, offsets[i], p)
        bond_i[offsets[i] : p] = i
