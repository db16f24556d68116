"""Deck time functions: the factor f(t) of a boundary condition or a rigid body's
motion (constant, ramp, table, triangular, sine and square pulses, blast)."""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, model_validator

from peridynamics.deck.types import Finite, NonNegFloat, PosFloat, Strict

#: a blast's scaled distance may lie this factor outside the fits' range (extrapolated,
#: with a warning), no further: the polynomials diverge beyond
BLAST_EXTRAPOLATION = 0.5


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

    @model_validator(mode="after")
    def _scaled_distance(self) -> BlastTF:
        import warnings

        from peridynamics.loading.blast import BlastPulse
        from peridynamics.loading.blast_parameters import FIT_RANGES

        low = min(r[0] for r in FIT_RANGES.values())
        high = max(r[1] for r in FIT_RANGES.values())
        z = self.standoff_m / self.charge_kg ** (1.0 / 3.0)
        check = "check charge_kg (kg of TNT) and standoff_m (m)"
        if not BLAST_EXTRAPOLATION * low <= z <= high / BLAST_EXTRAPOLATION:
            raise ValueError(
                f"[standoff_m] the scaled distance Z = standoff_m / charge_kg^(1/3) = {z:.3g} "
                f"m/kg^(1/3) is far outside the range of the Kingery-Bulmash fits ({low:g} to "
                f"{high:g}; extrapolated to {BLAST_EXTRAPOLATION * low:.3g} to "
                f"{high / BLAST_EXTRAPOLATION:.3g} at most); {check}"
            )
        try:
            with warnings.catch_warnings():  # the run warns of an extrapolation once
                warnings.simplefilter("ignore")
                pulse = BlastPulse(self.charge_kg, self.standoff_m, self.shape, self.delay)
            ok = math.isfinite(pulse.peak_Pa * pulse.duration_s) and pulse.duration_s > 0
            why = f"peak {pulse.peak_Pa:.3g} Pa, duration {pulse.duration_s:.3g} s"
        except (ValueError, ArithmeticError) as exc:
            ok, why = False, str(exc)
        if not ok:
            other = "; or shape: triangular" if "triangular" not in why else ""
            raise ValueError(
                f"[standoff_m] no {self.shape} pulse at the scaled distance Z = {z:.3g} "
                f"m/kg^(1/3) ({why}); {check}{other}"
            )
        return self


TimeFunctionSpec = Annotated[
    ConstantTF | RampTF | TableTF | TriangularPulseTF | SinePulseTF | SquarePulseTF | BlastTF,
    Field(discriminator="type"),
]
