"""Decomposition of a grid body without the global point cloud: every rank makes only
the points it holds (its owned points and ghosts) from the body's
:class:`~peridynamics.geometry.lattice.Lattice`.

The steps (collective; every message is O(slabs + blocks + ranks), none O(points)):

1. **Numbering.** The slabs of the first grid axis are shared among the ranks; each
   counts the kept points of its slabs, and an ``allgather`` gives every rank the first
   global id of every slab (the ids are those of the serial cloud: grid order).
2. **Weights.** The grid is cut into coarse blocks of ``b`` cells a side
   (:func:`block_side`); each rank counts the kept points per block over its slabs and
   an ``Allreduce`` sums them.
3. **Partition.** The recursive coordinate bisection of
   :func:`~peridynamics.parallel.decompose.rcb_partition` runs on the non-empty blocks
   (their centres, weighted by their point counts): every rank owns the points of its
   blocks, about the same number each.
4. **Window.** A rank makes the points of its blocks' bounding box widened by the
   ghost distance (:meth:`~peridynamics.geometry.lattice.Lattice.window`), keeps its own
   and, as ghosts, the others within the ghost distance of one of them; the owner of a
   ghost is the owner of its block. One ``alltoall`` agrees the halo lists.

What every rank holds beside its points (the replicated part): the slab counts (8 bytes
per slab of the first axis) and the block owners and counts (12 bytes per block; about
``512 N`` blocks for N ranks, at least 8 cells a block).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.geometry.lattice import Lattice
from peridynamics.parallel.decompose import Layout, ghost_distances, rcb_partition

#: blocks per rank the partition aims at (finer blocks balance better, cost more memory)
BLOCKS_PER_RANK = 512


def block_side(shape: tuple[int, ...], ranks: int) -> int:
    """Cells along each side of a partition block: about :data:`BLOCKS_PER_RANK` blocks
    per rank, at least one cell, at most the longest side."""
    cells = float(np.prod(np.asarray(shape, dtype=np.float64)))
    side = int((cells / (BLOCKS_PER_RANK * ranks)) ** (1.0 / len(shape)))
    return int(np.clip(side, 1, max(shape)))


@dataclass(frozen=True)
class WindowedPart:
    """What :func:`windowed_layout` makes for one rank.

    Attributes
    ----------
    layout : the rank's :class:`~peridynamics.parallel.decompose.Layout`.
    x : (n_local, dim) positions of its local points (m), ``[owned | ghosts]``.
    n_family : points with a bond family (owned and first ghost layer).
    replicated_bytes : bytes of the arrays every rank holds whatever its share
        (slab ids, block owners and counts).
    """

    layout: Layout
    x: NDArray[np.float64]
    n_family: int
    replicated_bytes: int


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
    counts = np.concatenate(comm.allgather(lattice.slab_counts(mine)))
    slab_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    n_global = int(slab_start[-1])
    if n_global < size:
        raise ValueError(
            f"{n_global} points cannot be shared by {size} ranks; use fewer ranks (mpiexec -n)"
        )
    side = block_side(shape, size)
    local_counts = lattice.block_counts(mine, side)
    block_counts = np.empty_like(local_counts)
    comm.Allreduce(local_counts, block_counts)
    block_part = _partition_blocks(block_counts, side, size)
    lo_b, hi_b = _owned_box(block_part, rank)
    reach = int(np.ceil(ghost_radius / lattice.spacing)) + 1
    lo = [int(v) * side - reach for v in lo_b]
    hi = [int(v) * side + reach for v in hi_b]
    x, ids, index = lattice.window(lo, hi, slab_start)
    owner = block_part[tuple((index // side).T)]
    is_owned = owner == rank
    owned = np.flatnonzero(is_owned)
    cand, dist = ghost_distances(x, owned, ghost_radius)
    first = dist <= search_radius * (1 + 1e-12) if ghost_families else np.zeros(len(cand), bool)
    ghosts = np.concatenate([cand[first], cand[~first]])
    local = np.concatenate([owned, ghosts])
    recv, send = build_exchange_lists(comm, owner[ghosts], ids[owned], ids[ghosts])
    layout = Layout(rank, size, n_global, ids[local], len(owned), recv, send)
    replicated = int(slab_start.nbytes + block_counts.nbytes + block_part.nbytes)
    return WindowedPart(layout, x[local], len(owned) + int(first.sum()), replicated)


def _partition_blocks(counts: NDArray[np.int64], side: int, size: int) -> NDArray[np.int32]:
    """Owner rank of every block (-1 for empty blocks), shape ``counts.shape``: the
    recursive coordinate bisection of the non-empty blocks weighted by their points."""
    full = np.flatnonzero(counts.reshape(-1) > 0)
    if full.size < size:
        raise ValueError(
            f"the body has {full.size} non-empty partition blocks of {side} cells a side "
            f"for {size} ranks; use fewer ranks (mpiexec -n)"
        )
    centres = np.column_stack(np.unravel_index(full, counts.shape)).astype(np.float64)
    weights = counts.reshape(-1)[full].astype(np.float64)
    part = np.full(counts.size, -1, dtype=np.int32)
    part[full] = rcb_partition(centres, weights, size)
    return part.reshape(counts.shape)


def _owned_box(block_part: NDArray[np.int32], rank: int) -> tuple[NDArray[np.intp], ...]:
    """Block index bounds ``[lo, hi)`` of the bounding box of a rank's blocks."""
    mine = np.argwhere(block_part == rank)
    return mine.min(axis=0), mine.max(axis=0) + 1
