"""Deck section ``geometry``: the body's shape (bar, rectangle, disc, box, cylinder,
mesh, surface, gmsh, image), its dimension, its point-volume factor, the node sets it
brings and the checks of its holes."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

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


GroupName = Annotated[str, Field(min_length=1, max_length=120)]


class MeshGeometry(Strict):
    """Points at cell centroids of a mesh file read by meshio (path relative to the deck)."""

    type: Literal["mesh"]
    file: str
    dim: Literal[2, 3] | None = None  # None: 3 if the mesh has volume cells, else 2
    thickness: PosFloat = 1.0
    plane: Literal["stress", "strain"] = "stress"
    groups: list[GroupName] | None = None


class SurfaceGeometry(Strict):
    """3-D solid inside a closed surface mesh (STL, OBJ, PLY; path relative to the deck)
    filled with the grid; ``scale``: metres per file unit."""

    type: Literal["surface"]
    file: str
    scale: PosFloat = 1.0


class GmshGeometry(Strict):
    """Cell centroids of a Gmsh model (``.geo`` meshed here, or ``.msh``) with its
    physical groups as node sets (``groups``: the ones to keep, default all)."""

    type: Literal["gmsh"]
    file: str
    dim: Literal[2, 3] | None = None  # None: the model's dimension
    mesh_size: PosFloat | None = None  # .geo: largest element edge, file units
    scale: PosFloat = 1.0
    thickness: PosFloat = 1.0
    plane: Literal["stress", "strain"] = "stress"
    groups: list[GroupName] | None = None


class PhaseSpec(Strict):
    """A phase of an image: grey levels ``grey`` = [lo, hi] (0 .. 1, closed), a node set
    ``name``; ``remove: true`` takes its points out (pores)."""

    name: Annotated[str, Field(min_length=1, max_length=60, pattern=r"^[A-Za-z][A-Za-z0-9_]*$")]
    grey: tuple[Annotated[float, Field(ge=0.0, le=1.0)], Annotated[float, Field(ge=0.0, le=1.0)]]
    remove: bool = False

    @model_validator(mode="after")
    def _order(self) -> PhaseSpec:
        if self.grey[0] > self.grey[1]:
            raise ValueError(f"[grey] lo {self.grey[0]} must be <= hi {self.grey[1]}")
        return self


class ImageGeometry(Strict):
    """2-D plate from an image (PNG, TIFF) of pixels ``pixel_size`` (m) wide; phases by
    grey level become node sets (or are removed)."""

    type: Literal["image"]
    file: str
    pixel_size: PosFloat
    phases: list[PhaseSpec] = Field(min_length=1)
    origin: tuple[Finite, Finite] = (0.0, 0.0)
    thickness: PosFloat = 1.0
    plane: Literal["stress", "strain"] = "stress"

    @model_validator(mode="after")
    def _names(self) -> ImageGeometry:
        names = [p.name for p in self.phases]
        if len(set(names)) != len(names):
            raise ValueError(f"[phases] phase names must differ, got {names}")
        if all(p.remove for p in self.phases):
            raise ValueError("[phases] every phase is removed: keep at least one")
        return self


#: the geometry kinds read from a file named by ``file`` (made absolute on reading)
FILE_GEOMETRIES = (MeshGeometry, SurfaceGeometry, GmshGeometry, ImageGeometry)

Geometry = Annotated[
    BarGeometry
    | RectangleGeometry
    | DiscGeometry
    | BoxGeometry
    | CylinderGeometry
    | MeshGeometry
    | SurfaceGeometry
    | GmshGeometry
    | ImageGeometry,
    Field(discriminator="type"),
]


def geometry_set_names(g: Any) -> set[str]:
    """The node sets a geometry brings that a deck may name: an image's kept phases, the
    ``groups`` listed for a mesh or a Gmsh model (with ``groups`` left out every group
    is a node set of the built cloud, but the deck cannot know their names)."""
    if isinstance(g, ImageGeometry):
        return {p.name for p in g.phases if not p.remove}
    if isinstance(g, MeshGeometry | GmshGeometry) and g.groups is not None:
        return set(g.groups)
    return set()


def geometry_dim(g: Any) -> int:
    """Spatial dimension of a geometry section (mesh: declared dim, default 2)."""
    if isinstance(g, BarGeometry):
        return 1
    if isinstance(g, RectangleGeometry | DiscGeometry | ImageGeometry):
        return 2
    if isinstance(g, MeshGeometry | GmshGeometry):
        return g.dim or 2
    return 3


def cross_section(g: Any) -> float:
    """The point-volume factor of a geometry: bar area (1-D), thickness (2-D), 1 (3-D)."""
    if isinstance(g, BarGeometry):
        return g.area
    if isinstance(g, RectangleGeometry | DiscGeometry | ImageGeometry) or (
        isinstance(g, MeshGeometry | GmshGeometry) and geometry_dim(g) == 2
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
