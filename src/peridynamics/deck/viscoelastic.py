"""Deck key ``material.viscoelastic`` of the LPS family: a standard-linear-solid
deviatoric response (Mitchell (2011), docs/theory_viscoelasticity.md) and its checks
against the rest of the deck (3-D; explicit dynamics or dynamic relaxation on the Numba
backend, on one rank, one body, no thermal expansion)."""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import Field

from peridynamics.deck.history_limits import history_errors
from peridynamics.deck.types import Errors, Num, PosFloat, Strict

Fraction = Annotated[float, Field(ge=0.0, le=1.0, allow_inf_nan=False), Num]


class ViscoelasticSpec(Strict):
    """``fraction`` lambda in [0, 1], the share of the shear modulus that relaxes (the
    relaxed shear modulus is ``(1 - lambda) mu``); ``relaxation_time`` tau (s) of the
    Maxwell part."""

    fraction: Fraction
    relaxation_time: PosFloat


def viscoelastic_errors(deck: Any) -> Errors:
    """What ``material.viscoelastic`` does not run with: 2-D, the solvers without a
    history commit in time (static, fatigue, heat), the Warp backend, several bodies,
    thermal expansion."""
    errors: Errors = []
    key = "material.viscoelastic"
    if deck.dim != 3:
        errors.append((key, "needs a 3-D body (the 2-D deviatoric split is not implemented)"))
    errors += history_errors(
        deck, key, ("explicit", "adr"),
        "{solver} does not integrate the viscoelastic history in time; use explicit or adr "
        "(with load_time) with material.viscoelastic",
    )  # fmt: skip
    return errors
