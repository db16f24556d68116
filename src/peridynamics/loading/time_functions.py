"""Scalar time functions ``f(t)`` that scale boundary-condition values."""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


class TimeFunction(ABC):
    """A dimensionless amplitude ``f(t)``; t in s."""

    @abstractmethod
    def __call__(self, t: float) -> float:
        """Amplitude at time ``t``."""


@dataclass(frozen=True)
class Constant(TimeFunction):
    """f(t) = value (1 by default): a suddenly applied load."""

    value: float = 1.0

    def __call__(self, t: float) -> float:
        return float(self.value)


@dataclass(frozen=True)
class Ramp(TimeFunction):
    """Linear ramp from 0 at ``start`` to 1 at ``end``, then constant 1."""

    end: float
    start: float = 0.0

    def __post_init__(self) -> None:
        if self.start < 0 or not self.end > self.start:
            raise ValueError("ramp needs 0 <= start < end (s)")

    def __call__(self, t: float) -> float:
        return float(np.clip((t - self.start) / (self.end - self.start), 0.0, 1.0))


@dataclass(frozen=True)
class Table(TimeFunction):
    """Piecewise-linear table; held at the end values outside the range."""

    times: Sequence[float]
    values: Sequence[float]

    def __post_init__(self) -> None:
        t = np.asarray(self.times, dtype=float)
        if len(t) < 2 or len(t) != len(self.values):
            raise ValueError("table needs at least two times and as many values")
        if np.any(np.diff(t) <= 0):
            raise ValueError("table times must increase strictly")

    def __call__(self, t: float) -> float:
        return float(np.interp(t, self.times, self.values))


@dataclass(frozen=True)
class TriangularPulse(TimeFunction):
    """Triangle: 0 at t=0, ``peak`` at ``rise_time``, back to 0 at ``duration``, then 0."""

    peak: float
    rise_time: float
    duration: float

    def __post_init__(self) -> None:
        if not 0 < self.rise_time < self.duration:
            raise ValueError("triangular pulse needs 0 < rise_time < duration (s)")

    def __call__(self, t: float) -> float:
        if t <= 0 or t >= self.duration:
            return 0.0
        if t <= self.rise_time:
            return float(self.peak * t / self.rise_time)
        return float(self.peak * (self.duration - t) / (self.duration - self.rise_time))


@dataclass(frozen=True)
class SinePulse(TimeFunction):
    """One period of a sine: f(t) = sin(2 pi t / duration) for 0 <= t <= duration, else 0
    (an input wave of PD wave dispersion (n.d.), section 4.1.1; the paper does not print its
    parameters, see examples/waves/README.md)."""

    duration: float

    def __post_init__(self) -> None:
        if not self.duration > 0:
            raise ValueError("sine pulse needs duration > 0 (s)")

    def __call__(self, t: float) -> float:
        if t < 0 or t > self.duration:
            return 0.0
        return float(np.sin(2.0 * np.pi * t / self.duration))


@dataclass(frozen=True)
class SquarePulse(TimeFunction):
    """f(t) = 1 for 0 <= t <= duration, else 0 (the square wave of PD wave dispersion (n.d.),
    section 4.1.1)."""

    duration: float

    def __post_init__(self) -> None:
        if not self.duration > 0:
            raise ValueError("square pulse needs duration > 0 (s)")

    def __call__(self, t: float) -> float:
        return 1.0 if 0 <= t <= self.duration else 0.0
