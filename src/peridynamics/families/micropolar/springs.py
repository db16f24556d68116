"""The three bond spring constants of the micropolar family
(:mod:`peridynamics.families.micropolar.material` derives them)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SpringConstants:
    """The three bond spring constants (N/m^6 per unit stretch, shear, rotation)."""

    axial: float
    shear: float
    rotational: float
