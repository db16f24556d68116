"""Deck section ``boundary_conditions``: prescribed displacements and velocities,
fixed components, initial velocities, body forces, tractions and pressures, and their
checks against the model's dimension, family and node sets."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import Field, PlainValidator, model_validator

from peridynamics.deck.regions import check_len, check_nonzero
from peridynamics.deck.time_functions import BlastTF, ConstantTF, TimeFunctionSpec
from peridynamics.deck.types import Component, Errors, Finite, PosFloat, Strict
from peridynamics.io.options import MAX_MAGNITUDE


class _OnSet(Strict):
    set: str


class DisplacementBC(_OnSet):
    """Prescribed displacement components (m), times a time function."""

    type: Literal["displacement"]
    components: dict[Component, Finite] = Field(min_length=1)
    time_function: TimeFunctionSpec = ConstantTF(type="constant")


class VelocityBC(_OnSet):
    """Prescribed velocity components (m/s), times a time function."""

    type: Literal["velocity"]
    components: dict[Component, Finite] = Field(min_length=1)
    time_function: TimeFunctionSpec = ConstantTF(type="constant")


class FixedBC(_OnSet):
    """u = v = 0 for the listed components (all if omitted). ``rotation`` (micropolar
    models) fixes the point rotation too; omitting ``components`` clamps everything."""

    type: Literal["fixed"]
    components: list[Component | Literal["rotation"]] | None = Field(default=None, min_length=1)


def _field_component(v: Any) -> float | str:
    """One component of an initial field: a finite number, or an expression of the
    coordinates (checked here by :class:`peridynamics.loading.initial_fields.FieldExpression`)."""
    if isinstance(v, bool):
        raise ValueError("a number or an expression of x, y, z is expected, not true/false")
    if isinstance(v, int | float):
        if not math.isfinite(v):
            raise ValueError("Input should be a finite number")
        if abs(v) > MAX_MAGNITUDE:
            raise ValueError(
                f"a number between -{MAX_MAGNITUDE:.0e} and {MAX_MAGNITUDE:.0e} is expected; "
                "check the exponent and the units"
            )
        return float(v)
    if isinstance(v, str):
        from peridynamics.loading.initial_fields import FieldExpression

        FieldExpression(v)  # raises ValueError saying what is not allowed
        return v
    raise ValueError("a number or an expression of x, y, z (in quotes) is expected")


#: a number, or an expression of x, y, z (t = 0) such as "-50.0 * sin(pi * x / 0.01)"
FieldValue = Annotated[float | str, PlainValidator(_field_component)]


class InitialVelocityBC(_OnSet):
    """v(0) (m/s) from value (numbers or expressions of x, y, z) or file (.npy/.csv).

    ``value`` has one number or expression of x, y, z per component; ``file`` holds the
    point values (one row per point of the set, or per point of the body)."""

    type: Literal["initial_velocity"]
    value: list[FieldValue] | None = None
    file: str | None = None

    @model_validator(mode="after")
    def _one_source(self) -> InitialVelocityBC:
        if (self.value is None) == (self.file is None):
            raise ValueError(
                "[value] give exactly one of value (a vector of numbers or expressions "
                "of x, y, z) or file (a .npy or .csv file of point values)"
            )
        if self.file is not None and Path(self.file).suffix.lower() not in (".npy", ".csv"):
            raise ValueError(f"[file] use a .npy or a .csv file, got {self.file!r}")
        return self


class BodyForceBC(_OnSet):
    """Body-force density b = value * f(t) (N/m^3)."""

    type: Literal["body_force"]
    value: list[Finite]
    time_function: TimeFunctionSpec = ConstantTF(type="constant")


class TractionBC(_OnSet):
    """Surface traction (Pa) applied as a body force over the set's layer."""

    type: Literal["traction"]
    value: list[Finite]
    normal: list[Finite] | None = None
    layer_thickness: PosFloat | None = None
    time_function: TimeFunctionSpec = ConstantTF(type="constant")


class PressureBC(_OnSet):
    """Pressure p (Pa, > 0 pushes against the outward ``normal``), as a layer body force.

    Give either ``normal`` (a flat face) or ``center`` (a cavity: the pressure pushes every
    node radially away from the centre). With a ``blast`` time function (which gives Pa)
    ``value`` is a dimensionless multiplier, 1 by default.
    """

    type: Literal["pressure"]
    value: Finite | None = None
    normal: list[Finite] | None = None
    center: list[Finite] | None = None
    layer_thickness: PosFloat | None = None
    time_function: TimeFunctionSpec = ConstantTF(type="constant")

    @model_validator(mode="after")
    def _direction_and_value(self) -> PressureBC:
        if (self.normal is None) == (self.center is None):
            raise ValueError(
                "[normal] give exactly one of normal (a flat face) or center (a cavity)"
            )
        if self.value is None and not isinstance(self.time_function, BlastTF):
            raise ValueError(
                "[value] the pressure (Pa) is required unless the time function is a blast"
            )
        return self

    @property
    def scale(self) -> float:
        """The pressure value, or 1 (a multiplier of the blast pressure) when omitted."""
        return 1.0 if self.value is None else self.value


BoundaryCondition = Annotated[
    DisplacementBC
    | VelocityBC
    | FixedBC
    | InitialVelocityBC
    | BodyForceBC
    | TractionBC
    | PressureBC,
    Field(discriminator="type"),
]


# --------------------------------------------------------------------------- checks
def condition_errors(deck: Any, sets: set[str]) -> Errors:
    """Checks of ``boundary_conditions``: node sets, components and vector lengths of
    the model's dimension, rotations only for a family with point rotations."""
    errors: Errors = []
    dim = deck.dim
    for n, bc in enumerate(deck.boundary_conditions):
        path = f"boundary_conditions.{n}"
        if bc.set not in sets:
            errors.append((f"{path}.set", f"unknown node set {bc.set!r}; known: {sorted(sets)}"))
        comps = getattr(bc, "components", None) or []
        for comp in comps:
            if comp == "rotation":
                if not deck.material.point_rotations:
                    errors.append(
                        (
                            f"{path}.components.rotation",
                            "only material.model micropolar has point rotations",
                        )
                    )
                continue
            if "xyz".index(comp) >= dim:
                errors.append(
                    (f"{path}.components.{comp}", f"component {comp!r} does not exist in {dim}-D")
                )
        errors += _vector_errors(bc, path, dim)
    return errors


def _vector_errors(bc: Any, path: str, dim: int) -> Errors:
    """Lengths and non-zero normals of a condition's vectors; the axes its expressions
    of x, y, z use."""
    errors: Errors = []
    for key in ("value", "normal", "center"):
        vec = getattr(bc, key, None)
        if isinstance(vec, list):
            check_len(errors, f"{path}.{key}", vec, dim)
    normal = getattr(bc, "normal", None)
    if normal is not None:
        check_nonzero(errors, f"{path}.normal", normal)
    if isinstance(bc, TractionBC) and bc.normal is None and not any(bc.value):
        errors.append((f"{path}.normal", "give a normal when the traction value is zero"))
    if isinstance(bc, InitialVelocityBC) and bc.value is not None:
        from peridynamics.loading.initial_fields import FieldExpression

        for k, comp in enumerate(bc.value):
            if isinstance(comp, str):
                for name in sorted(FieldExpression(comp).names & {"x", "y", "z"}):
                    if "xyz".index(name) >= dim:
                        errors.append(
                            (f"{path}.value.{k}", f"uses {name!r}: no such axis in {dim}-D")
                        )
    return errors
