"""A rank's part of the body: its owned points and ghosts, and the bonds of its owned points.

:func:`local_cloud` cuts the global :class:`~peridynamics.geometry.cloud.PointCloud`
(every rank builds it: O(n_points) memory, small beside the bonds) into the points this
rank holds, ``[owned | ghost]``; node sets keep every member held here (ghosts too:
a no-fail zone is a property of its points), while boundary conditions keep their owned
points (:func:`localize_condition`) and probes run on the whole body on rank 0.
:func:`own_families` turns a bond list built on that local cloud into the list of the
owned families, each sorted by the global id of the neighbour (the serial order), with
empty families for the ghosts.
"""

from __future__ import annotations

from dataclasses import fields, replace
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.bonds.search import neighbour_counts
from peridynamics.geometry.cloud import PointCloud
from peridynamics.parallel.decompose import Layout, find_sorted, ghost_distances, rcb_partition


def decompose(
    comm: Any,
    cloud: PointCloud,
    search_radius: float,
    ghost_radius: float,
    ghost_families: bool = True,
) -> tuple[Layout, int]:
    """The layout of this rank and its number of points with a bond family (collective:
    one ``alltoall`` of ghost requests).

    Local points are ``[owned | first layer | second layer]``, each part in increasing
    global id. The first layer (ghosts within ``search_radius`` of an owned point) gets
    its bond families here too, so every per-point quantity the force pass reads at the
    far end of an owned bond (dilatation, deformation gradient, SED level, surface
    factors) is computed on this rank from exchanged displacements, bit for bit as its
    owner computes it: one halo exchange of u and v per evaluation suffices.

    Parameters
    ----------
    comm : mpi4py communicator.
    cloud : the global point cloud (the same on every rank).
    search_radius : bond search radius (m); the partition weight of a point is the number
        of points within it (its bond count).
    ghost_radius : distance (m) within which other ranks' points are held as ghosts, at
        least twice ``search_radius`` (the families of the first layer reach that far)
        with ``ghost_families``, at least ``search_radius`` without.
    ghost_families : give the first ghost layer its families (models whose force pass
        reads per-point quantities of the far end of a bond: LPS, correspondence, SED
        levels); plain bond-based PMB reads only u and v there and needs one layer.
    """
    from peridynamics.parallel.mpi import build_exchange_lists

    rank, size = int(comm.Get_rank()), int(comm.Get_size())
    weights = neighbour_counts(cloud.x, search_radius).astype(np.float64) + 1.0
    part = rcb_partition(cloud.x, weights, size)
    owned = np.flatnonzero(part == rank)
    ghosts, dist = ghost_distances(cloud.x, owned, ghost_radius)
    # the first layer: within the search radius (the bound ghost_points applies)
    first = dist <= search_radius * (1 + 1e-12) if ghost_families else np.zeros(len(ghosts), bool)
    ghosts = np.concatenate([ghosts[first], ghosts[~first]])
    recv, send = build_exchange_lists(comm, part[ghosts], owned, ghosts)
    local_ids = np.concatenate([owned, ghosts])
    layout = Layout(rank, size, cloud.n_points, local_ids, len(owned), recv, send)
    return layout, len(owned) + int(first.sum())


def local_cloud(cloud: PointCloud, layout: Layout) -> PointCloud:
    """The points this rank holds (owned, then ghosts) with their global ids. Node sets
    keep every member held here, ghosts included: a set that gives points a property
    (a no-fail zone, a material region) must give it to the ghosts as their owners have
    it. Loads are localised to owned points separately (:func:`localize_condition`)."""
    ids = layout.local_ids
    order = np.argsort(ids, kind="stable")
    sorted_ids = ids[order]
    sets = {}
    for name, members in cloud.node_sets.items():
        pos, hit = find_sorted(sorted_ids, members)
        sets[name] = np.sort(order[pos[hit]]).astype(np.intp)
    return replace(
        cloud,
        x=cloud.x[ids],
        volume=cloud.volume[ids],
        node_sets=sets,
        global_ids=ids.astype(np.int64),
        body_size=cloud.size,
    )


@numba.njit(cache=True, parallel=True)
def _sort_families(
    offsets: NDArray[np.int64],
    bond_j: NDArray[np.int32],
    intact: NDArray[np.uint8],
    gid: NDArray[np.int64],
) -> None:  # pragma: no cover - compiled
    """Sort every family by the global id of the neighbour (intact flags follow)."""
    for i in numba.prange(len(offsets) - 1):
        a, b = offsets[i], offsets[i + 1]
        keys = np.empty(b - a, dtype=np.int64)
        for k in range(a, b):
            keys[k - a] = gid[bond_j[k]]
        order = np.argsort(keys, kind="mergesort")
        js = bond_j[a:b].copy()
        fl = intact[a:b].copy()
        for k in range(b - a):
            bond_j[a + k] = js[order[k]]
            intact[a + k] = fl[order[k]]


def own_families(bonds: Bonds, cloud: PointCloud, n_owned: int | NDArray[np.bool_]) -> Bonds:
    """The bonds of the points with a family here (the first ``n_owned``, or the points
    of a mask (n_local,)) of a list built on the local cloud, each family in the serial
    order; the other points get empty families."""
    assert cloud.global_ids is not None
    counts = np.diff(bonds.offsets)
    if isinstance(n_owned, int | np.integer):
        keep = np.arange(len(counts)) < n_owned
    else:  # a mask (several bodies)
        keep = np.asarray(n_owned, dtype=bool)
    offsets = np.zeros(len(counts) + 1, dtype=np.int64)
    np.cumsum(np.where(keep, counts, 0), out=offsets[1:])
    sel = np.repeat(keep, counts)  # the bonds of the kept rows, in CSR order
    bond_j = np.ascontiguousarray(bonds.bond_j[sel])
    intact = np.ascontiguousarray(bonds.bond_intact[sel])
    _sort_families(offsets, bond_j, intact, cloud.global_ids)
    return bonds.replace(offsets=offsets, bond_j=bond_j, bond_intact=intact)


def localize_condition(cond: Any, owned_ids: NDArray[np.intp]) -> Any:
    """A boundary or initial condition built on the global cloud, restricted to the owned
    points of this rank in local numbering (per-node value arrays follow). Building on
    the global cloud keeps what depends on the whole node set (the layer thickness of a
    traction, a cavity's pressure layer) as in the serial run."""
    nodes = np.asarray(cond.nodes)
    pos, hit = find_sorted(owned_ids, nodes)
    changes: dict[str, Any] = {"nodes": pos[hit].astype(np.intp)}
    for f in fields(cond):
        value = getattr(cond, f.name)
        if f.name != "nodes" and isinstance(value, np.ndarray) and value.ndim >= 1:
            if value.shape[0] == nodes.shape[0]:
                changes[f.name] = value[hit]
    return replace(cond, **changes)
