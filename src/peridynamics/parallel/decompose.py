"""Domain decomposition: which rank owns which point, and which points it sees as ghosts.

Every rank computes the same partition from the global point cloud (no message): a
recursive coordinate bisection (RCB; Berger & Bokhari (1987)) that cuts the longest
side of each box at the weighted median, the weight of a point being the size of its
bond family, so every rank gets about the same number of bonds (the force pass costs
per bond). A rank owns the points of its box and holds as ghosts every other point
within ``radius`` (the bond search radius, widened by the contact distance where
contact is on) of one of its owned points. Bonds are built for owned points only.

Numbering on a rank is ``[owned | ghost]``, each part in increasing global id, so a
family sorted by the global id of its neighbours is the family of the serial run in
the same order: the force on a point sums the same terms in the same order as on one
process (the bit-for-bit property the tests check).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree


def rcb_partition(
    x: NDArray[np.float64], weights: NDArray[np.float64], n_parts: int
) -> NDArray[np.int32]:
    """Part of every point, shape (n_points,), by recursive coordinate bisection.

    Parameters
    ----------
    x : (n_points, dim) positions (m).
    weights : (n_points,) work per point (its number of bonds).
    n_parts : number of parts (ranks), any positive integer; a box of k parts is cut
        into ``k // 2`` and ``k - k // 2`` parts at the weight fraction ``(k // 2) / k``.

    Returns
    -------
    part : (n_points,) int32 in ``0 .. n_parts - 1``; parts are contiguous boxes.
    """
    n = x.shape[0]
    if n_parts < 1:
        raise ValueError(f"n_parts must be >= 1, got {n_parts}")
    if n < n_parts:
        raise ValueError(
            f"{n} points cannot be shared by {n_parts} ranks; use fewer ranks (mpiexec -n)"
        )
    part = np.zeros(n, dtype=np.int32)
    stack: list[tuple[NDArray[np.intp], int, int]] = [(np.arange(n), 0, n_parts)]
    while stack:
        idx, first, k = stack.pop()
        if k == 1:
            part[idx] = first
            continue
        pts = x[idx]
        axis = int(np.argmax(pts.max(axis=0) - pts.min(axis=0)))
        # sort by the coordinate, ties by global id: the same cut on every rank
        order = np.lexsort((idx, pts[:, axis]))
        w = np.cumsum(weights[idx[order]])
        left_parts = k // 2
        target = w[-1] * left_parts / k
        cut = int(np.searchsorted(w, target, side="left")) + 1
        # move the cut to a coordinate change so a grid row is never split (tidy boxes)
        coord = pts[order, axis]
        cut = int(np.clip(cut, left_parts, len(idx) - (k - left_parts)))
        lo_cut = cut
        while 0 < lo_cut < len(idx) and coord[lo_cut - 1] == coord[lo_cut]:
            lo_cut -= 1
        hi_cut = cut
        while 0 < hi_cut < len(idx) and coord[hi_cut - 1] == coord[hi_cut]:
            hi_cut += 1
        best = min(  # the valid row boundary nearer the weighted median
            (c for c in (lo_cut, hi_cut) if left_parts <= c <= len(idx) - (k - left_parts)),
            key=lambda c: abs(w[c - 1] - target),
            default=cut,
        )
        left, right = idx[order[:best]], idx[order[best:]]
        stack.append((np.sort(left), first, left_parts))
        stack.append((np.sort(right), first + left_parts, k - left_parts))
    return part


def ghost_points(
    x: NDArray[np.float64], owned: NDArray[np.intp], radius: float
) -> NDArray[np.intp]:
    """Global ids of the points not in ``owned`` within ``radius`` of an owned point,
    sorted, shape (n_ghost,) (:func:`ghost_distances` without the distances)."""
    return ghost_distances(x, owned, radius)[0]


def ghost_distances(
    x: NDArray[np.float64], owned: NDArray[np.intp], radius: float
) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """Global ids of the points not in ``owned`` within ``radius`` of an owned point,
    sorted, shape (n_ghost,), and their distance to the nearest owned point (m).

    Parameters
    ----------
    x : (n_points, dim) global positions (m).
    owned : (n_owned,) sorted global ids of the owned points.
    radius : ghost distance (m), at least the bond search radius.
    """
    mine = np.zeros(x.shape[0], dtype=bool)
    mine[owned] = True
    lo = x[owned].min(axis=0) - radius
    hi = x[owned].max(axis=0) + radius
    near = np.all((x >= lo) & (x <= hi), axis=1) & ~mine
    cand = np.flatnonzero(near)
    if cand.size == 0:
        return cand, np.zeros(0)
    tree = cKDTree(x[owned])
    dist, _ = tree.query(x[cand], k=1, distance_upper_bound=radius * (1 + 1e-12))
    within = np.isfinite(dist)
    return cand[within], dist[within]


def find_sorted(
    sorted_ids: NDArray[np.integer], members: NDArray[np.integer]
) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """Positions of ``members`` in the sorted array ``sorted_ids`` and which of them are
    there at all (bool mask); positions of the others are meaningless."""
    pos = np.searchsorted(sorted_ids, members)
    hit = pos < len(sorted_ids)
    hit[hit] = sorted_ids[pos[hit]] == members[hit]
    return pos, hit


@dataclass(frozen=True)
class Layout:
    """What one rank holds of the global cloud.

    Attributes
    ----------
    rank, size : this rank and the number of ranks.
    n_global : number of points of the whole body (no rank holds a per-point array of
        that length: the owners of the ghosts are found when the layout is made).
    local_ids : (n_local,) global ids of the local points, owned first then ghosts.
    n_owned : number of owned points (the first ``n_owned`` local points).
    recv : ``{rank q: local indices of the ghosts q owns}`` (increasing global id).
    send : ``{rank q: local indices of owned points that are ghosts on q}``, in the
        order q receives them.
    """

    rank: int
    size: int
    n_global: int
    local_ids: NDArray[np.intp]
    n_owned: int
    recv: dict[int, NDArray[np.intp]]
    send: dict[int, NDArray[np.intp]]

    @property
    def n_local(self) -> int:
        """Owned plus ghost points."""
        return int(self.local_ids.shape[0])

    @property
    def owned_ids(self) -> NDArray[np.intp]:
        """Global ids of the owned points (sorted)."""
        return self.local_ids[: self.n_owned]

    @property
    def ghost_ids(self) -> NDArray[np.intp]:
        """Global ids of the ghost points (sorted)."""
        return self.local_ids[self.n_owned :]


def receive_lists(owners: NDArray[np.int32], n_owned: int) -> dict[int, NDArray[np.intp]]:
    """Local indices of the ghosts by owner rank (ghost local index = n_owned + k), from
    the owner rank of every ghost, shape (n_ghost,)."""
    out: dict[int, NDArray[np.intp]] = {}
    for q in np.unique(owners):
        out[int(q)] = (n_owned + np.flatnonzero(owners == q)).astype(np.intp)
    return out
