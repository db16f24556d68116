"""Deck section ``geometry``: the body's shape (bar, rectangle, disc, box, cylinder,
mesh), its dimension, its point-volume factor and the checks of its holes."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field

from peridynamics.deck.regions import RegionSpec, check_region, uses
from peridynamics.deck.types import Errors, Finite, PosFloat, Strict


class BarGeometry(Strict):
    """1-D bar (a length off the spacing's multiples: the whole cells that fit, centred).

    docs/deck.md, geometry, gives the fitting rule."""

    type: Literal["bar"]
    length: PosFloat
    area: PosFloat = 1.0
    origin: Finite = 0.0
    nodes_on_boundary: bool = False


class RectangleGeometry(Strict):
    """2-D rectangle with holes (sides off the spacing: the whole cells that fit, centred).

    A side that is not a whole multiple of the spacing gets the floor(L / dx) cells that
    fit, centred in it, each point keeping its cell volume (docs/deck.md, geometry)."""

    type: Literal["rectangle"]
    size: tuple[PosFloat, PosFloat]
    origin: tuple[Finite, Finite] = (0.0, 0.0)
    thickness: PosFloat = 1.0
    plane: Literal["stress", "strain"] = "stress"
    holes: list[RegionSpec] = []


class BoxGeometry(Strict):
    """3-D box with optional cut-outs (sides fitted like a rectangle's: whole cells)."""

    type: Literal["box"]
    size: tuple[PosFloat, PosFloat, PosFloat]
    origin: tuple[Finite, Finite, Finite] = (0.0, 0.0, 0.0)
    holes: list[RegionSpec] = []


class CylinderGeometry(Strict):
    """3-D solid cylinder along z (any radius; the length gets the whole cells that fit)."""

    type: Literal["cylinder"]
    radius: PosFloat
    length: PosFloat
    origin: tuple[Finite, Finite, Finite] = (0.0, 0.0, 0.0)
    holes: list[RegionSpec] = []


class DiscGeometry(Strict):
    """2-D disc: square-grid points inside the circle, a cell corner at the centre.

    Any radius >= spacing / sqrt(2); every point has the volume spacing^2 x thickness."""

    type: Literal["disc"]
    radius: PosFloat
    center: tuple[Finite, Finite] = (0.0, 0.0)
    thickness: PosFloat = 1.0
    plane: Literal["stress", "strain"] = "stress"
    holes: list[RegionSpec] = []


class MeshGeometry(Strict):
    """Points at cell centroids of a mesh file read by meshio (path relative to the deck)."""

    type: Literal["mesh"]
    file: str
    dim: Literal[2, 3] | None = None  # None: 3 if the mesh has volume cells, else 2
    thickness: PosFloat = 1.0
    plane: Literal["stress", "strain"] = "stress"


Geometry = Annotated[
    BarGeometry | RectangleGeometry | DiscGeometry | BoxGeometry | CylinderGeometry | MeshGeometry,
    Field(discriminator="type"),
]


def geometry_dim(g: Any) -> int:
    """Spatial dimension of a geometry section (mesh: declared dim, default 2)."""
    if isinstance(g, BarGeometry):
        return 1
    if isinstance(g, RectangleGeometry | DiscGeometry):
        return 2
    if isinstance(g, MeshGeometry):
        return g.dim or 2
    return 3


def cross_section(g: Any) -> float:
    """The point-volume factor of a geometry: bar area (1-D), thickness (2-D), 1 (3-D)."""
    if isinstance(g, BarGeometry):
        return g.area
    if isinstance(g, RectangleGeometry | DiscGeometry) or (
        isinstance(g, MeshGeometry) and geometry_dim(g) == 2
    ):
        return g.thickness
    return 1.0


def hole_errors(deck: Any) -> Errors:
    """Checks of ``geometry.holes``: shapes only, of the model's dimension."""
    errors: Errors = []
    for n, hole in enumerate(getattr(deck.geometry, "holes", [])):
        if uses(hole, {"edge", "set", "point"}):
            errors.append(
                (
                    f"geometry.holes.{n}",
                    "holes are shapes (box, circle, polygon, ...); edge, set and "
                    "point regions only make sense for node sets",
                )
            )
        check_region(errors, f"geometry.holes.{n}", hole, deck.dim, set())
    return errors
