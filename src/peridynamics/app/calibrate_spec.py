"""The calibration file of ``peridynamics calibrate`` (docs/calibration.md): a strict
schema of the parameters to fit (deck key, bounds, scale), the targets (a simulated
curve from ``history.csv`` or a scalar of ``summary.json``, against measured data) and
the optimiser's options.

An invalid file raises :class:`CalibrationError` whose message names the key of the
calibration file (``parameters.0.bounds``) and the fix.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator


class CalibrationError(ValueError):
    """Bad calibration input: ``str(exc)`` names the key or option and the fix (exit 2)."""


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


Finite = Annotated[float, Field(allow_inf_nan=False)]
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]


class Parameter(_Strict):
    """A deck value to fit: ``key`` (dotted path, as for ``--set``), ``bounds`` [lo, hi]
    in the deck's units (SI), ``initial`` (default: the middle of the bounds in the
    chosen scale) and ``scale``: ``linear`` or ``log`` (the optimiser works on
    ``(p - lo) / (hi - lo)`` or ``ln(p / lo) / ln(hi / lo)``, both in [0, 1])."""

    key: Annotated[str, Field(min_length=1, pattern=r"^[^\s=]+$")]
    bounds: tuple[Finite, Finite]
    initial: Finite | None = None
    scale: Literal["linear", "log"] = "linear"
    name: str | None = None

    @model_validator(mode="after")
    def _check(self) -> Parameter:
        lo, hi = self.bounds
        if not lo < hi:
            raise ValueError(f"bounds [{lo}, {hi}]: write [lower, upper] with lower < upper")
        if self.scale == "log" and lo <= 0:
            raise ValueError(f"scale log needs positive bounds, got lower {lo}; use linear")
        if self.initial is not None and not lo <= self.initial <= hi:
            raise ValueError(f"initial {self.initial} lies outside bounds [{lo}, {hi}]")
        return self

    @property
    def label(self) -> str:
        """The parameter's name in reports (``name``, else the deck key)."""
        return self.name or self.key

    def to_unit(self, value: float) -> float:
        """Physical value -> the optimiser's variable in [0, 1]."""
        lo, hi = self.bounds
        if self.scale == "log":
            return math.log(value / lo) / math.log(hi / lo)
        return (value - lo) / (hi - lo)

    def from_unit(self, z: float) -> float:
        """The optimiser's variable in [0, 1] -> physical value."""
        lo, hi = self.bounds
        z = min(max(float(z), 0.0), 1.0)
        if self.scale == "log":
            return float(lo * math.exp(z * math.log(hi / lo)))
        return float(lo + z * (hi - lo))

    def dvalue_dunit(self, value: float) -> float:
        """d(physical value) / d(unit variable) at ``value``."""
        lo, hi = self.bounds
        return value * math.log(hi / lo) if self.scale == "log" else hi - lo


class Simulated(_Strict):
    """The simulated curve: ``x`` and ``y`` are expressions over the columns of a
    run's ``history.csv`` (a header with or without its ``[unit]``): a sum of terms
    ``[+|-][number *]column``, e.g. ``mouth_right_ux - mouth_left_ux``; each is
    multiplied by ``x_factor`` / ``y_factor`` (a sign or a unit change)."""

    x: Annotated[str, Field(min_length=1)]
    y: Annotated[str, Field(min_length=1)]
    x_factor: Finite = 1.0
    y_factor: Finite = 1.0


class Measured(_Strict):
    """The measured curve: a CSV ``file`` (relative to the calibration file), the
    columns ``x`` and ``y`` (headers, e.g. ``CMOD [mm]``) and the factors that turn them
    into the simulated curve's units (``x_factor: 1.0e-3`` for mm -> m); ``sigma``: an
    optional column of standard deviations of ``y`` (same units as y; residuals are
    divided by it)."""

    file: Annotated[str, Field(min_length=1)]
    x: Annotated[str, Field(min_length=1)]
    y: Annotated[str, Field(min_length=1)]
    x_factor: Finite = 1.0
    y_factor: Finite = 1.0
    sigma: str | None = None


class Target(_Strict):
    """One quantity to match. Either a curve (``simulated`` and ``measured``: the
    simulated y interpolated linearly at the measured x) or a scalar (``scalar``: a
    key of the run's ``summary.json`` results, flattened with dots as in sweep.csv,
    e.g. ``probes.reaction.peak``, and its measured ``value``). Residuals are divided by
    ``sigma`` (scalar; curves: the ``sigma`` column, else the largest |measured y|)
    and multiplied by ``weight``. ``monotone: true`` cuts both curves at the first
    point where x decreases (a snap-back)."""

    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    simulated: Simulated | None = None
    measured: Measured | None = None
    scalar: str | None = None
    value: Finite | None = None
    sigma: Positive | None = None
    weight: Positive = 1.0
    monotone: bool = False

    @model_validator(mode="after")
    def _check(self) -> Target:
        curve = self.simulated is not None or self.measured is not None
        if curve and self.scalar is not None:
            raise ValueError("give either simulated + measured (a curve) or scalar + value")
        if curve and (self.simulated is None or self.measured is None):
            raise ValueError("a curve needs both simulated: {x, y} and measured: {file, x, y}")
        if not curve and (self.scalar is None or self.value is None):
            raise ValueError(
                "give a curve (simulated: {x, y}, measured: {file, x, y}) or a scalar "
                "(scalar: probes.reaction.peak, value: 1.2e3)"
            )
        return self


class Options(_Strict):
    """The optimiser: ``method`` ``least_squares`` (SciPy's bounded trust-region
    reflective least squares with a forward-difference Jacobian whose runs go in
    parallel) or ``global`` (SciPy's differential evolution over the bounds, each
    generation run in parallel, then least squares from its best point); ``restarts``
    further least-squares starts from a Latin hypercube; ``fd_step`` the Jacobian's
    step in the unit variables; ``max_runs`` a cap on the number of runs."""

    method: Literal["least_squares", "global"] = "least_squares"
    jobs: Annotated[int, Field(ge=1, le=4096)] = 1
    restarts: Annotated[int, Field(ge=0, le=100)] = 0
    fd_step: Annotated[float, Field(gt=0, le=0.1)] = 1e-3
    max_runs: Annotated[int, Field(ge=1, le=1_000_000)] = 500
    tolerance: Annotated[float, Field(gt=0, lt=1)] = 1e-8
    population: Annotated[int, Field(ge=2, le=100)] = 8
    generations: Annotated[int, Field(ge=1, le=10_000)] = 10
    seed: Annotated[int, Field(ge=0)] = 0
    confidence: Annotated[float, Field(gt=0, lt=1)] = 0.95


class CalibrationSpec(_Strict):
    """A calibration file: ``set`` (fixed overrides of every run), ``parameters``,
    ``targets`` and ``options`` (the deck is the command's DECK argument)."""

    set: list[str] = []
    parameters: Annotated[list[Parameter], Field(min_length=1, max_length=50)]
    targets: Annotated[list[Target], Field(min_length=1)]
    options: Options = Options()

    @model_validator(mode="after")
    def _unique(self) -> CalibrationSpec:
        keys = [p.key for p in self.parameters]
        if len(set(keys)) < len(keys):
            raise ValueError("a parameter key is given twice; list each deck key once")
        names = [t.name for t in self.targets]
        if len(set(names)) < len(names):
            raise ValueError("two targets share a name; give each its own name")
        fixed = {s.split("=", 1)[0].strip() for s in self.set}
        both = sorted(fixed & set(keys))
        if both:
            raise ValueError(f"{both[0]} is both fitted (parameters) and fixed (set); drop one")
        return self


def _message(exc: ValidationError) -> str:
    lines = []
    for e in exc.errors():
        loc = ".".join(str(p) for p in e["loc"] if not str(p).startswith("function-"))
        msg = str(e["msg"]).removeprefix("Value error, ")
        lines.append(f"{loc}: {msg}" if loc else msg)
    return "\n  ".join(lines)


def parse_spec(data: Any, where: str = "calibration file") -> CalibrationSpec:
    """Validate a mapping (a parsed calibration file); raise :class:`CalibrationError`."""
    if not isinstance(data, dict):
        raise CalibrationError(f"{where}: a YAML mapping of parameters, targets, options")
    try:
        return CalibrationSpec.model_validate(data)
    except ValidationError as exc:
        raise CalibrationError(f"{where}: invalid:\n  {_message(exc)}") from None


def load_spec(path: str | Path) -> CalibrationSpec:
    """Read and validate a calibration file (YAML, read as decks are)."""
    from peridynamics.deck import yaml_load
    from peridynamics.deck.yaml_source import TextError, read_text

    p = Path(path)
    try:
        data = yaml_load(read_text(p, "the calibration file"))
    except OSError as exc:
        raise CalibrationError(f"{path}: cannot read the file ({exc.strerror})") from None
    except TextError as exc:
        raise CalibrationError(f"{path}: {exc}") from None
    except Exception as exc:  # noqa: BLE001 - any YAML error: name the file
        raise CalibrationError(f"{path}: not valid YAML ({str(exc).splitlines()[0]})") from None
    return parse_spec(data, str(path))
