"""Deck section ``contact``: short-range repulsion with Coulomb friction."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field, model_validator

from peridynamics.deck.types import NonNegFloat, Num, PosFloat, Strict


class Contact(Strict):
    """Short-range repulsion between points not joined by an intact bond, with Coulomb
    friction (``friction_static`` >= ``friction_kinetic``, both 0 by default)."""

    distance_factor: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False), Num] = 0.9
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
