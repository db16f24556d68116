"""A rank's part of a decomposed run made without the global point cloud.

For a deck whose body is a grid (rectangle, disc, box or cylinder, jittered or not,
holes and notches that are point-wise regions; :func:`deck_lattice`), every
rank makes only the points it holds (:mod:`peridynamics.parallel.windowed`), then:

- **node sets** are resolved on those points like :func:`~peridynamics.build.cloud.build_cloud`
  does on the whole body; the regions that look at the whole body are made global
  first: an ``edge`` layer takes the body's largest projection (an ``Allreduce`` max over
  the owned points) and a ``point`` the body's nearest point (ties: lowest global id,
  as a serial run picks it); a set that selects no point anywhere is the serial error;
- **boundary conditions** on a set are built on the owned members here, except the
  tractions and pressures, whose layer thickness and area are those of the whole set:
  they are built on the set's members gathered from every rank (what a rank then holds
  is that set's positions and volumes, 32 bytes per member in 3-D);
- every error found on a rank is raised on every rank (:func:`agreed`), so no rank
  waits for another that has stopped.

Decks that need the whole cloud (several bodies, mesh geometries, an initial velocity
read from a file of every point) keep the replicated set-up of
:func:`~peridynamics.build.decomposed.build_distributed`.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import replace
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from peridynamics import deck as dk
from peridynamics.build.bodies import has_bodies
from peridynamics.build.cloud import deck_notches, resolve_node_sets
from peridynamics.build.errors import SetupError
from peridynamics.build.loads import build_conditions
from peridynamics.build.regions import IndexSet, to_region
from peridynamics.geometry import PointCloud
from peridynamics.geometry.cloud import GeometryFitWarning
from peridynamics.geometry.jittered_lattice import jittered_lattice
from peridynamics.geometry.lattice import (
    Lattice,
    box_lattice,
    cylinder_lattice,
    disc_lattice,
    rectangle_lattice,
)
from peridynamics.geometry.regions import Layer, NearestPoint, Region, is_pointwise, map_leaves
from peridynamics.parallel.global_cloud import CloudMeta
from peridynamics.parallel.local import localize_condition
from peridynamics.parallel.windowed import WindowedPart

T = TypeVar("T")

#: geometry ``type`` -> lattice builder(section, discretisation, holes)
LATTICES: dict[str, Callable[[Any, dk.Discretisation, list[Region]], Lattice]] = {
    "rectangle": lambda g, d, h: rectangle_lattice(
        g.size, d.spacing, g.thickness, g.origin, g.plane, h
    ),
    "disc": lambda g, d, h: disc_lattice(g.radius, d.spacing, g.center, g.thickness, g.plane, h),
    "box": lambda g, d, h: box_lattice(g.size, d.spacing, g.origin, h),
    "cylinder": lambda g, d, h: cylinder_lattice(g.radius, g.length, d.spacing, g.origin, h),
}
#: condition types built on the whole set (their layer thickness and area)
SET_WIDE = ("traction", "pressure")


def deck_lattice(deck: dk.Deck) -> Lattice | None:
    """The deck's body as a lattice, or ``None`` when its set-up needs the whole cloud
    (module docstring)."""
    g, d = deck.geometry, deck.discretisation
    if g.type not in LATTICES or has_bodies(deck):
        return None
    if any(getattr(bc, "file", None) is not None for bc in deck.boundary_conditions):
        return None
    holes = [to_region(h) for h in getattr(g, "holes", [])]
    notches = [n.region() for n in deck_notches(deck)]
    if not all(is_pointwise(r) for r in (*holes, *notches)):
        return None
    try:
        lattice = LATTICES[g.type](g, d, holes)
    except ValueError as exc:
        raise SetupError("geometry", str(exc)) from None
    for fit in lattice.grid_fit:
        warnings.warn(fit.message(), GeometryFitWarning, stacklevel=2)
    lattice = lattice.with_removed(*notches)
    if d.jitter > 0:  # the generators' jitter, made a window at a time
        thickness = float(getattr(g, "thickness", 1.0)) if lattice.dim == 2 else 1.0
        lattice = jittered_lattice(lattice, d.jitter, d.seed, "voronoi", thickness)
    return lattice


def agreed(comm: Any, work: Callable[[], T]) -> T:
    """``work()`` on every rank; a SetupError on any rank is raised on all (the error
    of the lowest rank that failed)."""
    try:
        result, error = work(), None
    except SetupError as exc:
        result, error = None, (exc.path, exc.message)
    errors = [e for e in comm.allgather(error) if e is not None]
    if errors:
        raise SetupError(*errors[0])
    return result  # type: ignore[return-value]


def local_cloud(deck: dk.Deck, lattice: Lattice, part: WindowedPart, comm: Any) -> PointCloud:
    """This rank's points with the deck's node sets (members held here, ghosts too)."""
    lay = part.layout
    lo, hi = _bounds(comm, part.x[: lay.n_owned])
    cloud = PointCloud(
        x=part.x,
        volume=part.volume,
        spacing=lattice.spacing,
        cross_section=lattice.cross_section,
        plane=lattice.plane,
        irregular=lattice.irregular,
        grid_fit=lattice.grid_fit,
        global_ids=lay.local_ids.astype(np.int64),
        body_size=float(max(np.max(hi - lo), lattice.spacing)),
    )
    sets: dict[str, NDArray[np.intp]] = {"all": np.arange(lay.n_local)}

    def select(name: str, spec: dk.RegionSpec) -> tuple[NDArray[np.intp], int]:
        key = f"node_sets.{name}"
        region = agreed(comm, lambda: _region(spec, sets, cloud.spacing, key))
        region = map_leaves(region, lambda r: _global(r, comm, cloud, lay.n_owned, key))
        idx = cloud.select(region)
        return idx, int(comm.allreduce(int(np.count_nonzero(idx < lay.n_owned))))

    resolve_node_sets(deck, sets, select, (lo, hi))
    return cloud.with_node_sets(**sets)


def _region(spec: dk.RegionSpec, sets: dict, spacing: float, key: str) -> Region:
    try:
        return to_region(spec, sets, spacing)
    except ValueError as exc:
        raise SetupError(key, str(exc)) from None


def _bounds(comm: Any, x: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
    """The corners of the bounding box of every rank's points ``x`` (m)."""
    from mpi4py import MPI

    dim = x.shape[1]
    lo = x.min(axis=0) if len(x) else np.full(dim, np.inf)
    hi = x.max(axis=0) if len(x) else np.full(dim, -np.inf)
    g_lo, g_hi = np.empty(dim), np.empty(dim)
    comm.Allreduce(np.ascontiguousarray(lo), g_lo, op=MPI.MIN)
    comm.Allreduce(np.ascontiguousarray(hi), g_hi, op=MPI.MAX)
    return g_lo, g_hi


def _global(region: Region, comm: Any, cloud: PointCloud, n_owned: int, key: str) -> Region:
    """A leaf region that looks at the whole body, made to look at it from one rank."""
    own = cloud.x[:n_owned]
    if isinstance(region, Layer):
        proj = own @ np.asarray(region.normal)
        top = comm.allreduce(float(proj.max()) if proj.size else -np.inf, op=_max())
        return Layer(region.normal, region.depth, top=top)
    if isinstance(region, NearestPoint):
        gid = np.asarray(cloud.global_ids)
        best = (np.inf, -1)
        if n_owned:
            d2 = np.sum((own - np.asarray(region.location)) ** 2, axis=1)
            k = int(np.argmin(d2))  # the lowest local row: the lowest global id here
            best = (float(d2[k]), int(gid[k]))
        d2_min, chosen = min(comm.allgather(best))
        if np.sqrt(d2_min) > region.max_distance:
            raise SetupError(  # the same on every rank (allgathered)
                key,
                f"point {list(region.location)} is {np.sqrt(d2_min):.3g} m from the nearest "
                f"point of the body (more than {region.max_distance:.3g} m): is it outside "
                "the body or in a hole?",
            )
        return IndexSet(np.flatnonzero(gid == chosen))
    return region


def _max() -> Any:
    from mpi4py import MPI

    return MPI.MAX


def conditions(
    deck: dk.Deck, cloud: PointCloud, n_owned: int, comm: Any
) -> tuple[list, list, list]:
    """(body forces, kinematic constraints, initial velocities) of this rank's owned
    points, in local numbering (module docstring)."""
    owned = {k: v[v < n_owned] for k, v in cloud.node_sets.items()}
    here = replace(cloud, node_sets=owned)
    wide = {bc.set for bc in deck.boundary_conditions if bc.type in SET_WIDE}
    gathered = {name: _gathered_set(cloud, owned[name], name, comm) for name in sorted(wide)}
    owned_ids = np.asarray(cloud.global_ids)[:n_owned]

    def on(spec: Any) -> tuple[PointCloud, Callable[[Any], Any]] | None:
        if spec.type not in SET_WIDE:
            return None
        whole = gathered[spec.set]
        ids = np.asarray(whole.global_ids)
        return whole, lambda c: localize_condition(replace(c, nodes=ids[c.nodes]), owned_ids)

    return agreed(comm, lambda: build_conditions(deck, here, on))


def _gathered_set(cloud: PointCloud, owned: NDArray[np.intp], name: str, comm: Any) -> PointCloud:
    """The owned members of a node set of every rank, as a cloud in global order (its
    node set ``name`` is every point)."""
    gid = np.asarray(cloud.global_ids)
    parts = comm.allgather((gid[owned], cloud.x[owned], cloud.volume[owned]))
    ids = np.concatenate([p[0] for p in parts])
    order = np.argsort(ids)
    return PointCloud(
        x=np.concatenate([p[1] for p in parts])[order],
        volume=np.concatenate([p[2] for p in parts])[order],
        spacing=cloud.spacing,
        cross_section=cloud.cross_section,
        plane=cloud.plane,
        irregular=cloud.irregular,  # a jittered layer's thickness is its volume / area
        node_sets={name: np.arange(len(ids))},
        global_ids=ids[order],
    )


def cloud_meta(
    lattice: Lattice, cloud: PointCloud, n_owned: int, comm: Any, n_global: int
) -> CloudMeta:
    """What every rank knows of the whole body (for the observers' view)."""
    lo, hi = _bounds(comm, cloud.x[:n_owned])
    return CloudMeta(
        n_points=n_global,
        dim=lattice.dim,
        spacing=lattice.spacing,
        cross_section=lattice.cross_section,
        plane=lattice.plane,
        irregular=lattice.irregular,
        grid_fit=lattice.grid_fit,
        lo=lo,
        hi=hi,
        set_names=tuple(cloud.node_sets),
    )
