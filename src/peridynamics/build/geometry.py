"""Geometry sections -> point clouds (registry :data:`GEOMETRIES`, keyed by ``type``).

A geometry section (the deck's, a body's or a rigid body's point set) is built on the
deck's discretisation by the builder its ``type`` names; adding a geometry kind adds a
builder and one registry line.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from peridynamics import deck as dk
from peridynamics.build.errors import SetupError
from peridynamics.build.regions import to_region
from peridynamics.geometry import PointCloud, bar, box, cylinder, disc, rectangle
from peridynamics.geometry.gmsh_model import from_gmsh
from peridynamics.geometry.image_phases import Phase, from_image
from peridynamics.geometry.mesh_groups import from_mesh_groups
from peridynamics.geometry.surface_fill import fill_surface


def _bar(g: Any, d: dk.Discretisation) -> PointCloud:
    return bar(g.length, d.spacing, area=g.area, origin=g.origin,
               nodes_on_boundary=g.nodes_on_boundary)  # fmt: skip


def _rectangle(g: Any, d: dk.Discretisation) -> PointCloud:
    return rectangle(
        g.size,
        d.spacing,
        thickness=g.thickness,
        origin=g.origin,
        plane=g.plane,
        holes=[to_region(h) for h in g.holes],
        jitter=d.jitter,
        seed=d.seed,
    )


def _disc(g: Any, d: dk.Discretisation) -> PointCloud:
    return disc(
        g.radius,
        d.spacing,
        center=g.center,
        thickness=g.thickness,
        plane=g.plane,
        holes=[to_region(h) for h in g.holes],
        jitter=d.jitter,
        seed=d.seed,
    )


def _box(g: Any, d: dk.Discretisation) -> PointCloud:
    return box(
        g.size,
        d.spacing,
        origin=g.origin,
        holes=[to_region(h) for h in g.holes],
        jitter=d.jitter,
        seed=d.seed,
    )


def _cylinder(g: Any, d: dk.Discretisation) -> PointCloud:
    return cylinder(
        g.radius,
        g.length,
        d.spacing,
        origin=g.origin,
        holes=[to_region(h) for h in g.holes],
        jitter=d.jitter,
        seed=d.seed,
    )


def _mesh(g: Any, d: dk.Discretisation) -> PointCloud:
    return from_mesh_groups(g.file, dim=g.dim, thickness=g.thickness, plane=g.plane,
                            spacing=d.spacing, groups=g.groups)  # fmt: skip


def _surface(g: Any, d: dk.Discretisation) -> PointCloud:
    return fill_surface(g.file, d.spacing, scale=g.scale)


def _gmsh(g: Any, d: dk.Discretisation) -> PointCloud:
    return from_gmsh(g.file, d.spacing, dim=g.dim, mesh_size=g.mesh_size, scale=g.scale,
                     thickness=g.thickness, plane=g.plane, groups=g.groups)  # fmt: skip


def _image(g: Any, d: dk.Discretisation) -> PointCloud:
    phases = [Phase(p.name, p.grey[0], p.grey[1], p.remove) for p in g.phases]
    return from_image(g.file, g.pixel_size, d.spacing, phases, origin=g.origin,
                      thickness=g.thickness, plane=g.plane)  # fmt: skip


#: geometry ``type`` -> builder(section, discretisation) -> PointCloud
GEOMETRIES: dict[str, Callable[[Any, dk.Discretisation], PointCloud]] = {
    "bar": _bar,
    "rectangle": _rectangle,
    "disc": _disc,
    "box": _box,
    "cylinder": _cylinder,
    "mesh": _mesh,
    "surface": _surface,
    "gmsh": _gmsh,
    "image": _image,
}
#: geometry kinds whose points cannot be jittered (a mesh's points are its centroids)
NO_JITTER = ("bar", "mesh", "surface", "gmsh", "image")


def geometry_cloud(g: Any, d: dk.Discretisation) -> PointCloud:
    """A geometry section (the deck's, a body's or a rigid body's) -> PointCloud without
    node sets, on the deck's discretisation."""
    try:
        if d.jitter > 0 and g.type in NO_JITTER:
            raise ValueError(
                f"discretisation.jitter = {d.jitter} needs a rectangle, disc, box or cylinder "
                f"geometry, not a {g.type} (a mesh's points are its cell centroids, a "
                "surface or image is filled with the regular grid); set "
                "discretisation.jitter: 0"
            )
        cloud = GEOMETRIES[g.type](g, d)
    except ValueError as exc:
        raise SetupError("geometry", str(exc)) from None
    return cloud
