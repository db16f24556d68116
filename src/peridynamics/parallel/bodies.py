"""The decomposition of a deck with several deformable bodies: each rank owns points of
one body.

A composite model (:mod:`peridynamics.bodies.composite`) runs each body's force model
on a contiguous range of points. A rank's points are ``[owned | ghosts]``; when every
owned point belongs to one body X and the ghosts are ordered ``[X's | each other
body's]``, every body's points on the rank are contiguous and the composite model runs
unchanged. So the ranks are shared among the bodies in proportion to their work (their
bond counts, at least one rank each), and each body's points are cut among its ranks by
recursive coordinate bisection (:func:`~peridynamics.parallel.decompose.rcb_partition`).

Families: the owned points and X's first ghost layer get their bond families, as in a
one-body decomposition (:func:`~peridynamics.parallel.local.decompose`). Another body's
points reach an owned point only through interface bonds (bond-based: they read u and
v there), but its model runs on the points held here too: its first layer (within the
bond search radius of an owned point) gets families and its second layer is held, so
that model sees the same kind of local cloud as X's; a body with no point within the
search radius of an owned point is not held at all.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.search import neighbour_counts
from peridynamics.geometry.cloud import PointCloud
from peridynamics.parallel.decompose import Layout, ghost_distances, rcb_partition


def ranks_per_body(work: NDArray[np.float64], size: int) -> NDArray[np.int64]:
    """Ranks given to each body (at least one each, the rest by largest remainder of
    the work share), shape (n_bodies,); ValueError when ``size`` < number of bodies."""
    n = len(work)
    if size < n:
        raise ValueError(
            f"a deck with {n} deformable bodies runs decomposed on at least {n} ranks "
            f"(each rank owns points of one body); use mpiexec -n {n} or more, or one rank"
        )
    share = work / work.sum() * size
    ranks = np.maximum(1, np.floor(share)).astype(np.int64)
    while ranks.sum() > size:  # the minimum of one rank overshot: take from the richest
        k = int(np.argmax(np.where(ranks > 1, ranks - share, -np.inf)))
        ranks[k] -= 1
    while ranks.sum() < size:
        ranks[int(np.argmax(share - ranks))] += 1
    return ranks


def body_partition(
    x: NDArray[np.float64], weights: NDArray[np.float64], body: NDArray[np.int64], size: int
) -> NDArray[np.int32]:
    """Rank of every point, shape (n,): body k's points are cut by RCB among ranks
    ``first_k .. first_k + ranks_k - 1`` (:func:`ranks_per_body`)."""
    n_bodies = int(body.max()) + 1
    ranks = ranks_per_body(np.bincount(body, weights, n_bodies).astype(np.float64), size)
    part = np.empty(len(x), dtype=np.int32)
    first = 0
    for k in range(n_bodies):
        idx = np.flatnonzero(body == k)
        part[idx] = first + rcb_partition(x[idx], weights[idx], int(ranks[k]))
        first += int(ranks[k])
    return part


def decompose_bodies(
    comm: Any,
    cloud: PointCloud,
    body: NDArray[np.int64],
    search_radius: float,
    ghost_radius: float,
    ghost_families: bool = True,
) -> tuple[Layout, NDArray[np.bool_]]:
    """The layout of this rank and which local points get a bond family (collective).

    Parameters
    ----------
    comm : mpi4py communicator.
    cloud : the global point cloud (the same on every rank), bodies contiguous.
    body : (n_points,) int, the body index of every point (deck order, ``main`` 0).
    search_radius, ghost_radius : m, as for :func:`~peridynamics.parallel.local.decompose`.
    ghost_families : give the first ghost layer of the owned body its families.

    Returns
    -------
    layout : :class:`~peridynamics.parallel.decompose.Layout`; local points are
        ``[owned | owned body's ghosts | each other body's ghosts]``, the ghosts of a body
        first-layer first, each part in increasing global id.
    has_family : (n_local,) bool, the points whose bond families this rank builds.
    """
    from peridynamics.parallel.mpi import build_exchange_lists

    rank, size = int(comm.Get_rank()), int(comm.Get_size())
    weights = neighbour_counts(cloud.x, search_radius).astype(np.float64) + 1.0
    part = body_partition(cloud.x, weights, body, size)
    owned = np.flatnonzero(part == rank)
    mine = int(body[owned[0]])
    ghosts, dist = ghost_distances(cloud.x, owned, ghost_radius)
    near = dist <= search_radius * (1 + 1e-12)
    gb = body[ghosts]
    present = np.unique(gb[near])  # other bodies reach owned points through interfaces
    keep = (gb == mine) | np.isin(gb, present)
    ghosts, near, gb = ghosts[keep], near[keep], gb[keep]
    first = near & ((gb != mine) | ghost_families)
    rank_of_body = np.where(gb == mine, -1, gb)  # the owned body's ghosts first
    order = np.lexsort((ghosts, ~first, rank_of_body))
    ghosts, first = ghosts[order], first[order]
    recv, send = build_exchange_lists(comm, part[ghosts], owned, ghosts)
    local_ids = np.concatenate([owned, ghosts])
    layout = Layout(rank, size, cloud.n_points, local_ids, len(owned), recv, send)
    return layout, np.concatenate([np.ones(len(owned), dtype=bool), first])
