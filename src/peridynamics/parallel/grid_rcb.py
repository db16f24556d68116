"""Recursive coordinate bisection of a grid body in index space, from point counts.

The body is a grid of ``shape`` cells with some cells removed (holes, notches, the
outside of a disc). A box of the grid shared by ``k`` ranks is cut across its longest
side between two layers of cells, ``k // 2`` ranks on the lower side, at the layer
boundary whose point count is nearest the share ``(k // 2) / k`` of the box's points
(Berger & Bokhari (1987), the weights being the points); the halves are cut in turn
until every box has one rank. The counts come from a callable, so the same bisection
runs on one process (the whole body's masks) and over MPI ranks (each counts its own
slabs, one ``Allreduce`` per level of the tree: :mod:`peridynamics.parallel.windowed`).
Cuts fall between grid layers: the balance is exact to one layer of points.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

#: a box of the grid: (lower, upper) cell indices, upper exclusive, shape (dim,) each
Box = tuple[NDArray[np.int64], NDArray[np.int64]]
#: counts of points per layer along ``axis`` of each requested ``(box, axis)``
LayerCounts = Callable[[Sequence[tuple[Box, int]]], list[NDArray[np.int64]]]


def rcb_boxes(shape: Sequence[int], n_parts: int, layer_counts: LayerCounts) -> list[Box]:
    """The box of every part (rank order), shape ``(lo, hi)`` each.

    Parameters
    ----------
    shape : cells along each axis of the grid.
    n_parts : number of parts (ranks), >= 1.
    layer_counts : given a list of ``(box, axis)``, the points of the body in each
        layer of cells of the box along the axis, a vector of the box's extent along it
        (the whole body's counts, whoever computes them).

    Raises
    ------
    ValueError
        When a box must be cut for more parts than it has points or layers.
    """
    dim = len(shape)
    pending: list[tuple[Box, int, int]] = [
        ((np.zeros(dim, np.int64), np.asarray(shape, np.int64)), 0, n_parts)
    ]
    done: dict[int, Box] = {}
    while pending:
        cut = [(b, first, k) for b, first, k in pending if k > 1]
        for b, first, k in pending:
            if k == 1:
                done[first] = b
        if not cut:
            break
        axes = [int(np.argmax(b[1] - b[0])) for b, _, _ in cut]
        counts = layer_counts([(b, a) for (b, _, _), a in zip(cut, axes, strict=True)])
        pending = []
        for (box, first, k), axis, layers in zip(cut, axes, counts, strict=True):
            left = k // 2
            c = _cut_layer(np.asarray(layers, np.int64), left, k)
            lo, hi = box
            mid = lo[axis] + c
            hi_left, lo_right = hi.copy(), lo.copy()
            hi_left[axis], lo_right[axis] = mid, mid
            pending.append(((lo, hi_left), first, left))
            pending.append(((lo_right, hi), first + left, k - left))
    return [done[r] for r in range(n_parts)]


def _cut_layer(layers: NDArray[np.int64], left: int, k: int) -> int:
    """Layers of a box below the cut: the layer boundary whose points below are nearest
    ``left / k`` of the box's, each side keeping at least as many points as parts."""
    cum = np.concatenate([[0], np.cumsum(layers)])
    total = int(cum[-1])
    if total < k or len(layers) < 2:
        raise ValueError(
            f"a part of the body with {total} points in {len(layers)} layers cannot be "
            f"shared by {k} ranks; use fewer ranks (mpiexec -n)"
        )
    target = total * left / k
    j = int(np.searchsorted(cum, target, side="left"))
    best, gap = -1, np.inf
    for c in (j - 1, j):
        if 1 <= c <= len(layers) - 1 and cum[c] >= left and total - cum[c] >= k - left:
            if abs(cum[c] - target) < gap:
                best, gap = c, abs(cum[c] - target)
    if best < 0:  # the median layer holds nearly everything: the nearest valid cut
        valid = [c for c in range(1, len(layers)) if cum[c] >= left and total - cum[c] >= k - left]
        if not valid:
            raise ValueError(
                f"a part of the body with {total} points cannot be cut for {k} ranks; use "
                "fewer ranks (mpiexec -n)"
            )
        best = min(valid, key=lambda c: abs(cum[c] - target))
    return best


def box_owner(boxes: Sequence[Box], index: NDArray[np.integer]) -> NDArray[np.int32]:
    """The part whose box holds each grid index ``index`` (n, dim); -1 for none."""
    owner = np.full(len(index), -1, dtype=np.int32)
    for r, (lo, hi) in enumerate(boxes):
        owner[np.all((index >= lo) & (index < hi), axis=1)] = r
    return owner


def mask_layer_counts(
    masks: NDArray[np.bool_], first_slab: int, requests: Sequence[tuple[Box, int]]
) -> list[NDArray[np.int64]]:
    """The counts of ``LayerCounts`` from the kept-point masks of the slabs
    ``first_slab ..`` of the first axis, shape ``(slabs, *shape[1:])`` (a rank's share:
    sum the ranks' counts for the body's)."""
    out = []
    n_mine = masks.shape[0]
    for (lo, hi), axis in requests:
        counts = np.zeros(int(hi[axis] - lo[axis]), dtype=np.int64)
        a, b = max(int(lo[0]), first_slab), min(int(hi[0]), first_slab + n_mine)
        if a < b:
            rest = tuple(slice(int(p), int(q)) for p, q in zip(lo[1:], hi[1:], strict=True))
            sub = masks[(slice(a - first_slab, b - first_slab), *rest)]
            if axis == 0:
                counts[a - int(lo[0]) : b - int(lo[0])] = sub.reshape(b - a, -1).sum(axis=1)
            else:
                others = tuple(d for d in range(masks.ndim) if d != axis)
                counts[:] = sub.sum(axis=others)
        out.append(counts)
    return out
