"""The deck's point cloud with its node sets, and its bonds (pre-cracks, notches cut).

:func:`build_cloud` builds the geometry (and further bodies), removes the points
inside the notches and resolves the node sets; :func:`build_bonds_for` the bonds with
partial volumes and the bonds across pre-cracks and notches cut.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics import deck as dk
from peridynamics.bonds import build_bonds, make_crack
from peridynamics.bonds.bonds import Bonds
from peridynamics.bonds.precrack import crossing_bonds
from peridynamics.build.bodies import build_body_points, has_bodies
from peridynamics.build.errors import SetupError
from peridynamics.build.geometry import geometry_cloud
from peridynamics.build.plausibility import (
    warn_direct_solver,
    warn_horizon,
    warn_idle_precracks,
    warn_overlapping_bodies,
)
from peridynamics.build.regions import to_region
from peridynamics.geometry import Notch, PointCloud


def deck_notches(deck: dk.Deck) -> list[Notch]:
    """The deck's ``notches`` as :class:`~peridynamics.geometry.notches.Notch` objects."""
    out = []
    for n, spec in enumerate(deck.notches):
        try:
            out.append(Notch(spec.start, spec.end, spec.width, spec.tip, spec.z))
        except ValueError as exc:
            raise SetupError(f"notches.{n}", str(exc)) from None
    return out


def _cut_notches(
    deck: dk.Deck, cloud: PointCloud, body_sets: dict[str, NDArray[np.intp]]
) -> tuple[PointCloud, dict[str, NDArray[np.intp]]]:
    """Remove the points inside the deck's notches (every body's); the body node sets
    are re-indexed (each body stays contiguous)."""
    notches = deck_notches(deck)
    if not notches:
        return cloud, body_sets
    cut = cloud.with_node_sets(**body_sets)
    for n, notch in enumerate(notches):
        try:
            cut = cut.remove(notch.region())
        except ValueError as exc:
            raise SetupError(f"notches.{n}", str(exc)) from None
    for name in body_sets:
        if cut.node_sets[name].size == 0:
            raise SetupError("notches", f"the notches remove every point of body {name!r}")
    return cut, {name: cut.node_sets[name] for name in body_sets}


def build_cloud(deck: dk.Deck) -> PointCloud:
    """Geometry section (and further bodies) -> PointCloud with the deck's node sets
    (plus 'all' and one set per body of a deck with ``bodies``); the points inside the
    deck's ``notches`` are removed before the node sets are built."""
    cloud = geometry_cloud(deck.geometry, deck.discretisation)
    body_sets: dict[str, NDArray[np.intp]] = {}
    if has_bodies(deck):
        fit = cloud.grid_fit
        cloud, layout = build_body_points(deck, cloud)
        cloud = replace(cloud, grid_fit=fit)
        warn_overlapping_bodies(deck, cloud, layout)
        body_sets = layout.node_sets()
        clash = sorted(set(body_sets) & set(deck.node_sets))
        if clash:
            raise SetupError(
                f"node_sets.{clash[0]}",
                "has the name of a body (each body is a node set of that name); rename it",
            )
        if "all" in body_sets:
            raise SetupError("bodies", "'all' is built in (every point); rename the body")
    cloud, body_sets = _cut_notches(deck, cloud, body_sets)
    clash = sorted(set(deck.node_sets) & set(cloud.node_sets))
    if clash:
        raise SetupError(
            f"node_sets.{clash[0]}",
            "has the name of a node set of the geometry (a gmsh group, a mesh block or set, "
            "an image phase); rename it",
        )
    sets: dict[str, NDArray[np.intp]] = {
        **cloud.node_sets,  # a geometry's groups (gmsh, mesh blocks, image phases)
        "all": np.arange(cloud.n_points),
        **body_sets,
    }

    def select(name: str, spec: dk.RegionSpec) -> tuple[NDArray[np.intp], int]:
        try:
            idx = cloud.select(to_region(spec, sets, cloud.spacing))
        except ValueError as exc:
            raise SetupError(f"node_sets.{name}", str(exc)) from None
        return idx, int(idx.size)

    resolve_node_sets(deck, sets, select, cloud.bounds)
    warn_horizon(deck, *cloud.bounds, cloud.n_points, cloud.spacing)
    warn_direct_solver(deck, cloud.n_points)
    return cloud.with_node_sets(**sets)


def resolve_node_sets(
    deck: dk.Deck,
    sets: dict[str, NDArray[np.intp]],
    select: Callable[[str, dk.RegionSpec], tuple[NDArray[np.intp], int]],
    bounds: tuple[NDArray[np.float64], NDArray[np.float64]],
) -> None:
    """Add every node set of the deck to ``sets`` (in place), each after the sets its
    region names. ``select(name, spec)`` gives a set's indices and its number of points
    in the whole body (a rank counts the owned ones of every rank); SetupError for a
    cycle of references and for a set that selects no point (``bounds``: the corners of
    the whole body, m, for the message)."""
    visiting: set[str] = set()

    def resolve(name: str) -> NDArray[np.intp]:
        if name in sets:
            return sets[name]
        if name in visiting:
            raise SetupError(f"node_sets.{name}", "node sets refer to each other in a cycle")
        visiting.add(name)
        spec = deck.node_sets[name]
        collect_refs(spec, resolve)
        idx, total = select(name, spec)
        if total == 0:
            lo, hi = bounds
            raise SetupError(
                f"node_sets.{name}",
                "selects no point; check the region against the geometry "
                f"(points span {np.asarray(lo).tolist()} .. {np.asarray(hi).tolist()} m)",
            )
        sets[name] = idx
        return idx

    for name in deck.node_sets:
        resolve(name)


def collect_refs(spec: dk.RegionSpec, resolve: Callable[[str], Any]) -> None:
    """Call ``resolve`` on every node set a region spec refers to (``set``, nested)."""
    k = spec.kind()
    v = getattr(spec, k)
    if k == "set":
        resolve(v)
    elif k in ("all_of", "any_of"):
        for s in v:
            collect_refs(s, resolve)
    elif k == "not_":
        collect_refs(v, resolve)


def build_bonds_for(
    deck: dk.Deck,
    cloud: PointCloud,
    bounds: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
) -> Bonds:
    """Bonds with partial volumes, pre-cracks and the bonds across notches cut.

    A notch cuts like a pre-crack along its centre line (``Notch.crack``); in 3-D a
    notch without a z-range cuts over the body's z-extent widened by one spacing
    (``bounds``: the corners of the whole body when ``cloud`` is a rank's part)."""
    d = deck.discretisation
    notches = deck_notches(deck)
    z_bounds = None
    if notches and cloud.dim == 3:
        lo, hi = cloud.bounds if bounds is None else bounds
        z_bounds = (float(lo[2]) - cloud.spacing, float(hi[2]) + cloud.spacing)
    try:
        cracks = [make_crack(c.points) for c in deck.precracks]
        cracks += [notch.crack(z_bounds) for notch in notches]
        bonds = build_bonds(cloud, d.delta, d.partial_volume)
        # one crack at a time (as Bonds.cut does), so that a pre-crack that cuts no bond
        # is seen without a second search
        hits = [crossing_bonds(cloud.x, bonds.bond_i, bonds.bond_j, [c]) for c in cracks]
    except ValueError as exc:
        raise SetupError("discretisation", str(exc)) from None
    warn_idle_precracks(deck, cloud.x, hits[: len(deck.precracks)])
    return bonds.without(np.logical_or.reduce(hits)) if hits else bonds
