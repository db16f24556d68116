"""Deck section ``discretisation``: grid spacing, horizon, partial volumes, surface
correction and the jitter of an irregular grid."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, field_validator, model_validator

from peridynamics.deck.types import Num, PosFloat, Strict


class Discretisation(Strict):
    """Grid spacing and horizon; ``jitter`` (fraction of the spacing, 0 <= jitter < 0.5)
    moves every grid point by a uniform random offset of at most ``jitter * spacing``
    along each axis, drawn from ``seed`` (rectangle, box and cylinder geometries)."""

    spacing: PosFloat
    horizon: PosFloat | None = None
    horizon_factor: Annotated[float, Field(ge=1.0, allow_inf_nan=False), Num] | None = None
    partial_volume: Literal["truncated", "extended", "none"] = "truncated"
    surface_correction: bool = True  # the nominal E in the interior and at surfaces
    #: bond-based models on a regular 3-D grid: bond factors quartic in the direction
    #: make the family isotropic (nu = 1/4, E0), not the cubic lattice (nu 0.269)
    isotropic_family: bool = True
    #: bond-based models on a regular grid: the critical stretch (and the softening
    #: envelopes) from the fracture energy the grid's interior family holds across a
    #: plane, not the continuous family's (families/pmb/fracture_energy.py)
    lattice_fracture_energy: bool = False
    jitter: Annotated[float, Field(allow_inf_nan=False), Num] = 0.0
    seed: Annotated[int, Field(ge=0), Num] = 0

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
