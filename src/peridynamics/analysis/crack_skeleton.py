"""The skeleton of one crack's cluster: the branch polylines of
:func:`peridynamics.analysis.crack_path.extract_crack_paths` (steps 1-4 of that module's
doc). The points are binned by their geodesic distance g from the seed, each bin is
split into connected pieces, each piece hangs from the piece holding the Dijkstra
predecessor of its nearest point, and a branch is the chain of piece centroids from the
seed to a leaf, closed by the leaf's farthest point.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse import csgraph

from peridynamics.analysis.crack_polyline import arc_lengths

__all__ = ["crack_branches"]


class _Pieces(NamedTuple):
    """The level-set pieces of one cluster, each array indexed by piece except ``piece``."""

    piece: NDArray[np.intp]  # piece of each cluster point
    centroid: NDArray[np.float64]  # (n_pc, dim)
    first: NDArray[np.intp]  # its nearest (min g) cluster point
    last: NDArray[np.intp]  # its farthest (max g) cluster point
    parent: NDArray[np.intp]  # the piece it hangs from; -1: from the seed
    level: NDArray[np.intp]  # its bin of g
    g_min: NDArray[np.float64]  # g of its nearest point
    reach: NDArray[np.float64]  # g of its farthest point (then of its subtree's)


def _pieces(
    pts: NDArray[np.float64],
    pairs: NDArray[np.intp],
    members: NDArray[np.intp],
    g: NDArray[np.float64],
    pred_all: NDArray[np.int32],
    width: float,
) -> _Pieces:
    """Level-set pieces: bins of g split into connected components, and their tree."""
    dim = pts.shape[1]
    m = pts.shape[0]
    k = members.size
    local = np.full(m, -1, dtype=np.intp)
    local[members] = np.arange(k)
    pred = pred_all[members]
    pred_local = np.where(pred >= m, -1, local[np.clip(pred, 0, m - 1)])  # -1: the seed

    b = np.floor(g / width).astype(np.intp)
    pl = local[pairs]  # pairs in cluster-local numbering (-1 if outside)
    pl = pl[(pl[:, 0] >= 0) & (pl[:, 1] >= 0)]
    ps = pl[b[pl[:, 0]] == b[pl[:, 1]]]
    sub = sp.coo_matrix((np.ones(ps.shape[0]), (ps[:, 0], ps[:, 1])), shape=(k, k)).tocsr()
    n_pc, piece = csgraph.connected_components(sub, directed=False)
    counts = np.bincount(piece, minlength=n_pc).astype(np.float64)
    cen = (
        np.stack(
            [np.bincount(piece, weights=pts[members, j], minlength=n_pc) for j in range(dim)],
            axis=1,
        )
        / counts[:, None]
    )
    # nearest (min g) and farthest (max g) point of each piece
    order = np.lexsort((g, piece))
    first = order[np.searchsorted(piece[order], np.arange(n_pc), side="left")]
    last = order[np.searchsorted(piece[order], np.arange(n_pc), side="right") - 1]
    p_near = pred_local[first]
    parent = np.where(p_near < 0, -1, piece[np.maximum(p_near, 0)])
    pbin = b[first]
    g_min = g[first]
    reach = g[last].copy()  # becomes the farthest g below each piece
    return _Pieces(piece, cen, first, last, parent, pbin, g_min, reach)


def _best_child(pc: _Pieces) -> NDArray[np.intp]:
    """Subtree reach (``pc.reach`` updated in place, bin by bin from the far end) and the
    best child of every piece: the child reaching farthest (-1: a leaf)."""
    parent, pbin, reach = pc.parent, pc.level, pc.reach
    n_pc = parent.size
    by_bin = np.argsort(pbin, kind="stable")
    bounds = np.searchsorted(pbin[by_bin], np.arange(pbin.max() + 2))
    for level in range(int(pbin.max()), 0, -1):  # over bins (path vertices)
        pcs = by_bin[bounds[level] : bounds[level + 1]]
        has = parent[pcs] >= 0
        np.maximum.at(reach, parent[pcs[has]], reach[pcs[has]])
    best_child = np.full(n_pc, -1, dtype=np.intp)
    child = np.flatnonzero(parent >= 0)
    if child.size:
        o = np.lexsort((reach[child], parent[child]))
        c_sorted = child[o]
        par_sorted = parent[c_sorted]
        is_last = np.r_[par_sorted[1:] != par_sorted[:-1], True]
        best_child[par_sorted[is_last]] = c_sorted[is_last]
    return best_child


def _chains(pc: _Pieces, best_child: NDArray[np.intp], tip_piece: int, min_branch: float) -> list:
    """Chains of pieces of the main branch (to ``tip_piece``) and of every side branch
    reaching at least ``min_branch`` beyond its junction, in the order they are found."""
    parent, reach = pc.parent, pc.reach

    def chain_up(p: int) -> list[int]:
        chain = []
        while p >= 0:  # over path vertices
            chain.append(p)
            p = int(parent[p])
        return chain[::-1]

    def chain_down(p: int) -> list[int]:
        chain = []
        while p >= 0:  # over path vertices
            chain.append(p)
            p = int(best_child[p])
        return chain

    main = chain_up(tip_piece)
    chains = [main]
    on_path = np.zeros(parent.size, dtype=bool)
    on_path[main] = True
    long_enough = (reach - pc.g_min) >= min_branch
    while True:  # over branches kept
        hang = np.where(parent >= 0, on_path[np.maximum(parent, 0)], True)  # from a path
        roots = np.flatnonzero(hang & ~on_path & long_enough)  # or from the seed
        if roots.size == 0:
            break
        r = int(roots[np.argmax(reach[roots])])
        down = chain_down(r)
        chains.append((chain_up(int(parent[r])) if parent[r] >= 0 else []) + down)
        on_path[down] = True
    return chains


def crack_branches(
    pts: NDArray[np.float64],
    pairs: NDArray[np.intp],
    members: NDArray[np.intp],
    g_all: NDArray[np.float64],
    pred_all: NDArray[np.int32],
    start: NDArray[np.float64],
    spacing: float,
    width: float,
    min_branch: float,
) -> tuple[list[NDArray[np.float64]], NDArray[np.float64], int]:
    """Branch polylines of one seed's cluster.

    Parameters
    ----------
    pts : ndarray, shape (m, dim)
        The cracked points, m.
    pairs : ndarray of int, shape (p, 2)
        Neighbour pairs of ``pts``.
    members : ndarray of int, shape (k,)
        The seed's cluster (indices into ``pts``).
    g_all, pred_all : ndarray, shape (m + n_seeds,)
        Geodesic distance from the seed (m) and shortest-path predecessor of every node
        (a predecessor ``>= m`` is a virtual seed node).
    start : ndarray, shape (dim,)
        Start of every polyline, m.
    spacing, width, min_branch : float
        Grid spacing, bin width and shortest side branch kept, m.

    Returns
    -------
    lines : list of ndarray, each shape (k_b, dim)
        The main branch first, then the side branches by decreasing length, m.
    lengths : ndarray, shape (n_branches,)
        Their lengths, m.
    tip : int
        Index into ``pts`` of the main branch's tip.
    """
    g = g_all[members]
    pc = _pieces(pts, pairs, members, g, pred_all, width)
    best_child = _best_child(pc)
    chains = _chains(pc, best_child, int(pc.piece[int(np.argmax(g))]), min_branch)

    def polyline(chain: list[int]) -> NDArray[np.float64]:
        tip_pt = pts[members[pc.last[chain[-1]]]]
        v = np.vstack([start[None, :], pc.centroid[chain], tip_pt[None, :]])
        step = np.linalg.norm(np.diff(v, axis=0), axis=1)
        return v[np.r_[True, step > 1e-9 * spacing]]  # no zero-length segments

    lines = [polyline(c) for c in chains]
    lengths = np.array([arc_lengths(v)[-1] for v in lines])
    order_b = np.r_[0, 1 + np.argsort(-lengths[1:], kind="stable")].astype(np.intp)
    lines = [lines[i] for i in order_b]
    lengths = lengths[order_b]
    return lines, lengths, int(members[pc.last[chains[0][-1]]])
