"""Deck sections ``precracks`` and ``notches``: bonds cut before the run (segments,
rectangles, slots of a width), with their checks against the model's dimension."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, model_validator

from peridynamics.deck.regions import check_len
from peridynamics.deck.types import Errors, Finite, PosFloat, Strict


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


# --------------------------------------------------------------------------- checks
def precrack_errors(deck: Any) -> Errors:
    """Checks of ``precracks``: a 2-D or 3-D model, 2 or 3 points of its dimension,
    a crack the bond builder can cut."""
    errors: Errors = []
    dim = deck.dim
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
            check_len(errors, f"precracks.{n}.points.{k}", p, dim)
        if len(crack.points) == want and all(len(p) == dim for p in crack.points):
            from peridynamics.bonds.precrack import make_crack

            try:
                make_crack(crack.points)
            except ValueError as exc:
                errors.append((f"precracks.{n}.points", str(exc)))
    return errors


def notch_errors(deck: Any) -> Errors:
    """Checks of ``notches``: a 2-D or 3-D model, [x, y] ends, z only in 3-D."""
    errors: Errors = []
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
