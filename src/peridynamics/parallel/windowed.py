"""Decomposition of a grid body without the global point cloud: every rank makes only
the points it holds (its owned points and ghosts) from the body's
:class:`~peridynamics.geometry.lattice.Lattice`.

The steps (collective; every message is O(slabs + ranks + box extents), none O(points)):

1. **Masks and numbering.** The slabs of the first grid axis are shared among the ranks
   in contiguous ranges; each makes the kept-point mask of its slabs (one byte per grid
   cell of its share) and counts them, and an ``allgather`` gives every rank the first
   global id of every slab (the ids are those of the serial cloud: grid order).
2. **Partition.** Recursive coordinate bisection in index space
   (:func:`~peridynamics.parallel.grid_rcb.rcb_boxes`): every box is cut across its
   longest side between two layers of cells at the layer nearest the weighted median of
   its points, the counts per layer summed over the ranks' masks (one ``Allreduce`` per
   level of the tree). Each rank owns the points of one box; the balance is exact to a
   layer of points.
3. **Window.** A rank makes the points of its box widened by the ghost distance
   (:meth:`~peridynamics.geometry.lattice.Lattice.window`), keeps its own and, as
   ghosts, the others within the ghost distance of one of them; the owner of a ghost is
   the rank whose box holds its grid index. One ``alltoall`` agrees the halo lists.

What every rank holds beside its points (the replicated part): the first global id of
every slab of the first axis (8 bytes each) and the box of every rank (``2 dim`` int64
each); the masks of its slabs (one byte per cell of its share) live during set-up only.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.geometry.lattice import Lattice
from peridynamics.parallel.decompose import Layout, ghost_distances
from peridynamics.parallel.grid_rcb import Box, box_owner, mask_layer_counts, rcb_boxes


@dataclass(frozen=True)
class WindowedPart:
    """What :func:`windowed_layout` makes for one rank.

    Attributes
    ----------
    layout : the rank's :class:`~peridynamics.parallel.decompose.Layout`.
    x : (n_local, dim) positions of its local points (m), ``[owned | ghosts]``.
    n_family : points with a bond family (owned and first ghost layer).
    replicated_bytes : bytes of the arrays every rank holds whatever its share
        (slab ids, the boxes of the ranks).
    volume : (n_local,) nodal volumes (m^3) of its local points (the lattice's
        ``volumes_at``).
    """

    layout: Layout
    x: NDArray[np.float64]
    n_family: int
    replicated_bytes: int
    volume: NDArray[np.float64]


def windowed_layout(
    comm: Any,
    lattice: Lattice,
    search_radius: float,
    ghost_radius: float,
    ghost_families: bool = True,
) -> WindowedPart:
    """This rank's part of a lattice body (collective; arguments as in
    :func:`peridynamics.parallel.local.decompose`)."""
    from peridynamics.parallel.mpi import build_exchange_lists

    rank, size = int(comm.Get_rank()), int(comm.Get_size())
    shape = lattice.shape
    mine = np.array_split(np.arange(shape[0]), size)[rank]
    first_slab = int(mine[0]) if mine.size else 0
    masks = np.zeros((mine.size, *shape[1:]), dtype=bool)
    for k, i in enumerate(mine):
        masks[k] = lattice.kept(lattice.grid(int(i), int(i) + 1)).reshape(shape[1:])
    counts = np.concatenate(comm.allgather(masks.reshape(mine.size, -1).sum(axis=1)))
    slab_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    n_global = int(slab_start[-1])
    if n_global < size:
        raise ValueError(
            f"{n_global} points cannot be shared by {size} ranks; use fewer ranks (mpiexec -n)"
        )

    def layer_counts(requests: Sequence[tuple[Box, int]]) -> list[NDArray[np.int64]]:
        local = mask_layer_counts(masks, first_slab, requests)
        flat = np.concatenate(local) if local else np.zeros(0, np.int64)
        total = np.empty_like(flat)
        comm.Allreduce(flat, total)
        return np.split(total, np.cumsum([len(v) for v in local])[:-1])

    boxes = rcb_boxes(shape, size, layer_counts)
    lo_own, hi_own = boxes[rank]
    reach = int(np.ceil(ghost_radius / lattice.spacing)) + 1
    x, ids, index = lattice.window(
        [int(v) - reach for v in lo_own], [int(v) + reach for v in hi_own], slab_start
    )
    owner = box_owner(boxes, index)
    owned = np.flatnonzero(owner == rank)
    cand, dist = ghost_distances(x, owned, ghost_radius)
    first = dist <= search_radius * (1 + 1e-12) if ghost_families else np.zeros(len(cand), bool)
    ghosts = np.concatenate([cand[first], cand[~first]])
    local = np.concatenate([owned, ghosts])
    recv, send = build_exchange_lists(comm, owner[ghosts], ids[owned], ids[ghosts])
    layout = Layout(rank, size, n_global, ids[local], len(owned), recv, send)
    replicated = int(slab_start.nbytes + sum(lo.nbytes + hi.nbytes for lo, hi in boxes))
    volume = lattice.volumes_at(index[local])
    return WindowedPart(layout, x[local], len(owned) + int(first.sum()), replicated, volume)
