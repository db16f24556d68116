"""YAML input decks with a strict schema (pydantic v2).

Every section forbids unknown keys; every number is checked for range; errors name the
key path (``material.youngs_modulus``) and say what is allowed. The schema is documented
with one example per section in ``docs/deck.md``.
"""

from __future__ import annotations

import contextlib
import io
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any, Literal

import yaml
from pydantic import (
    ConfigDict,
    Discriminator,
    Field,
    PlainValidator,
    Tag,
    ValidationError,
    field_validator,
    model_validator,
)

from peridynamics.io.deck_bodies import (
    BodySpec,
    InterfaceSpec,
    RigidBodySpec,
    RigidShapeSpec,
    bodies_errors,
)
from peridynamics.io.deck_help import hint
from peridynamics.io.deck_output import (
    CrackPathSpec,  # noqa: F401 - re-exported
    CrackTip,  # noqa: F401 - re-exported
    Fracture,  # noqa: F401 - re-exported
    Output,
    Period,  # noqa: F401 - re-exported
    Probe,  # noqa: F401 - re-exported
    Quantity,  # noqa: F401 - re-exported
    StressStrain,  # noqa: F401 - re-exported
    WaveComparison,  # noqa: F401 - re-exported
    output_errors,
)
from peridynamics.io.deck_types import (
    Component,
    Finite,
    NonNegFloat,
    PosFloat,
    Strict,
    _Num,
)


class DeckError(ValueError):
    """An invalid deck. ``errors`` is a list of (key path, message)."""

    def __init__(self, errors: list[tuple[str, str]]) -> None:
        self.errors = errors
        lines = [f"{path}: {msg}" if path else msg for path, msg in errors]
        see = hint(path for path, _ in errors)
        super().__init__("invalid deck:\n  " + "\n  ".join(lines) + (f"\n{see}" if see else ""))


# --------------------------------------------------------------------------- regions
class BoxRegion(Strict):
    """Axis-aligned box; ``.inf`` / ``-.inf`` allowed for open sides."""

    min: list[Annotated[float, Field(allow_inf_nan=True), _Num]]
    max: list[Annotated[float, Field(allow_inf_nan=True), _Num]]

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


class CylinderRegionSpec(Strict):
    """3-D cylinder from ``base`` along ``axis`` over ``length``."""

    base: list[Finite]
    axis: list[Finite]
    radius: PosFloat
    length: PosFloat


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
    layers: Annotated[int, Field(ge=1), _Num] = 1


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


# -------------------------------------------------------------------------- geometry
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


# -------------------------------------------------------------------- discretisation
class Discretisation(Strict):
    """Grid spacing and horizon; ``jitter`` (fraction of the spacing, 0 <= jitter < 0.5)
    moves every grid point by a uniform random offset of at most ``jitter * spacing``
    along each axis, drawn from ``seed`` (rectangle, box and cylinder geometries)."""

    spacing: PosFloat
    horizon: PosFloat | None = None
    horizon_factor: Annotated[float, Field(ge=1.0, allow_inf_nan=False), _Num] | None = None
    partial_volume: Literal["truncated", "extended", "none"] = "truncated"
    surface_correction: bool = True  # the nominal E in the interior and at surfaces
    jitter: Annotated[float, Field(allow_inf_nan=False), _Num] = 0.0
    seed: Annotated[int, Field(ge=0), _Num] = 0

    @field_validator("jitter")
    @classmethod
    def _jitter(cls, v: float) -> float:
        if not 0.0 <= v < 0.5:
            raise ValueError(
                "jitter is a fraction of the spacing with 0 <= jitter < 0.5 (each point "
                "moves by at most jitter * spacing along each axis; 0: the regular grid)"
            )
        return v

    @model_validator(mode="after")
    def _horizon(self) -> Discretisation:
        if (self.horizon is None) == (self.horizon_factor is None):
            raise ValueError(
                "[horizon] give exactly one of horizon (m) or horizon_factor (m = delta/dx)"
            )
        if self.horizon is not None and self.horizon < self.spacing * (1 - 1e-9):
            raise ValueError(
                f"[horizon] horizon {self.horizon} m is smaller than spacing {self.spacing} m; "
                "use horizon >= spacing (typically 3.015 * spacing)"
            )
        return self

    @property
    def delta(self) -> float:
        """Horizon (m)."""
        if self.horizon is not None:
            return self.horizon
        assert self.horizon_factor is not None
        return self.horizon_factor * self.spacing


# -------------------------------------------------------------------------- material
class Viscosity(Strict):
    """Viscous bond forces of PD wave dispersion (n.d.) (eqs 53-56): b1 (linear), b2 (quadratic)."""

    linear: NonNegFloat = 0.0
    quadratic: NonNegFloat = 0.0


class Material(Strict):
    """Bond-based PMB material (``model: pmb``, the default)."""

    model: Literal["pmb", "bond_based"] = "pmb"
    youngs_modulus: PosFloat
    density: PosFloat
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5, allow_inf_nan=False), _Num] | None = None
    micromodulus_profile: Literal["constant", "conical"] = "constant"
    micromodulus: PosFloat | None = None  # N/m^6: overrides the energy-equivalent c
    viscosity: Viscosity | None = None


class LPSMaterialSpec(Strict):
    """Ordinary state-based linear peridynamic solid (``model: lps``; Silling et al.
    2007, 2-D forms of Le et al. 2014): any Poisson ratio in the admissible range."""

    model: Literal["lps"]
    youngs_modulus: PosFloat
    density: PosFloat
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5, allow_inf_nan=False), _Num] = 0.25
    influence: Literal["constant", "inverse"] = "constant"
    viscosity: Viscosity | None = None


class MicropolarMaterialSpec(Strict):
    """Micropolar bond-based material (``model: micropolar``; 2-D): axial, shear and
    rotational bond springs, every point with (u, v, theta); Zhou, Zhu & Li (n.d.),
    Diana & Casolo 2019. ``poisson_ratio`` up to 1/3 (plane stress) or 1/4 (plane
    strain); ``rotational_stiffness_ratio`` = k_phi / k_t (1/12: beam lattice)."""

    model: Literal["micropolar"]
    youngs_modulus: PosFloat
    density: PosFloat
    poisson_ratio: Annotated[float, Field(gt=-1.0, le=1.0 / 3.0, allow_inf_nan=False), _Num] = 0.25
    rotational_stiffness_ratio: NonNegFloat = 1.0 / 12.0


class CorrespondenceMaterialSpec(Strict):
    """Correspondence (non-ordinary state-based) material (``model: correspondence``;
    2-D and 3-D): deformation gradient, a classical stress law and zero-energy-mode
    control (PD zero-energy modes (n.d.); Silling 2017). ``stabilization``: ``lbscmm``
    (default, parameter-free), ``silling2017`` (penalty ``stabilization_g``,
    dimensionless: Silling's G over the horizon volume, default 0.1) or ``none``."""

    model: Literal["correspondence"]
    youngs_modulus: PosFloat
    density: PosFloat
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5, allow_inf_nan=False), _Num] = 0.25
    stabilization: Literal["lbscmm", "silling2017", "none"] = "lbscmm"
    stabilization_g: PosFloat | None = None
    law: Literal["st_venant_kirchhoff", "linear_elastic"] = "st_venant_kirchhoff"

    @model_validator(mode="after")
    def _g_only_for_silling(self) -> CorrespondenceMaterialSpec:
        if self.stabilization_g is not None and self.stabilization != "silling2017":
            raise ValueError(
                "[stabilization_g] is the penalty of stabilization 'silling2017'; remove it "
                f"or set stabilization: silling2017 (got {self.stabilization!r})"
            )
        return self


#: the registry of model families: deck name -> schema of its material section
MATERIAL_SCHEMAS: dict[str, type[Strict]] = {
    "pmb": Material,
    "bond_based": Material,
    "lps": LPSMaterialSpec,
    "micropolar": MicropolarMaterialSpec,
    "correspondence": CorrespondenceMaterialSpec,
}


def _tag(default: str, key: str) -> Any:
    def pick(v: Any) -> str:
        if isinstance(v, dict):
            return str(v.get(key, default))
        return str(getattr(v, key, default))

    return pick


AnyMaterial = Annotated[
    Annotated[Material, Tag("pmb")]
    | Annotated[Material, Tag("bond_based")]
    | Annotated[LPSMaterialSpec, Tag("lps")]
    | Annotated[MicropolarMaterialSpec, Tag("micropolar")]
    | Annotated[CorrespondenceMaterialSpec, Tag("correspondence")],
    Discriminator(_tag("pmb", "model")),
]


class WeibullSpec(Strict):
    """Weibull heterogeneity of the critical stretch (SED-PD (2021), eqs 25-26)."""

    shape: PosFloat
    seed: Annotated[int, Field(ge=0), _Num] = 0
    variable: Literal["fracture_energy", "critical_stretch"] = "fracture_energy"
    u0_is: Literal["scale", "mean"] = "scale"


class SEDSofteningSpec(Strict):
    """Strain-energy-density softening (SED-PD (2021), eqs 18-24)."""

    levels: Annotated[int, Field(ge=1, le=1000), _Num] = 10
    k_c: Annotated[float, Field(gt=1, allow_inf_nan=False), _Num] = 4.0
    residual: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False), _Num] = 0.05
    threshold_stretch: PosFloat | None = None
    energy: Literal["total", "tensile"] = "total"


class Damage(Strict):
    """Bond breaking: ``critical_stretch`` (s0 or fracture_energy; with
    ``tensile_strength`` too, a bond breaks at whichever comes first),
    ``principal_stress`` (``tensile_strength`` only: the mean of the two points' largest
    principal stresses, correspondence models) or ``none``. ``bond_law`` ``bilinear`` /
    ``trilinear`` (PMB only) replaces the brittle bond by a tension-softening one: peak
    at s0 = tensile_strength / E, the failure stretch from fracture_energy;
    ``trilinear_knee`` [r, beta] places the knee (default Petersson's [2/9, 1/3])."""

    model: Literal["critical_stretch", "principal_stress", "none"] = "critical_stretch"
    critical_stretch: PosFloat | None = None
    fracture_energy: PosFloat | None = None
    tensile_strength: PosFloat | None = None
    no_fail: list[str] = []
    weibull: WeibullSpec | None = None
    sed_softening: SEDSofteningSpec | None = None
    bond_law: Literal["brittle", "bilinear", "trilinear"] = "brittle"
    trilinear_knee: tuple[Finite, Finite] | None = None

    @model_validator(mode="after")
    def _one(self) -> Damage:
        if self.trilinear_knee is not None:
            if self.bond_law != "trilinear":
                raise ValueError("[trilinear_knee] is only used with bond_law 'trilinear'")
            for name, v in zip(("r", "beta"), self.trilinear_knee, strict=True):
                if not 0.0 < v < 1.0:
                    raise ValueError(f"[trilinear_knee] {name} must be in (0, 1), got {v}")
        if self.bond_law != "brittle":
            law = f"bond_law {self.bond_law!r}"
            if self.model != "critical_stretch":
                raise ValueError(f"[bond_law] {law} needs model 'critical_stretch'")
            if self.critical_stretch is not None:
                raise ValueError(
                    f"[critical_stretch] {law} takes tensile_strength (the peak, s0 = f_t/E) "
                    "and fracture_energy (the tail), not critical_stretch"
                )
            for key in ("tensile_strength", "fracture_energy"):
                if getattr(self, key) is None:
                    raise ValueError(
                        f"[{key}] {law} needs tensile_strength (f_t, Pa) and "
                        "fracture_energy (G0, J/m^2)"
                    )
            for key in ("sed_softening", "weibull"):
                if getattr(self, key) is not None:
                    raise ValueError(f"[{key}] does not combine with {law}; use bond_law 'brittle'")
            return self
        if self.model == "none":
            if self.critical_stretch is not None or self.fracture_energy is not None:
                raise ValueError(
                    "[model] model 'none' takes neither critical_stretch nor fracture_energy"
                )
            if self.tensile_strength is not None:
                raise ValueError("[tensile_strength] has no effect with model 'none'; remove it")
            if self.weibull is not None or self.sed_softening is not None:
                raise ValueError("[model] weibull and sed_softening need model 'critical_stretch'")
        elif self.model == "principal_stress":
            if self.tensile_strength is None:
                raise ValueError(
                    "[tensile_strength] model 'principal_stress' needs tensile_strength (f_t, Pa)"
                )
            if self.critical_stretch is not None or self.fracture_energy is not None:
                raise ValueError(
                    "[model] model 'principal_stress' uses tensile_strength only; for both "
                    "criteria use model 'critical_stretch' with tensile_strength"
                )
            if self.weibull is not None or self.sed_softening is not None:
                raise ValueError("[model] weibull and sed_softening need model 'critical_stretch'")
        elif (self.critical_stretch is None) == (self.fracture_energy is None):
            raise ValueError(
                "[critical_stretch] give exactly one of critical_stretch (s0) "
                "or fracture_energy (G0, J/m^2)"
            )
        return self


# --------------------------------------------------------------------- time functions
class ConstantTF(Strict):
    """f(t) = value."""

    type: Literal["constant"]
    value: Finite = 1.0


class RampTF(Strict):
    """0 at start, 1 at end, then 1."""

    type: Literal["ramp"]
    end: PosFloat
    start: NonNegFloat = 0.0

    @model_validator(mode="after")
    def _order(self) -> RampTF:
        if self.end <= self.start:
            raise ValueError(f"[end] end ({self.end} s) must be > start ({self.start} s)")
        return self


class TableTF(Strict):
    """Piecewise-linear table."""

    type: Literal["table"]
    times: list[NonNegFloat] = Field(min_length=2)
    values: list[Finite] = Field(min_length=2)

    @model_validator(mode="after")
    def _table(self) -> TableTF:
        if len(self.times) != len(self.values):
            raise ValueError("[values] times and values need the same length")
        if any(b <= a for a, b in zip(self.times, self.times[1:], strict=False)):
            raise ValueError("[times] times must increase strictly")
        return self


class TriangularPulseTF(Strict):
    """Triangle: 0 -> peak at rise_time -> 0 at duration."""

    type: Literal["triangular_pulse"]
    peak: Finite = 1.0
    rise_time: PosFloat
    duration: PosFloat

    @model_validator(mode="after")
    def _order(self) -> TriangularPulseTF:
        if self.rise_time >= self.duration:
            raise ValueError(
                f"[rise_time] rise_time ({self.rise_time} s) must be < duration ({self.duration} s)"
            )
        return self


class SinePulseTF(Strict):
    """One sine period: sin(2 pi t / duration) for 0 <= t <= duration, then 0."""

    type: Literal["sine_pulse"]
    duration: PosFloat


class SquarePulseTF(Strict):
    """1 for 0 <= t <= duration, then 0."""

    type: Literal["square_pulse"]
    duration: PosFloat


class BlastTF(Strict):
    """Reflected blast pressure (Pa) of a TNT charge (Kingery-Bulmash, UFC 3-340-02)."""

    type: Literal["blast"]
    charge_kg: PosFloat
    standoff_m: PosFloat
    shape: Literal["triangular", "friedlander"] = "triangular"
    delay: NonNegFloat = 0.0


TimeFunctionSpec = Annotated[
    ConstantTF | RampTF | TableTF | TriangularPulseTF | SinePulseTF | SquarePulseTF | BlastTF,
    Field(discriminator="type"),
]


# ---------------------------------------------------------------- boundary conditions
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


class Precrack(Strict):
    """2 points (2-D segment) or 3 points (3-D rectangle corner p0, p1, p2)."""

    points: list[list[Finite]] = Field(min_length=2, max_length=3)


class NotchSpec(Strict):
    """A slot of ``width`` along start -> end ([x, y]; along z in 3-D): removes the points
    inside it and cuts the bonds across its centre line like a pre-crack.

    A notch is a top-level list, not a region kind of ``geometry.holes``: a region can
    only remove points, and a notch narrower than the spacing removes none, so its
    defining effect, the bonds cut across it, has to reach the bond builder as the
    ``precracks`` do. It applies to every deformable point of the model (the main
    geometry and every body). ``tip``: ``flat`` (square end at ``end``) or ``round`` (a
    half-disc of radius width/2 beyond ``end``). ``z``: 3-D only, the slot's extent
    [z_min, z_max] (m); left out, the slot runs through the whole body along z.
    """

    start: list[Finite]
    end: list[Finite]
    width: PosFloat
    tip: Literal["flat", "round"] = "flat"
    z: tuple[Finite, Finite] | None = None

    @model_validator(mode="after")
    def _z_order(self) -> NotchSpec:
        if self.z is not None and not self.z[0] < self.z[1]:
            raise ValueError(f"[z] the z-range [z_min, z_max] needs z_min < z_max, got {self.z}")
        return self


# ----------------------------------------------------------------------------- solver
class Hybrid(Strict):
    """Run a cheap first model until the stretch reaches ``switch_fraction`` x s0, then
    the deck's peridynamic model (Lu & Wang (2016), section 3.3)."""

    first: Literal["fdm", "pd"]
    first_horizon_factor: Annotated[float, Field(ge=1.0, allow_inf_nan=False), _Num] = 1.0
    switch_fraction: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False), _Num] = 0.9


class Solver(Strict):
    """Explicit dynamics (``type: explicit``, the default)."""

    type: Literal["explicit"] = "explicit"
    method: Literal["pd", "fdm"] = "pd"
    hybrid: Hybrid | None = None
    integrator: Literal["velocity_verlet", "central_difference"] = "velocity_verlet"
    time_step: PosFloat | None = None
    safety_factor: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False), _Num] = 0.8
    end_time: PosFloat | None = None
    steps: Annotated[int, Field(gt=0), _Num] | None = None
    allow_unstable: bool = False
    blowup_factor: PosFloat = 1.0
    max_stretch: PosFloat = 1.0
    check_every: Annotated[int, Field(gt=0), _Num] = 10
    damping: NonNegFloat = 0.0  # mass-proportional damping coefficient (1/s)
    precision: Literal["float64", "float32"] = "float64"
    backend: Literal["numba", "warp"] = "numba"
    device: Literal["auto", "cuda", "cpu"] = "auto"

    @model_validator(mode="after")
    def _length(self) -> Solver:
        if (self.end_time is None) == (self.steps is None):
            raise ValueError("[end_time] give exactly one of end_time (s) or steps")
        if self.method == "fdm" and self.hybrid is not None:
            raise ValueError(
                "[hybrid] a hybrid run switches to the deck's PD model: "
                "use method: pd with hybrid: {first: fdm}"
            )
        return self


# ----------------------------------------------------------------------------- output


def _numba_only(data: Any, solver: str) -> Any:
    """``backend``/``device`` in a static solver's section: ``numba`` is accepted (and
    dropped), anything else is refused with the reason (the Warp backend runs explicit
    dynamics only)."""
    if isinstance(data, dict) and ("backend" in data or "device" in data):
        data = dict(data)
        if data.get("backend", "numba") != "numba" or "device" in data:
            raise ValueError(
                f"[backend] the Warp backend runs explicit dynamics only; solver.type "
                f"{solver} runs on the Numba backend: remove solver.backend / solver.device"
            )
        data.pop("backend", None)
    return data


class ADRSolverSpec(Strict):
    """Adaptive dynamic relaxation to static equilibrium (``type: adr``; Kilic & Madenci
    2010), loads applied in ``load_steps`` proportional steps, damage committed per
    accepted load step."""

    type: Literal["adr"]
    load_steps: Annotated[int, Field(ge=1, le=1_000_000), _Num] = 1
    tolerance: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False), _Num] = 1e-8
    max_iterations: Annotated[int, Field(ge=1), _Num] = 200_000
    proportional: bool = True
    max_damage_rounds: Annotated[int, Field(ge=1), _Num] = 50

    @model_validator(mode="before")
    @classmethod
    def _backend(cls, data: Any) -> Any:
        return _numba_only(data, "adr")


class StaticSolverSpec(Strict):
    """Implicit static solver (``type: static``): Newton iterations on the unbalanced
    force with the model's tangent, ``load_steps`` load levels (cut back when Newton
    does not converge), prescribed displacements eliminated, and bond breaking between
    solves (scheme A, B or C of Zhou, Zhu & Li (n.d.)); ``linear_solver`` auto picks a
    direct solver up to 250 000 free dofs and AMG-preconditioned CG above."""

    type: Literal["static"]
    load_steps: Annotated[int, Field(ge=1, le=1_000_000), _Num] = 10
    tolerance: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False), _Num] = 1e-8
    max_iterations: Annotated[int, Field(ge=1, le=10_000), _Num] = 20
    max_cutbacks: Annotated[int, Field(ge=0, le=60), _Num] = 6
    proportional: bool = True
    linear_solver: Literal["auto", "direct", "iterative"] = "auto"
    breaking: Literal["A", "B", "C"] = "C"
    bonds_per_event: Annotated[int, Field(ge=1), _Num] = 4
    event_driven: bool = True
    reuse_factorization: bool = True
    max_solves: Annotated[int, Field(ge=1), _Num] = 1_000_000

    @model_validator(mode="before")
    @classmethod
    def _backend(cls, data: Any) -> Any:
        return _numba_only(data, "static")


#: the registry of solvers: deck name -> schema of its section
SOLVER_SCHEMAS: dict[str, type[Strict]] = {
    "explicit": Solver,
    "adr": ADRSolverSpec,
    "static": StaticSolverSpec,
}

AnySolver = Annotated[
    Annotated[Solver, Tag("explicit")]
    | Annotated[ADRSolverSpec, Tag("adr")]
    | Annotated[StaticSolverSpec, Tag("static")],
    Discriminator(_tag("explicit", "type")),
]


class Contact(Strict):
    """Short-range repulsion between points not joined by an intact bond, with Coulomb
    friction (``friction_static`` >= ``friction_kinetic``, both 0 by default)."""

    distance_factor: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False), _Num] = 0.9
    stiffness_factor: PosFloat = 15.0
    friction_static: NonNegFloat = 0.0
    friction_kinetic: NonNegFloat = 0.0

    @model_validator(mode="after")
    def _coulomb(self) -> Contact:
        if self.friction_kinetic > self.friction_static:
            raise ValueError(
                f"[friction_kinetic] {self.friction_kinetic} must be <= friction_static "
                f"{self.friction_static} (Coulomb friction)"
            )
        return self


# the sections of a model with several bodies refer to the schemas above
for _schema in (BodySpec, InterfaceSpec, RigidShapeSpec, RigidBodySpec):
    _schema.model_rebuild(_types_namespace=globals())


class Deck(Strict):
    """A whole simulation."""

    name: str = Field(min_length=1, max_length=100, pattern=r"^[A-Za-z0-9_.-]+$")
    description: str = ""
    geometry: Geometry
    discretisation: Discretisation
    material: AnyMaterial
    damage: Damage = Damage(model="none")
    node_sets: dict[str, RegionSpec] = {}
    precracks: list[Precrack] = []
    notches: list[NotchSpec] = []
    contact: Contact | None = None
    bodies: list[BodySpec] = []
    interfaces: list[InterfaceSpec] = []
    rigid_bodies: list[RigidBodySpec] = []
    boundary_conditions: list[BoundaryCondition] = []
    solver: AnySolver
    output: Output = Output()

    @field_validator("name")
    @classmethod
    def _file_stem(cls, v: str) -> str:
        if v in (".", ".."):
            raise ValueError("the name becomes a file name: use letters, digits, _ . -")
        return v

    @field_validator("node_sets")
    @classmethod
    def _names(cls, v: dict[str, RegionSpec]) -> dict[str, RegionSpec]:
        for name in v:
            if not name:
                raise ValueError("node set names must not be empty")
            if name == "all":
                raise ValueError("[all] 'all' is built in (every point); choose another name")
        return v

    @property
    def dim(self) -> int:
        """Spatial dimension."""
        return geometry_dim(self.geometry)


# ----------------------------------------------------------- cross-field validation
def _check_len(errors: list, path: str, vec: list | tuple | None, dim: int) -> None:
    if vec is not None and len(vec) != dim:
        what = "1 component" if dim == 1 else f"{dim} components"
        errors.append((path, f"needs {what} for a {dim}-D model, got {len(vec)}"))


def _check_nonzero(errors: list, path: str, vec: list | None) -> None:
    if vec is not None and not any(vec):
        errors.append((path, "must be a non-zero vector"))


def _check_region(errors: list, path: str, r: RegionSpec, dim: int, sets: set[str]) -> None:
    k = r.kind()
    val = getattr(r, k)
    if k == "box":
        _check_len(errors, f"{path}.box.min", val.min, dim)
        _check_len(errors, f"{path}.box.max", val.max, dim)
    elif k in ("ball", "circle", "sphere"):
        _check_len(errors, f"{path}.{k}.center", val.center, dim)
    elif k == "cylinder":
        if dim != 3:
            errors.append((f"{path}.cylinder", "cylinder regions are 3-D"))
        _check_len(errors, f"{path}.cylinder.base", val.base, 3)
        _check_len(errors, f"{path}.cylinder.axis", val.axis, 3)
        _check_nonzero(errors, f"{path}.cylinder.axis", val.axis)
    elif k == "polygon":
        if dim != 2:
            errors.append((f"{path}.polygon", "polygon regions are 2-D"))
        for n, v in enumerate(val.vertices):
            _check_len(errors, f"{path}.polygon.vertices.{n}", v, 2)
    elif k == "half_space":
        _check_len(errors, f"{path}.half_space.point", val.point, dim)
        _check_len(errors, f"{path}.half_space.normal", val.normal, dim)
        _check_nonzero(errors, f"{path}.half_space.normal", val.normal)
    elif k == "edge":
        _check_len(errors, f"{path}.edge.normal", val.normal, dim)
        _check_nonzero(errors, f"{path}.edge.normal", val.normal)
    elif k == "point":
        _check_len(errors, f"{path}.point", val, dim)
    elif k == "set":
        if val not in sets:
            errors.append((f"{path}.set", f"unknown node set {val!r}; known: {sorted(sets)}"))
    elif k in ("all_of", "any_of"):
        for n, sub in enumerate(val):
            _check_region(errors, f"{path}.{k}.{n}", sub, dim, sets)
    elif k == "not_":
        _check_region(errors, f"{path}.not", val, dim, sets)


def _uses(r: RegionSpec, kinds: set[str]) -> bool:
    k = r.kind()
    v = getattr(r, k)
    if k in kinds:
        return True
    if k in ("all_of", "any_of"):
        return any(_uses(x, kinds) for x in v)
    return k == "not_" and _uses(v, kinds)


def _notch_errors(deck: Deck) -> list[tuple[str, str]]:
    """Checks of ``notches``: a 2-D or 3-D model, [x, y] ends, z only in 3-D."""
    errors: list[tuple[str, str]] = []
    for n, notch in enumerate(deck.notches):
        path = f"notches.{n}"
        if deck.dim == 1:
            errors.append((path, "notches need a 2-D or 3-D model (a bar has no width)"))
            continue
        for key in ("start", "end"):
            vec = getattr(notch, key)
            if len(vec) != 2:
                along = " and runs along z (its z-range is notches.N.z)" if deck.dim == 3 else ""
                why = f"is [x, y]: the slot is drawn in the x-y plane{along}"
                errors.append((f"{path}.{key}", f"{why}; got {len(vec)} components"))
        if len(notch.start) == 2 and notch.start == notch.end:
            errors.append((f"{path}.end", "equals start: a notch needs a length > 0"))
        if notch.z is not None and deck.dim != 3:
            errors.append((f"{path}.z", "is the slot's z-range in a 3-D model; remove it in 2-D"))
    return errors


def cross_check(deck: Deck) -> list[tuple[str, str]]:
    """Checks that need several sections: dimensions, node-set names, Poisson ratio."""
    from peridynamics.materials.bond_based import fixed_poisson_ratio

    errors: list[tuple[str, str]] = []
    dim = deck.dim
    g = deck.geometry
    sets = set(deck.node_sets) | {"all"}
    if deck.bodies or deck.interfaces:  # every body is a node set of its name
        sets |= {"main", *(b.name for b in deck.bodies)}
    for name, region in deck.node_sets.items():
        _check_region(errors, f"node_sets.{name}", region, dim, sets - {name})
    for n, hole in enumerate(getattr(g, "holes", [])):
        if _uses(hole, {"edge", "set", "point"}):
            errors.append(
                (
                    f"geometry.holes.{n}",
                    "holes are shapes (box, circle, polygon, ...); edge, set and "
                    "point regions only make sense for node sets",
                )
            )
        _check_region(errors, f"geometry.holes.{n}", hole, dim, set())
    plane = getattr(g, "plane", None)
    nu_fixed = fixed_poisson_ratio(dim, plane if dim == 2 else None)
    mat = deck.material
    nu = mat.poisson_ratio if isinstance(mat, Material) else None
    if nu is not None and nu_fixed is not None and abs(nu - nu_fixed) > 1e-6:
        what = f"{dim}-D" + (f" plane {plane}" if dim == 2 else "")
        errors.append(
            (
                "material.poisson_ratio",
                f"bond-based PMB fixes nu = {nu_fixed:.6g} in {what}; got {nu} "
                "(omit poisson_ratio or set it to that value)",
            )
        )
    if isinstance(mat, MicropolarMaterialSpec):
        if dim != 2:
            errors.append(("material.model", "micropolar is a 2-D model (plane stress or strain)"))
        elif plane == "strain" and mat.poisson_ratio > 0.25:
            errors.append(
                (
                    "material.poisson_ratio",
                    f"{mat.poisson_ratio} is above the micropolar plane-strain limit 1/4 (the "
                    "shear spring would be negative); use <= 0.25, plane stress or model lps",
                )
            )
        if deck.damage.sed_softening is not None:
            errors.append(
                ("damage.sed_softening", "softens bond stiffness: needs material.model pmb")
            )
    if deck.damage.bond_law != "brittle":  # tension-softening bonds: bond-based PMB only
        if not isinstance(mat, Material):
            errors.append(
                (
                    "damage.bond_law",
                    f"{deck.damage.bond_law!r} softens bond-based PMB bonds: needs "
                    f"material.model pmb or bond_based (got {mat.model!r}); use bond_law "
                    "'brittle' with this material",
                )
            )
        sv = deck.solver
        if (
            isinstance(sv, StaticSolverSpec)
            or getattr(sv, "hybrid", None) is not None
            or getattr(sv, "method", "pd") != "pd"
        ):
            errors.append(
                (
                    "damage.bond_law",
                    f"{deck.damage.bond_law!r} bonds keep a history that the explicit "
                    "(method pd, no hybrid) and adr solvers commit; use one of them",
                )
            )
    elif deck.damage.tensile_strength is not None and not isinstance(
        mat, CorrespondenceMaterialSpec
    ):
        errors.append(
            (
                "damage.tensile_strength",
                "the principal-stress criterion reads the stress tensor of a correspondence "
                "model: use material.model correspondence, or a critical stretch",
            )
        )
    if isinstance(mat, CorrespondenceMaterialSpec):
        if dim == 1:
            errors.append(("material.model", "correspondence is a 2-D / 3-D model"))
        if deck.damage.sed_softening is not None:
            errors.append(
                ("damage.sed_softening", "softens bond stiffness: needs material.model pmb")
            )
    if isinstance(mat, LPSMaterialSpec):
        if dim == 1:
            errors.append(("material.model", "lps is a 2-D / 3-D model; use pmb for bars"))
        if deck.damage.sed_softening is not None:
            errors.append(
                ("damage.sed_softening", "softens bond stiffness: needs material.model pmb")
            )
    if (
        isinstance(mat, Material)
        and mat.micromodulus is not None
        and deck.damage.fracture_energy is not None
    ):
        errors.append(
            (
                "damage.fracture_energy",
                "with an explicit material.micromodulus the fracture energy does not "
                "fix s0; give damage.critical_stretch instead",
            )
        )
    if deck.damage.model == "none" and deck.damage.no_fail:
        errors.append(("damage.no_fail", "has no effect with model 'none'; remove it"))
    for n, name in enumerate(deck.damage.no_fail):
        if name not in sets:
            errors.append(
                (f"damage.no_fail.{n}", f"unknown node set {name!r}; known: {sorted(sets)}")
            )
    for n, bc in enumerate(deck.boundary_conditions):
        path = f"boundary_conditions.{n}"
        if bc.set not in sets:
            errors.append((f"{path}.set", f"unknown node set {bc.set!r}; known: {sorted(sets)}"))
        comps = getattr(bc, "components", None) or []
        for comp in comps:
            if comp == "rotation":
                if not isinstance(deck.material, MicropolarMaterialSpec):
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
        for key in ("value", "normal", "center"):
            vec = getattr(bc, key, None)
            if isinstance(vec, list):
                _check_len(errors, f"{path}.{key}", vec, dim)
        normal = getattr(bc, "normal", None)
        if normal is not None:
            _check_nonzero(errors, f"{path}.normal", normal)
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
    for n, crack in enumerate(deck.precracks):
        want = 2 if dim == 2 else 3
        if dim == 1:
            errors.append((f"precracks.{n}", "pre-cracks need a 2-D or 3-D model"))
            continue
        if len(crack.points) != want:
            errors.append(
                (
                    f"precracks.{n}.points",
                    f"a {dim}-D crack is {want} points, got {len(crack.points)}",
                )
            )
        for k, p in enumerate(crack.points):
            _check_len(errors, f"precracks.{n}.points.{k}", p, dim)
        if len(crack.points) == want and all(len(p) == dim for p in crack.points):
            from peridynamics.bonds.precrack import make_crack

            try:
                make_crack(crack.points)
            except ValueError as exc:
                errors.append((f"precracks.{n}.points", str(exc)))
    probe_names = {p.name for p in deck.output.probes}
    if deck.output.period is not None and deck.output.period.probe not in probe_names:
        errors.append(
            (
                "output.period.probe",
                f"unknown probe {deck.output.period.probe!r}; known: {sorted(probe_names)}",
            )
        )
    ss = deck.output.stress_strain
    errors += output_errors(deck.output, dim, sets, {b.name for b in deck.rigid_bodies})
    if ss is not None:
        _check_len(errors, "output.stress_strain.direction", ss.direction, dim)
        _check_nonzero(errors, "output.stress_strain.direction", ss.direction)
    if deck.output.wave_comparison is not None and deck.dim != 1:
        errors.append(("output.wave_comparison", "the d'Alembert comparison is 1-D"))
    if deck.dim != 1:
        sv = deck.solver
        if isinstance(sv, Solver) and (sv.method == "fdm" or sv.hybrid is not None):
            errors.append(("solver.method", "finite differences and hybrids are 1-D"))
        for n, probe in enumerate(deck.output.probes):
            if probe.quantity == "section_stress":
                errors.append((f"output.probes.{n}.quantity", "section_stress is 1-D"))
    for n, probe in enumerate(deck.output.probes):
        if probe.set not in sets and probe.quantity not in ("difference", "sum"):
            errors.append(
                (f"output.probes.{n}.set", f"unknown node set {probe.set!r}; known: {sorted(sets)}")
            )
        if probe.component in ("y", "z") and "xyz".index(probe.component) >= dim:
            errors.append(
                (
                    f"output.probes.{n}.component",
                    f"component {probe.component!r} does not exist in {dim}-D",
                )
            )
    names = [p.name for p in deck.output.probes]
    dup = sorted({p for p in names if names.count(p) > 1})
    if dup:
        errors.append(("output.probes", f"probe names must be unique; repeated: {dup}"))
    names_seen: set[str] = set()
    for n, cp in enumerate(deck.output.crack_paths):
        path = f"output.crack_paths.{n}"
        if dim == 1:
            errors.append((path, "crack paths need a 2-D or 3-D model"))
        _check_len(errors, f"{path}.seed", cp.seed, dim)
        _check_len(errors, f"{path}.direction", cp.direction, dim)
        _check_nonzero(errors, f"{path}.direction", cp.direction)
        if cp.within is not None and cp.within not in sets:
            errors.append((f"{path}.within", f"unknown node set {cp.within!r}"))
        if cp.name in names_seen:
            errors.append((f"{path}.name", f"crack path {cp.name!r} is given twice"))
        names_seen.add(cp.name)
    if deck.output.crack_tip is not None:
        _check_len(errors, "output.crack_tip.origin", deck.output.crack_tip.origin, dim)
        _check_len(errors, "output.crack_tip.direction", deck.output.crack_tip.direction, dim)
        _check_nonzero(errors, "output.crack_tip.direction", deck.output.crack_tip.direction)
    errors += _notch_errors(deck)
    errors += bodies_errors(deck, _check_len, _check_region)
    return errors + derived_errors(deck)


# ------------------------------------------------------------ derived quantities, size
SPEED_OF_LIGHT = 299_792_458.0  # m/s: no wave in a solid is faster
#: a typical solid (rock, glass): the reference for saying which of E and rho is off
_TYPICAL_E, _TYPICAL_RHO = 1.0e10, 2.5e3


def cross_section(g: Any) -> float:
    """The point-volume factor of a geometry: bar area (1-D), thickness (2-D), 1 (3-D)."""
    if isinstance(g, BarGeometry):
        return g.area
    if isinstance(g, RectangleGeometry | DiscGeometry) or (
        isinstance(g, MeshGeometry) and geometry_dim(g) == 2
    ):
        return g.thickness
    return 1.0


def _finite_positive(value: float) -> bool:
    return math.isfinite(value) and value > 0


def derived_errors(deck: Deck) -> list[tuple[str, str]]:
    """Quantities derived from several keys that must be finite and non-zero: the wave
    speed sqrt(E / rho) (and below the speed of light), the micromodulus and the
    critical stretch computed from the fracture energy. Absurd values (E = 1e308,
    rho = 1e-300, a typo in the exponent) then fail here with the key named instead of
    giving a zero or a 1e-100 s time step."""
    errors: list[tuple[str, str]] = []
    m = deck.material
    E, rho = m.youngs_modulus, m.density
    try:
        speed = math.sqrt(E / rho)
    except (OverflowError, ZeroDivisionError):
        speed = math.inf
    off_e = abs(math.log10(E / _TYPICAL_E))
    off_rho = abs(math.log10(rho / _TYPICAL_RHO))
    blame = "material.youngs_modulus" if off_e >= off_rho else "material.density"
    units = "check the units: youngs_modulus in Pa, density in kg/m^3"
    if not _finite_positive(speed) or speed > SPEED_OF_LIGHT:
        why = "faster than light" if speed > SPEED_OF_LIGHT else "not a finite number > 0"
        errors.append(
            (
                blame,
                f"the wave speed sqrt(E / rho) = {speed:.3g} m/s (E = {E:.6g} Pa, "
                f"rho = {rho:.6g} kg/m^3) is {why}; {units}",
            )
        )
        return errors
    if not isinstance(m, Material):
        return errors
    from peridynamics.materials.bond_based import BondBasedMaterial

    g, dim = deck.geometry, deck.dim
    plane = getattr(g, "plane", None) if dim == 2 else None
    area = cross_section(g)
    delta = deck.discretisation.delta
    try:
        mat = BondBasedMaterial(E, rho, m.micromodulus_profile, m.micromodulus)
        c0 = mat.micromodulus_constant(dim, delta, area, plane)
    except (OverflowError, ZeroDivisionError, ValueError):
        c0 = math.inf
    if not _finite_positive(c0):
        if m.micromodulus is not None:
            key = "material.micromodulus"
        elif max(off_e, off_rho) > 3:  # E or rho 1000 x off a typical solid
            key = blame
        elif deck.discretisation.horizon is not None:
            key = "discretisation.horizon"
        else:
            key = "discretisation.spacing"
        errors.append(
            (
                key,
                f"the micromodulus c = {c0:.3g} N/m^6 (E = {E:.6g} Pa, horizon = "
                f"{delta:.6g} m) is not a finite number > 0; {units}, lengths in m",
            )
        )
        return errors
    g0 = deck.damage.fracture_energy
    if deck.damage.model != "none" and g0 is not None:
        try:
            s0 = mat.critical_stretch(g0, dim, delta, area, plane)
        except (OverflowError, ZeroDivisionError, ValueError):
            s0 = math.nan
        if not _finite_positive(s0):
            errors.append(
                (
                    "damage.fracture_energy",
                    f"the critical stretch from G0 = {g0:.6g} J/m^2 and E = {E:.6g} Pa is "
                    f"{s0:.3g}, not a finite number > 0; check the units (J/m^2, Pa)",
                )
            )
    return errors


@dataclass(frozen=True)
class SizeEstimate:
    """The size of a model estimated from its deck before anything is built: ``points``
    from the bounding volume / spacing^dim, ``bonds`` (directed) from points x the
    volume of the horizon ball / spacing^dim, ``bytes`` of peak memory from the
    measured cost of a run (about 150 bytes per bond and 500 per point, plus the
    interpreter and libraries). Floats: absurd decks give 1e30, not an overflow."""

    points: float
    bonds: float
    bytes: float

    BASE_BYTES = 0.3e9
    BYTES_PER_POINT = 500.0
    BYTES_PER_BOND = 150.0

    def describe(self) -> str:
        """One line: points, bonds, GB."""
        return (
            f"about {self.points:.3g} points, {self.bonds:.3g} bonds, "
            f"{self.bytes / 1e9:.3g} GB of memory"
        )


def estimate_size(deck: Deck, n_points: float | None = None) -> SizeEstimate | None:
    """Estimate points, bonds and memory from the deck alone (``None`` for a mesh
    geometry unless ``n_points`` is given: its points are only known once it is read)."""
    g, d = deck.geometry, deck.discretisation
    dx, dim = d.spacing, deck.dim

    def cells(length: float) -> float:
        return length / dx

    if n_points is None:
        if isinstance(g, BarGeometry):
            n_points = cells(g.length) + 1.0
        elif isinstance(g, RectangleGeometry):
            n_points = cells(g.size[0]) * cells(g.size[1])
        elif isinstance(g, BoxGeometry):
            n_points = cells(g.size[0]) * cells(g.size[1]) * cells(g.size[2])
        elif isinstance(g, CylinderGeometry):
            n_points = math.pi * cells(g.radius) ** 2 * cells(g.length)
        elif isinstance(g, DiscGeometry):
            n_points = math.pi * cells(g.radius) ** 2
        else:
            return None
    reach = d.delta + (0.5 * dx if d.partial_volume == "extended" else 0.0)
    r = reach / dx
    family = {1: 2.0 * r, 2: math.pi * r * r, 3: 4.0 / 3.0 * math.pi * r**3}[dim]
    n = float(n_points)
    family = min(family, max(n - 1.0, 0.0))  # a family holds at most every other point
    bonds = n * family
    size = SizeEstimate.BASE_BYTES + SizeEstimate.BYTES_PER_POINT * n
    return SizeEstimate(n, bonds, size + SizeEstimate.BYTES_PER_BOND * bonds)


def estimate_steps(deck: Deck) -> float | None:
    """Steps of an explicit run estimated before the bonds exist (``None`` for a static
    solver): ``steps``, or ``end_time`` / dt with dt = ``time_step`` or ``safety_factor``
    x the continuum estimate of the stable step of the PMB model (delta / (3 c) in 2-D,
    delta / (sqrt(12) c) in 3-D, delta / (c sqrt(2 H_m)) in 1-D, c = sqrt(E / rho))."""
    s = deck.solver
    if not isinstance(s, Solver):
        return None
    if s.steps is not None:
        return float(s.steps)
    assert s.end_time is not None
    if s.time_step is not None:
        return math.ceil(s.end_time / s.time_step)
    m, d = deck.material, deck.discretisation
    speed = math.sqrt(m.youngs_modulus / m.density)
    m_ratio = max(d.delta / d.spacing, 1.0)
    harmonic = math.log(m_ratio) + 0.5772 + 0.5 / m_ratio
    factor = {1: math.sqrt(2.0 * harmonic), 2: 3.0, 3: math.sqrt(12.0)}[deck.dim]
    dt = s.safety_factor * d.delta / (factor * speed)
    return s.end_time / dt if dt > 0 else math.inf


# -------------------------------------------------------------------- load / overrides
def _format_loc(loc: tuple[Any, ...]) -> str:
    parts = []
    for p in loc:
        if isinstance(p, str) and p.endswith("]"):
            continue  # pydantic's union-member tags, e.g. 'function-after[...]'
        parts.append("not" if p == "not_" else str(p))
    return ".".join(parts)


_TYPE_TAGS = {
    "bar",
    "rectangle",
    "disc",
    "box",
    "cylinder",
    "mesh",
    "constant",
    "ramp",
    "table",
    "triangular_pulse",
    "displacement",
    "velocity",
    "fixed",
    "initial_velocity",
    "body_force",
    "traction",
    "pressure",
}
#: tags of the callable-discriminated sections (model families, solvers)
_SECTION_TAGS = {"material": set(MATERIAL_SCHEMAS), "solver": set(SOLVER_SCHEMAS)}


def _clean_loc(loc: tuple[Any, ...]) -> tuple[Any, ...]:
    # drop discriminator tags that pydantic inserts into the location
    out = []
    for n, p in enumerate(loc):
        if n > 0 and loc[n - 1] in _SECTION_TAGS and p in _SECTION_TAGS[loc[n - 1]]:
            continue
        if isinstance(p, str) and p in _TYPE_TAGS and n > 0 and loc[n - 1] not in ("type",):
            prev = loc[n - 1]
            if isinstance(prev, int) or prev in ("geometry", "time_function"):
                continue
        out.append(p)
    return tuple(out)


_ALLOWED_TYPES = {
    "geometry": "bar, rectangle, box, cylinder, mesh, disc",
    "boundary_conditions": "displacement, velocity, fixed, initial_velocity, body_force, "
    "traction, pressure",
    "time_function": "constant, ramp, table, triangular_pulse",
    "material": ", ".join(MATERIAL_SCHEMAS),
    "solver": ", ".join(SOLVER_SCHEMAS),
}
#: the key that names the kind of a section (``type`` unless listed)
_TAG_KEY = {"material": "model"}


def _section_of(path: str) -> str:
    parts = [p for p in path.split(".") if not p.isdigit()]
    return parts[-1] if parts else ""


def named_key(msg: str) -> tuple[str | None, str]:
    """``"[key] message"`` (a validator or solver naming the offending key) -> (key,
    message); (None, msg) for a message that names none."""
    if msg.startswith("[") and "] " in msg:
        key, rest = msg[1:].split("] ", 1)
        return key, rest
    return None, msg


def validation_errors(exc: ValidationError) -> list[tuple[str, str]]:
    """(key path, message) pairs from a pydantic error."""
    out = []
    for e in exc.errors():
        path = _format_loc(_clean_loc(tuple(e["loc"])))
        msg = e["msg"]
        if e["type"] == "extra_forbidden":
            section = path.split(".")[0] if "." in path else ""
            msg = (
                "unknown key (check the spelling; `peridynamics help deck"
                f"{'.' + section if section else ''}` lists the allowed keys)"
            )
        elif e["type"] == "missing":
            msg = "required key is missing"
        elif e["type"] in ("union_tag_not_found", "union_tag_invalid"):
            kinds = _ALLOWED_TYPES.get(_section_of(path), "")
            key = _TAG_KEY.get(_section_of(path), "type")
            missing = e["type"] == "union_tag_not_found"
            msg = (f"required key '{key}' is missing" if missing else f"unknown {key}") + (
                f"; one of: {kinds}" if kinds else ""
            )
            if not missing:
                path = f"{path}.{key}" if path else key
        msg = msg.removeprefix("Value error, ")
        named, msg = named_key(msg)
        if named is not None:  # relative to the section the validator checks
            path = f"{path}.{named}" if path else named
        if "input" in e and e["type"] not in ("missing", "extra_forbidden"):
            inp = e["input"]
            if not isinstance(inp, dict | list):
                msg += f" (got {inp!r})"
        out.append((path, msg))
    return out


def apply_overrides(data: dict[str, Any], overrides: list[str]) -> dict[str, Any]:
    """Apply ``key.path=value`` overrides (value parsed as YAML) to a raw deck dict."""
    for item in overrides:
        if "=" not in item:
            raise DeckError([(item, "an override is key.path=value")])
        key, raw = item.split("=", 1)
        key = key.strip()
        if not key:
            raise DeckError([(item, "an override is key.path=value; the key path is empty")])
        try:
            value = yaml.load(raw, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader
        except yaml.YAMLError as exc:
            problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
            raise DeckError(
                [
                    (
                        key,
                        f"--set value {raw!r} is not valid YAML ({problem}); quote the "
                        "argument in the shell and close brackets: key=[1, 2]",
                    )
                ]
            ) from None
        node: Any = data
        parts = key.split(".")
        for n, part in enumerate(parts):
            last = n == len(parts) - 1
            if isinstance(node, list):
                try:
                    idx = int(part)
                    if idx < 0:
                        raise IndexError
                    node[idx]  # noqa: B018 - existence check
                except (ValueError, IndexError):
                    raise DeckError(
                        [(key, f"no list item {part!r} (indices start at 0)")]
                    ) from None
                if last:
                    node[idx] = value
                else:
                    node = node[idx]
            else:
                if not isinstance(node, dict):
                    raise DeckError([(key, f"{'.'.join(parts[:n])} is not a section")])
                if last:
                    node[part] = value
                else:
                    node = node.setdefault(part, {})
    return data


def parse_deck(data: Any, base_dir: Path | None = None) -> Deck:
    """Validate a raw mapping into a :class:`Deck`; raise :class:`DeckError`."""
    if not isinstance(data, dict):
        raise DeckError([("", "a deck is a YAML mapping of sections (name, geometry, ...)")])
    try:
        deck = Deck.model_validate(data)
    except ValidationError as exc:
        raise DeckError(validation_errors(exc)) from None
    if isinstance(deck.geometry, MeshGeometry) and (
        base_dir is not None or deck.geometry.dim is None
    ):  # without base_dir and with dim given, the file is not looked up
        deck = _resolve_mesh(deck, base_dir or Path.cwd())
    deck = _resolve_field_files(deck, base_dir or Path.cwd())
    errors = cross_check(deck)
    if errors:
        raise DeckError(errors)
    return deck


def _resolve_mesh(deck: Deck, base_dir: Path) -> Deck:
    """Make the mesh path absolute and fill ``dim`` from the mesh's cells if omitted."""
    import meshio

    g = deck.geometry
    assert isinstance(g, MeshGeometry)
    path = Path(g.file)
    if not path.is_absolute():
        path = base_dir / path
    if not path.exists():
        raise DeckError([("geometry.file", f"mesh file {str(path)!r} does not exist")])
    update: dict[str, Any] = {"file": str(path)}
    if g.dim is None:
        said = io.StringIO()  # meshio prints its reason and then raises SystemExit(1)
        try:
            with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said):
                kinds = {blk.type for blk in meshio.read(path).cells}
        except (Exception, SystemExit) as exc:
            reason = " ".join(said.getvalue().split()).removeprefix("Error: ")
            if not isinstance(exc, SystemExit) and str(exc):
                reason = f"{reason}; {exc}" if reason else str(exc)
            detail = f": {reason}" if reason else " (not a mesh format meshio recognises)"
            raise DeckError(
                [("geometry.file", f"meshio cannot read {str(path)!r}{detail}")]
            ) from None
        update["dim"] = 3 if kinds & {"tetra", "hexahedron"} else 2
    return deck.model_copy(update={"geometry": g.model_copy(update=update)})


def _resolve_field_files(deck: Deck, base_dir: Path) -> Deck:
    """Make the ``file`` of initial fields absolute (relative to the deck's folder) and
    check that it exists; its rows are checked against the node set when it is built."""
    bcs = list(deck.boundary_conditions)
    errors = []
    for n, spec in enumerate(bcs):
        if isinstance(spec, InitialVelocityBC) and spec.file is not None:
            path = Path(spec.file)
            if not path.is_absolute():
                path = base_dir / path
            if not path.is_file():
                errors.append((f"boundary_conditions.{n}.file", f"no file {str(path)!r}"))
            bcs[n] = spec.model_copy(update={"file": str(path)})
    if errors:
        raise DeckError(errors)
    return deck.model_copy(update={"boundary_conditions": bcs})


class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses a key given twice in one mapping (YAML keeps the last)."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
        seen: dict[Any, Any] = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)  # type: ignore[no-untyped-call]
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None,
                    None,
                    f"key {key!r} appears twice in one section "
                    f"(line {seen[key] + 1} and line {key_node.start_mark.line + 1})",
                    key_node.start_mark,
                )
            seen[key] = key_node.start_mark.line
        return super().construct_mapping(node, deep=deep)


# YAML 1.1 (PyYAML) reads a float only with a dot and a signed exponent (1.0e+6):
# `1e6`, `1.0e6`, `6.02e23` or `.5e3` would be strings, and an integer key would refuse
# `steps: 1e3`. Read every number in scientific notation as a float, as YAML 1.2 does.
_UniqueKeyLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(
        r"""^(?:[-+]?[0-9][0-9_]*(?:\.[0-9_]*)?[eE][-+]?[0-9]+
            |[-+]?\.[0-9][0-9_]*[eE][-+]?[0-9]+)$""",
        re.X,
    ),
    list("-+0123456789."),
)


def yaml_load(text: str) -> Any:
    """Parse YAML as decks are read: safe, a repeated key is an error, and numbers in
    scientific notation (1e6, 1.0e6, -2.5E-3) are floats."""
    return yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader


def load_deck(path: str | Path, overrides: list[str] | None = None) -> Deck:
    """Read and validate a YAML deck file, applying ``key.path=value`` overrides."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise DeckError([("", f"cannot read deck {str(path)!r}: {exc.strerror}")]) from None
    try:
        data = yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader
    except yaml.YAMLError as exc:
        raise DeckError([("", f"not valid YAML: {exc}")]) from None
    if overrides:
        if not isinstance(data, dict):
            raise DeckError([("", "a deck is a YAML mapping")])
        data = apply_overrides(data, overrides)
    return parse_deck(data, base_dir=path.parent)
