"""Deck key ``material.plasticity`` of the correspondence family: a history-dependent
law (docs/theory_plasticity.md), ``type: j2`` or ``type: drucker_prager``, and its
checks against the rest of the deck (3-D or plane strain; explicit dynamics, dynamic
relaxation or the static (Newton) solver on the Numba backend, on one rank)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Discriminator, Field, Tag, model_validator

from peridynamics.deck.history_limits import history_errors
from peridynamics.deck.types import Errors, NonNegFloat, NotBool, PosFloat, Strict, tag_of

Angle = Annotated[float, Field(ge=0.0, lt=90.0, allow_inf_nan=False), NotBool]
#: the strain of the return map: corotated U - I, or Hencky ln U (finite strain)
StrainMeasure = Literal["small", "logarithmic"]


class J2Spec(Strict):
    """Von Mises plasticity with linear isotropic (``hardening_modulus``, Pa) and linear
    kinematic (``kinematic_modulus``, Pa) hardening; ``yield_stress`` (Pa) the initial
    uniaxial yield stress (Simo & Hughes 1998, box 3.2); ``strain`` the strain of the
    return map (``small``: U - I; ``logarithmic``: ln U, Eterovic & Bathe 1990)."""

    type: Literal["j2"]
    yield_stress: PosFloat
    hardening_modulus: NonNegFloat = 0.0
    kinematic_modulus: NonNegFloat = 0.0
    strain: StrainMeasure = "small"


class DruckerPragerSpec(Strict):
    """Perfectly plastic Drucker-Prager cone (Mohr-Coulomb compressive meridian):
    ``cohesion`` (Pa), ``friction_angle`` and ``dilation_angle`` (degrees, 0 <= psi <=
    phi < 90; psi < phi: non-associated flow), ``tension_cutoff`` (Pa, the largest
    mean stress; default: the apex of the cone), ``strain`` as for j2."""

    type: Literal["drucker_prager"]
    cohesion: PosFloat
    friction_angle: Angle
    dilation_angle: Angle = 0.0
    tension_cutoff: NonNegFloat | None = None
    strain: StrainMeasure = "small"

    @model_validator(mode="after")
    def _angles(self) -> DruckerPragerSpec:
        if self.dilation_angle > self.friction_angle:
            raise ValueError(
                f"[dilation_angle] {self.dilation_angle} exceeds friction_angle "
                f"{self.friction_angle}; give 0 <= dilation_angle <= friction_angle"
            )
        from peridynamics.families.correspondence.plasticity import DruckerPrager

        try:
            DruckerPrager(
                self.cohesion, self.friction_angle, self.dilation_angle, self.tension_cutoff
            )
        except ValueError as exc:
            raise ValueError(
                "[tension_cutoff] " + str(exc).removeprefix("material.plasticity.")
            ) from None
        return self


AnyPlasticity = Annotated[
    Annotated[J2Spec, Tag("j2")] | Annotated[DruckerPragerSpec, Tag("drucker_prager")],
    Discriminator(tag_of("j2", "type")),
]


def plasticity_errors(deck: Any, law_given: bool) -> Errors:
    """What ``material.plasticity`` does not run with: plane stress, the solvers that do
    not commit a history (other than explicit, adr and static), the Warp backend, an
    explicit elastic ``law``."""
    errors: Errors = []
    key = "material.plasticity"
    if deck.dim == 2 and getattr(deck.geometry, "plane", None) != "strain":
        errors.append(
            (key, "needs a 3-D body or geometry.plane: strain (no plane-stress return map)")
        )
    errors += history_errors(
        deck, key, ("explicit", "adr", "static"),
        "{solver} does not commit the plastic history; use explicit, adr or static with "
        "material.plasticity",
    )  # fmt: skip
    if law_given:
        errors.append(
            (
                "material.law",
                "with material.plasticity the elastic part is linear in the corotated strain; "
                "remove material.law",
            )
        )
    return errors
