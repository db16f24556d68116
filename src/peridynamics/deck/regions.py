"""Deck regions: the shapes and set expressions of ``node_sets`` and
``geometry.holes`` (``docs/deck.md``, section "node_sets"), and their checks against
the model's dimension and the names of the node sets."""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import ConfigDict, Field, model_validator

from peridynamics.deck.types import Errors, Finite, Num, PosFloat, Strict


class BoxRegion(Strict):
    """Axis-aligned box; ``.inf`` / ``-.inf`` allowed for open sides."""

    min: list[Annotated[float, Field(allow_inf_nan=True), Num]]
    max: list[Annotated[float, Field(allow_inf_nan=True), Num]]

    @model_validator(mode="after")
    def _order(self) -> BoxRegion:
        if len(self.min) != len(self.max):
            raise ValueError("[max] min and max need the same number of components")
        if any(math.isnan(v) for v in [*self.min, *self.max]):
            raise ValueError("NaN is not allowed")
        if any(a > b for a, b in zip(self.min, self.max, strict=True)):
            raise ValueError(f"[max] min {self.min} must be <= max {self.max} component-wise")
        return self


class BallRegion(Strict):
    """Disc (2-D) or sphere (3-D) around ``center``."""

    center: list[Finite]
    radius: PosFloat


AXES = {"x": [1.0, 0.0, 0.0], "y": [0.0, 1.0, 0.0], "z": [0.0, 0.0, 1.0]}


def _numbers(v: Any) -> list[float] | None:
    """``v`` as a list of finite floats, ``None`` if it is not one (the field's own
    validation then says why)."""
    if not isinstance(v, list | tuple) or not v:
        return None
    try:
        out = [float(c) for c in v]
    except (TypeError, ValueError, OverflowError):
        return None
    return out if all(math.isfinite(c) for c in out) else None


def cylinder_placed(data: Any, keep: str) -> Any:
    """A cylinder given either way (``base``: the centre of one end face, or ``center``:
    its middle; ``axis``: x, y, z or a vector) rewritten to ``keep`` (``base`` or
    ``center``), the axis a vector; other input is returned for the fields to judge."""
    if not isinstance(data, dict):
        return data
    data = dict(data)
    if isinstance(data.get("axis"), str) and data["axis"] in AXES:
        data["axis"] = AXES[data["axis"]]
    drop = "center" if keep == "base" else "base"
    if drop not in data:
        return data
    if keep in data:
        raise ValueError(f"[{drop}] give {keep} or {drop}, not both")
    point, axis = _numbers(data[drop]), _numbers(data.get("axis", AXES["z"]))
    length = data.get("length")
    if (
        point is None
        or axis is None
        or len(point) != len(axis)
        or not isinstance(length, int | float)
    ):
        return data  # reported by the fields (or: a length is needed to place it)
    norm = math.sqrt(sum(c * c for c in axis)) or 1.0
    sign = -0.5 if keep == "base" else 0.5
    data[keep] = [p + sign * float(length) * a / norm for p, a in zip(point, axis, strict=True)]
    del data[drop]
    return data


class CylinderRegionSpec(Strict):
    """3-D cylinder of ``radius`` and ``length`` along ``axis`` (x, y, z or a vector),
    placed by ``base`` (the centre of one end face) or ``center`` (its middle), as a
    rigid cylinder is; stored as ``base`` and an axis vector."""

    base: list[Finite]
    axis: list[Finite]
    radius: PosFloat
    length: PosFloat

    @model_validator(mode="before")
    @classmethod
    def _either_form(cls, data: Any) -> Any:
        return cylinder_placed(data, "base")


class PolygonRegion(Strict):
    """2-D polygon; at least 3 vertices."""

    vertices: list[list[Finite]] = Field(min_length=3)


class HalfSpaceRegion(Strict):
    """Points with (x - point) . normal >= 0."""

    point: list[Finite]
    normal: list[Finite]


class EdgeRegion(Strict):
    """The outermost ``layers`` grid rows on the side the outward ``normal`` points to."""

    normal: list[Finite]
    layers: Annotated[int, Field(ge=1), Num] = 1


class RegionSpec(Strict):
    """Exactly one of the keys below."""

    box: BoxRegion | None = None
    ball: BallRegion | None = None
    circle: BallRegion | None = None
    sphere: BallRegion | None = None
    cylinder: CylinderRegionSpec | None = None
    polygon: PolygonRegion | None = None
    half_space: HalfSpaceRegion | None = None
    edge: EdgeRegion | None = None
    point: list[Finite] | None = None
    everywhere: Literal[True] | None = None
    set: str | None = None
    all_of: list[RegionSpec] | None = Field(default=None, min_length=1)
    any_of: list[RegionSpec] | None = Field(default=None, min_length=1)
    not_: RegionSpec | None = Field(default=None, alias="not")

    model_config = ConfigDict(extra="forbid", frozen=True)

    @model_validator(mode="after")
    def _exactly_one(self) -> RegionSpec:
        given = [k for k in type(self).model_fields if getattr(self, k) is not None]
        if len(given) != 1:
            keys = ", ".join(k.rstrip("_") for k in type(self).model_fields)
            raise ValueError(f"a region needs exactly one of: {keys}; got {given or 'none'}")
        return self

    def kind(self) -> str:
        """The key given."""
        return next(k for k in type(self).model_fields if getattr(self, k) is not None)


# --------------------------------------------------------------------------- checks
def check_len(errors: Errors, path: str, vec: list | tuple | None, dim: int) -> None:
    """Append an error when ``vec`` (if given) has not ``dim`` components."""
    if vec is not None and len(vec) != dim:
        what = "1 component" if dim == 1 else f"{dim} components"
        errors.append((path, f"needs {what} for a {dim}-D model, got {len(vec)}"))


def check_nonzero(errors: Errors, path: str, vec: list | None) -> None:
    """Append an error when ``vec`` (if given) is the zero vector, or so short that its
    length underflows to zero (it is divided by its length)."""
    if vec is not None and not any(vec):
        errors.append((path, "must be a non-zero vector"))
    elif vec is not None and not sum(float(c) * float(c) for c in vec) > 0:
        errors.append((path, "must be a non-zero vector (its length underflows to 0: scale it)"))


def check_region(errors: Errors, path: str, r: RegionSpec, dim: int, sets: set[str]) -> None:
    """Append the errors of region ``r`` at ``path``: vector lengths for a ``dim``-D
    model, non-zero normals and axes, node sets named in ``sets``."""
    k = r.kind()
    val = getattr(r, k)
    if k == "box":
        check_len(errors, f"{path}.box.min", val.min, dim)
        check_len(errors, f"{path}.box.max", val.max, dim)
    elif k in ("ball", "circle", "sphere"):
        check_len(errors, f"{path}.{k}.center", val.center, dim)
    elif k == "cylinder":
        if dim != 3:
            errors.append((f"{path}.cylinder", "cylinder regions are 3-D"))
        check_len(errors, f"{path}.cylinder.base", val.base, 3)
        check_len(errors, f"{path}.cylinder.axis", val.axis, 3)
        check_nonzero(errors, f"{path}.cylinder.axis", val.axis)
    elif k == "polygon":
        if dim != 2:
            errors.append((f"{path}.polygon", "polygon regions are 2-D"))
        for n, v in enumerate(val.vertices):
            check_len(errors, f"{path}.polygon.vertices.{n}", v, 2)
    elif k == "half_space":
        check_len(errors, f"{path}.half_space.point", val.point, dim)
        check_len(errors, f"{path}.half_space.normal", val.normal, dim)
        check_nonzero(errors, f"{path}.half_space.normal", val.normal)
    elif k == "edge":
        check_len(errors, f"{path}.edge.normal", val.normal, dim)
        check_nonzero(errors, f"{path}.edge.normal", val.normal)
    elif k == "point":
        check_len(errors, f"{path}.point", val, dim)
    elif k == "set":
        if val not in sets:
            errors.append((f"{path}.set", f"unknown node set {val!r}; known: {sorted(sets)}"))
    elif k in ("all_of", "any_of"):
        for n, sub in enumerate(val):
            check_region(errors, f"{path}.{k}.{n}", sub, dim, sets)
    elif k == "not_":
        check_region(errors, f"{path}.not", val, dim, sets)


def uses(r: RegionSpec, kinds: set[str]) -> bool:
    """Whether region ``r`` or a region nested in it is of one of ``kinds``."""
    k = r.kind()
    v = getattr(r, k)
    if k in kinds:
        return True
    if k in ("all_of", "any_of"):
        return any(uses(x, kinds) for x in v)
    return k == "not_" and uses(v, kinds)


def node_set_names(deck: Any) -> set[str]:
    """The node sets a deck may name: its ``node_sets``, ``all``, and with several
    bodies ``main`` and every body (a body is a node set of its name)."""
    sets = set(deck.node_sets) | {"all"}
    if deck.bodies or deck.interfaces:
        sets |= {"main", *(b.name for b in deck.bodies)}
    return sets


def node_set_errors(deck: Any, sets: set[str]) -> Errors:
    """Checks of ``node_sets``: each region against the dimension and the other sets."""
    errors: Errors = []
    for name, region in deck.node_sets.items():
        check_region(errors, f"node_sets.{name}", region, deck.dim, sets - {name})
    return errors
