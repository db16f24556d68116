"""Output options: plain pydantic models of what a run writes (histories, probes,
derived probes, crack tracking, frames at chosen times and events, figures).

The deck's section ``output`` is the model :class:`Output` (``docs/deck.md``, section
"output"; ``docs/output.md`` for the files); observers and writers read these options
and know no deck. The strict base model and the number types defined here are shared
with the deck's schemas (:mod:`peridynamics.deck.types`).
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, PlainValidator, model_validator

#: the largest magnitude of a finite number of the deck and the output options: the
#: square of a length or the product of two values must not overflow (no physical
#: input comes near it; a typo in an exponent does)
MAX_MAGNITUDE = 1e100


def _not_bool(v: Any) -> Any:
    if isinstance(v, bool):
        raise ValueError("a number is expected, not true/false")
    return v


def _number(v: Any) -> Any:
    v = _not_bool(v)
    if isinstance(v, int | float) and math.isfinite(v) and abs(v) > MAX_MAGNITUDE:
        raise ValueError(
            f"a number between -{MAX_MAGNITUDE:.0e} and {MAX_MAGNITUDE:.0e} is expected; "
            "check the exponent and the units"
        )
    return v


#: refuses true/false where a number is expected (YAML reads ``yes`` as a bool)
NotBool = BeforeValidator(_not_bool)
#: refuses true/false where a number is expected, and a finite number beyond
#: :data:`MAX_MAGNITUDE`
Num = BeforeValidator(_number)
PosFloat = Annotated[float, Field(gt=0, allow_inf_nan=False), Num]
NonNegFloat = Annotated[float, Field(ge=0, allow_inf_nan=False), Num]
Finite = Annotated[float, Field(allow_inf_nan=False), Num]


class Strict(BaseModel):
    """Base: unknown keys are errors; values are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True)


Quantity = Literal[
    "displacement",
    "velocity",
    "force_density",
    "reaction_force",
    "rotation",
    "moment",
    "max_stretch",
    "damage",
    "section_stress",
    "difference",
    "sum",
    "stress",
    "strain",
    "von_mises",
    "pressure",
    "principal_stress",
    "temperature",
]
DERIVED = ("difference", "sum")
#: probe quantities computed from the model's point stress and strain (``tensor``: with
#: a component xx, yy, zz, xy, yz or xz; the others are one number per point)
TENSOR_QUANTITIES = ("stress", "strain")
STRESS_QUANTITIES = ("stress", "strain", "von_mises", "pressure", "principal_stress")
#: component of a 3 x 3 tensor -> its index in the row-major (n, 9) rows
TENSOR_COMPONENTS = {"xx": 0, "yy": 4, "zz": 8, "xy": 1, "yz": 5, "xz": 2}
EventName = Literal["first_damage", "peak_load", "fracture"]
PlotKind = Literal["damage", "deformed", "probes", "energies", "stress_strain"]
PLOT_KINDS = ("damage", "deformed", "probes", "energies", "stress_strain")


def _plot_choice(v: Any) -> str | list[str]:
    """``auto``, ``none``, one figure kind or a list of kinds (one clear message)."""
    kinds = ", ".join(repr(k) for k in PLOT_KINDS)
    if isinstance(v, str) and (v in ("auto", "none") or v in PLOT_KINDS):
        return v
    if isinstance(v, list) and v and all(isinstance(k, str) and k in PLOT_KINDS for k in v):
        return list(v)
    raise ValueError(f"'auto', 'none', one of {kinds} or a list of them (got {v!r})")


PlotChoice = Annotated[str | list[str], PlainValidator(_plot_choice)]


class Probe(Strict):
    """A recorded quantity on a node set, reduced to one number per record.

    Derived probes combine probes listed before them: ``difference`` (``of: [a, b]``:
    a - b, e.g. a crack-mouth opening from two displacement probes) and ``sum``
    (``of: [a, b, ...]``). ``reaction_force`` with ``body: NAME`` is the contact force
    on a rigid body (its reaction, N) instead of the force on a node set. ``stress`` and
    ``strain`` take a tensor component (``xx`` ... ``xz``; ``x``, ``y``, ``z`` read as
    ``xx``, ``yy``, ``zz``); ``von_mises``, ``pressure`` and ``principal_stress`` (the
    largest principal stress) are one number per point.
    """

    name: str = Field(min_length=1)
    quantity: Quantity
    set: str = "all"
    component: Literal["x", "y", "z", "magnitude", "xx", "yy", "zz", "xy", "yz", "xz"] = "x"
    reduce: Literal["mean", "sum", "max", "min"] | None = None
    position: Finite | None = None  # section_stress: x of the section (1-D, m)
    of: list[str] | None = None  # derived probes: the probes combined
    body: str | None = None  # reaction_force of a rigid body

    @model_validator(mode="after")
    def _section(self) -> Probe:
        if (self.quantity == "section_stress") != (self.position is not None):
            raise ValueError(
                "[position] section_stress needs position (x of the section, "
                "m); other quantities take none"
            )
        if (self.quantity in DERIVED) != (self.of is not None):
            raise ValueError(
                "[of] difference and sum need `of: [probe, probe, ...]` (names of probes "
                "listed before this one); other quantities take none"
            )
        if self.quantity == "difference" and self.of is not None and len(self.of) != 2:
            raise ValueError("[of] difference takes exactly two probes: of: [a, b] gives a - b")
        if self.quantity == "sum" and self.of is not None and len(self.of) < 2:
            raise ValueError("[of] sum takes two or more probes")
        if self.component in TENSOR_COMPONENTS and self.quantity not in TENSOR_QUANTITIES:
            raise ValueError(
                f"[component] {self.component} is a tensor component: only stress and strain "
                "take one; vectors take x, y, z or magnitude"
            )
        if self.quantity in TENSOR_QUANTITIES and self.component == "magnitude":
            raise ValueError(
                "[component] stress and strain take xx, yy, zz, xy, yz or xz (the equivalent "
                "stress is quantity von_mises)"
            )
        if self.body is not None and self.quantity != "reaction_force":
            raise ValueError("[body] only reaction_force takes a rigid body (body: NAME)")
        return self


class CrackTip(Strict):
    """Track the damaged point farthest from ``origin`` along ``direction``."""

    origin: list[Finite]
    direction: list[Finite] | None = None
    damage_threshold: Annotated[float, Field(gt=0, lt=1), Num] = 0.35


class CrackPathSpec(Strict):
    """A crack followed from a seed point as a polyline (connected damaged points)."""

    name: str = Field(min_length=1, max_length=60, pattern=r"^[A-Za-z0-9_.-]+$")
    seed: list[Finite]
    direction: list[Finite] = [1.0, 0.0]
    within: str | None = None
    damage_threshold: Annotated[float, Field(gt=0, lt=1), Num] = 0.35
    initial_length: PosFloat | None = None


class Fracture(Strict):
    """Fracture detection: the first time any point's damage reaches ``damage_threshold``
    (Lu & Wang (2016): phi0 = 0.3), checked after every step in which bonds break."""

    damage_threshold: Annotated[float, Field(gt=0, le=1), Num] = 0.3
    stop: bool = False


class WaveComparison(Strict):
    """Compare the final 1-D displacement profile with the exact d'Alembert pulse
    u_in(t - (x - source_position) / sqrt(E / rho)), u_in = amplitude x shape(t)."""

    shape: Literal["sine", "square"]
    amplitude: PosFloat
    duration: PosFloat
    source_position: Finite = 0.0
    tail_margin: NonNegFloat = 0.0  # m: trailing region ends this far behind the pulse


class StressStrain(Strict):
    """Nominal stress-strain curve of a loading platen (node set ``set``):
    strain = mean(u) . direction / length, stress = -(sum_i V_i f_i) . direction / area
    (both positive while the platen loads the body along ``direction``). With
    ``body: NAME`` the platen is a rigid body: its displacement and its reaction
    (contact force) along ``direction``. ``zero_at: first_contact`` measures the strain
    from the last record before the stress first exceeds ``contact_fraction`` of its
    peak (a platen that travels before it touches adds no strain)."""

    set: str | None = None
    body: str | None = None
    direction: list[Finite]
    area: PosFloat
    length: PosFloat
    zero_at: Literal["start", "first_contact"] = "start"
    contact_fraction: Annotated[float, Field(gt=0, lt=1), Num] = 0.01

    @model_validator(mode="after")
    def _source(self) -> StressStrain:
        if (self.set is None) == (self.body is None):
            raise ValueError(
                "give either set (a node set that loads the body) or body (a rigid body)"
            )
        return self


class Slice(Strict):
    """A plane through a 3-D model for figures: the points within half a spacing of
    ``{axis} = position`` (``position`` omitted: the middle of the model)."""

    axis: Literal["x", "y", "z"]
    position: Finite | None = None


class Period(Strict):
    """Dominant period of a probe history (autocorrelation) -> results.period_s. ``of``:
    the value itself, its magnitude, or ``rate``, |d value / dt| (a train of wave fronts,
    whatever their sign and however long the load lasts)."""

    probe: str
    min_period: NonNegFloat = 0.0
    of: Literal["value", "magnitude", "rate"] = "value"


#: a point field of the frames: stored in the State, or computed from the model and the
#: state when a frame is written (stress to principal_direction:
#: :mod:`peridynamics.io.observers.point_fields`)
FrameField = Literal[
    "displacement", "velocity", "damage", "force_density", "rotation", "moment",
    "stress", "strain", "von_mises", "pressure", "principal_stress", "principal_direction",
    "temperature",
]  # fmt: skip


class Output(Strict):
    """What to write: VTU frames every ``vtk_every`` steps, at the times ``frames_at``
    and at the events ``frames_on`` (first_damage: the first bond broken in the run;
    peak_load: the state at the largest load, written at the end; fracture: the
    damage of a point not damaged that much by pre-cracks first reaches
    ``fracture.damage_threshold``, 0.3 by default), in
    ``frame_precision`` with ``frame_compression``; histories (also as ``history.csv``),
    probes, crack tracking; the figures ``plot`` (one kind or a list)."""

    vtk_every: Annotated[int, Field(ge=0), Num] = 0
    frames_at: list[NonNegFloat] = []  # s: a frame at the first step at or after each
    frames_on: list[EventName] = []  # events: a frame when each happens
    frame_precision: Literal["float32", "float64"] = "float32"
    frame_compression: Literal["zlib", "none"] = "zlib"
    png_frames: bool = False  # a PNG (damage on the deformed shape) with every frame
    deformation_scale: PosFloat | None = None  # None: 99th percentile of |u| = 5 % of size
    slices: list[Slice] = []  # 3-D figures: default the three mid-planes
    load_probe: str | None = None  # the load of the peak_load event
    history_csv: bool = True  # history.csv beside summary.json
    history_every: Annotated[int, Field(gt=0), Num] | None = None
    fields: list[FrameField] = [
        "displacement", "velocity", "damage", "force_density", "rotation", "moment"
    ]  # fmt: skip
    probes: list[Probe] = []
    crack_tip: CrackTip | None = None
    crack_paths: list[CrackPathSpec] = []
    fracture: Fracture | None = None
    wave_comparison: WaveComparison | None = None
    period: Period | None = None
    stress_strain: StressStrain | None = None
    plot: PlotChoice = "auto"
    bonds: bool = True  # write bonds.npz: the bond list (pairs, lengths, final status)
    crack_length: bool = True  # results.crack_length_m / crack_area_m2 from broken bonds


def load_source(out: Output) -> str | None:
    """What ``peak_load`` follows: ``probe:NAME``, ``stress_strain`` or ``None``."""
    if out.load_probe is not None:
        return f"probe:{out.load_probe}"
    if out.stress_strain is not None:
        return "stress_strain"
    for p in out.probes:
        if p.quantity == "reaction_force":
            return f"probe:{p.name}"
    return None
