"""Deck sections of a model with several bodies: ``bodies``, ``interfaces``,
``rigid_bodies`` (see ``docs/deck.md``, section "Several bodies").

The deck's ``geometry``, ``material`` and ``damage`` describe the first deformable body,
named ``main``. Each entry of ``bodies`` adds a deformable body: either the points of
the main geometry inside a ``region`` (an inclusion, an aggregate) or a separate
``geometry`` (a second specimen); its material and damage default to the deck's.
Bonds join points of one body only; ``interfaces`` bond two bodies with their own
stiffness and strength. ``rigid_bodies`` are platens, supports, indenters and strikers:
analytic shapes or point sets that touch the deformable points through contact only.

"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from peridynamics.deck.damage import Damage
from peridynamics.deck.geometry import Geometry, geometry_dim
from peridynamics.deck.materials import AnyMaterial
from peridynamics.deck.regions import RegionSpec, check_len, check_region, cylinder_placed
from peridynamics.deck.time_functions import TimeFunctionSpec
from peridynamics.deck.types import Errors, Finite, NonNegFloat, PosFloat, Strict

Name = Annotated[str, Field(min_length=1, max_length=60, pattern=r"^[A-Za-z][A-Za-z0-9_]*$")]


def _length2(vec: list[float]) -> float:
    """Squared length of a vector (0 for the zero vector, or one so short that its
    length underflows: a direction divided by its length)."""
    return sum(float(c) * float(c) for c in vec)


class BodySpec(Strict):
    """A further deformable body: ``region`` (carved out of the main geometry) or
    ``geometry`` (new points); ``material`` and ``damage`` default to the deck's."""

    name: Name
    region: RegionSpec | None = None
    geometry: Geometry | None = None
    material: AnyMaterial | None = None
    damage: Damage | None = None

    @model_validator(mode="after")
    def _where(self) -> BodySpec:
        if (self.region is None) == (self.geometry is None):
            raise ValueError(
                "[region] give exactly one of region (points of the main geometry inside "
                "it) or geometry (a separate body)"
            )
        return self


class InterfaceSpec(Strict):
    """How two deformable bodies meet: ``bonded`` (interface bonds with their own
    stiffness and strength) or ``contact`` (no bonds; contact forces when
    ``contact`` is on)."""

    bodies: list[Name] = Field(min_length=2, max_length=2)
    type: Literal["bonded", "contact"] = "bonded"
    stiffness_factor: PosFloat = 1.0
    critical_stretch: PosFloat | None = None
    fracture_energy: PosFloat | None = None

    @model_validator(mode="after")
    def _strength(self) -> InterfaceSpec:
        if self.bodies[0] == self.bodies[1]:
            raise ValueError("[bodies] an interface joins two different bodies")
        if self.type == "contact":
            if self.critical_stretch is not None or self.fracture_energy is not None:
                raise ValueError(
                    "[type] a contact interface has no bonds: remove critical_stretch / "
                    "fracture_energy or use type 'bonded'"
                )
        elif self.critical_stretch is not None and self.fracture_energy is not None:
            raise ValueError(
                "[critical_stretch] give at most one of critical_stretch or fracture_energy "
                "(neither: interface bonds never break)"
            )
        return self


class PlaneShape(Strict):
    """Half-space behind the plane through ``point`` with outward ``normal``."""

    point: list[Finite]
    normal: list[Finite]


class BoxShape(Strict):
    """Axis-aligned solid box (in its initial position)."""

    min: list[Finite]
    max: list[Finite]

    @model_validator(mode="after")
    def _order(self) -> BoxShape:
        if len(self.min) != len(self.max):
            raise ValueError("[max] min and max need the same number of components")
        if any(a >= b for a, b in zip(self.min, self.max, strict=True)):
            raise ValueError(f"[max] min {self.min} must be < max {self.max} component-wise")
        return self


class SphereShape(Strict):
    """Solid sphere (3-D) or disc (2-D)."""

    center: list[Finite]
    radius: PosFloat


class CylinderShape(Strict):
    """Solid capped cylinder (3-D: ``axis`` x, y or z, or a vector along one of them,
    and ``length``); placed by ``center`` (its middle) or ``base`` (the centre of one end
    face), as a node-set cylinder is; in 2-D a disc."""

    center: list[Finite]
    radius: PosFloat
    axis: Literal["x", "y", "z"] = "z"
    length: PosFloat | None = None

    @model_validator(mode="before")
    @classmethod
    def _either_form(cls, data: Any) -> Any:
        if isinstance(data, dict) and "base" in data and data.get("length") is None:
            raise ValueError("[length] a cylinder placed by its base needs its length (m)")
        data = cylinder_placed(data, "center")
        if isinstance(data, dict) and isinstance(data.get("axis"), list | tuple):
            axis = [abs(float(c)) if isinstance(c, int | float) else 0.0 for c in data["axis"]]
            along = [k for k, c in enumerate(axis) if c > 1e-12 * max(axis, default=0.0)]
            if len(along) != 1 or along[0] > 2:
                raise ValueError(
                    f"[axis] a rigid cylinder's axis is along x, y or z (got {data['axis']})"
                )
            data["axis"] = "xyz"[along[0]]
        return data


class RigidShapeSpec(Strict):
    """Exactly one of: plane, box, sphere, cylinder (analytic), points (a geometry
    whose points are the rigid body)."""

    plane: PlaneShape | None = None
    box: BoxShape | None = None
    sphere: SphereShape | None = None
    cylinder: CylinderShape | None = None
    points: Geometry | None = None

    @model_validator(mode="after")
    def _one(self) -> RigidShapeSpec:
        given = [k for k in type(self).model_fields if getattr(self, k) is not None]
        if len(given) != 1:
            keys = ", ".join(type(self).model_fields)
            raise ValueError(f"a rigid shape needs exactly one of: {keys}; got {given or 'none'}")
        return self

    def kind(self) -> str:
        """The key given."""
        return next(k for k in type(self).model_fields if getattr(self, k) is not None)


class RigidBodySpec(Strict):
    """A rigid body. ``motion: prescribed`` (default) moves it with ``velocity`` (m/s)
    times ``time_function`` (default 1); ``motion: free`` integrates its translation and
    rotation under the contact forces from ``velocity`` / ``angular_velocity`` at t = 0,
    with the mass of ``density`` times its volume. ``touch: true`` first moves the body
    along its velocity (``touch: [direction]``: along that vector) until it just touches
    the deformable points (seating), so the gap a grid leaves below a curved or offset
    surface does not delay the loading."""

    name: Name
    shape: RigidShapeSpec
    motion: Literal["prescribed", "free"] = "prescribed"
    velocity: list[Finite] | None = None
    time_function: TimeFunctionSpec | None = None
    angular_velocity: list[Finite] | None = None
    density: PosFloat | None = None
    touch: bool | list[Finite] = False
    friction_static: NonNegFloat | None = None
    friction_kinetic: NonNegFloat | None = None

    @model_validator(mode="after")
    def _motion(self) -> RigidBodySpec:
        if self.motion == "free":
            if self.density is None:
                raise ValueError("[density] a free rigid body needs its density (kg/m^3)")
            if self.time_function is not None:
                raise ValueError(
                    "[time_function] a free rigid body moves under its contact forces; "
                    "time_function belongs to motion 'prescribed'"
                )
            if self.shape.plane is not None:
                raise ValueError("[shape] a plane has no finite mass: it cannot be free")
        elif self.angular_velocity is not None:
            raise ValueError("[angular_velocity] only a free rigid body rotates")
        if self.touch is True and (self.velocity is None or not _length2(self.velocity) > 0):
            raise ValueError(
                "[touch] true moves the body along its velocity: give a velocity, or give "
                "touch a direction (a vector, e.g. [0, 1] for a fixed support below)"
            )
        if isinstance(self.touch, list) and not _length2(self.touch) > 0:
            raise ValueError("[touch] the direction must not be zero")
        if self.touch and self.shape.points is not None:
            raise ValueError("[touch] works with analytic shapes (plane, box, sphere, cylinder)")
        fs, fk = self.friction_static, self.friction_kinetic
        if fs is not None and fk is not None and fk > fs:
            raise ValueError(
                f"[friction_kinetic] {fk} must be <= friction_static {fs} (Coulomb friction)"
            )
        if (fs is None) != (fk is None):
            raise ValueError("[friction_static] give both friction_static and friction_kinetic")
        return self


def bodies_errors(deck: Any, geometry_sets: set[str] | None = None) -> Errors:
    """Cross-section checks of ``bodies``, ``interfaces`` and ``rigid_bodies``: vector
    lengths, unique names, known bodies; a body's ``region`` may name the node sets of
    ``geometry_sets`` (an image's phases, a mesh's groups: a body per phase)."""
    errors: Errors = []
    dim = deck.dim
    names = ["main"]
    for k, b in enumerate(deck.bodies):
        path = f"bodies.{k}"
        if b.name in names:
            errors.append(
                (f"{path}.name", f"body name {b.name!r} is used twice ('main' is the deck's)")
            )
        names.append(b.name)
        if b.region is not None:
            check_region(errors, f"{path}.region", b.region, dim, set(geometry_sets or ()))
        if getattr(b.material, "plasticity", None) is not None:
            errors.append((f"{path}.material.plasticity", "plasticity runs in a single body"))
        if getattr(b.material, "viscoelastic", None) is not None:
            errors.append(
                (f"{path}.material.viscoelastic", "viscoelasticity runs in a single body")
            )
        if b.geometry is not None and geometry_dim(b.geometry) != dim:
            errors.append(
                (f"{path}.geometry", f"a {geometry_dim(b.geometry)}-D body in a {dim}-D deck")
            )
    for k, i in enumerate(deck.interfaces):
        for n in i.bodies:
            if n not in names:
                errors.append((f"interfaces.{k}.bodies", f"unknown body {n!r}; bodies are {names}"))
    rigid: list[str] = []
    for k, r in enumerate(deck.rigid_bodies):
        path = f"rigid_bodies.{k}"
        if r.name in names or r.name in rigid:
            errors.append((f"{path}.name", f"name {r.name!r} is used twice"))
        rigid.append(r.name)
        check_len(errors, f"{path}.velocity", r.velocity, dim)
        shape = r.shape
        kind = shape.kind()
        spec = getattr(shape, kind)
        if kind == "points":
            if geometry_dim(spec) != dim:
                errors.append(
                    (f"{path}.shape.points", f"a {geometry_dim(spec)}-D body in a {dim}-D deck")
                )
            continue
        for key in ("point", "normal", "min", "max", "center"):
            check_len(errors, f"{path}.shape.{kind}.{key}", getattr(spec, key, None), dim)
        if kind == "plane" and not _length2(spec.normal) > 0:
            errors.append((f"{path}.shape.plane.normal", "the normal must not be zero"))
        if kind == "cylinder" and dim == 3 and spec.length is None:
            errors.append((f"{path}.shape.cylinder.length", "a 3-D cylinder needs its length (m)"))
        w = r.angular_velocity
        if w is not None and len(w) != (1 if dim == 2 else 3):
            errors.append(
                (f"{path}.angular_velocity", f"give {1 if dim == 2 else 3} number(s) in {dim}-D")
            )
    if deck.rigid_bodies and dim == 1:
        errors.append(("rigid_bodies", "rigid bodies need a 2-D or 3-D model"))
    return errors


__all__ = [
    "BodySpec",
    "InterfaceSpec",
    "RigidBodySpec",
    "RigidShapeSpec",
    "bodies_errors",
]
