"""Deck section ``damage.fatigue``: the remaining-life fatigue law of the bonds
(``damage.model: fatigue``; Silling & Askari (2014)), and the checks that tie it to
``solver.type: fatigue``."""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import Field, model_validator

from peridynamics.deck.types import Errors, Num, PosFloat, Strict


class SNPoint(Strict):
    """One point of the S-N (strain-life) curve: a uniform bar cycled at the bond
    strain range ``strain_range`` breaks after ``cycles`` cycles."""

    strain_range: PosFloat
    cycles: PosFloat


class FatigueSpec(Strict):
    """Remaining life lambda of every bond, d lambda/dN = -A eps^m with eps = |1 - R|
    |s+|: phase I (``a1``, ``m1``; or ``sn_point`` with ``m1``: a1 = 1 / (N eps^m1))
    everywhere, phase II (``a2``, ``m2``; m2 is the Paris exponent) at bonds with an end
    point whose damage exceeds ``phase_two_damage``."""

    m1: PosFloat
    a1: PosFloat | None = None
    sn_point: SNPoint | None = None
    m2: PosFloat
    a2: PosFloat
    phase_two_damage: Annotated[float, Field(ge=0, lt=1, allow_inf_nan=False), Num] = 0.0

    @model_validator(mode="after")
    def _one(self) -> FatigueSpec:
        if (self.a1 is None) == (self.sn_point is None):
            raise ValueError(
                "[a1] give exactly one of a1 (1/cycle) or sn_point {strain_range, cycles}"
            )
        return self

    @property
    def phase_one_a(self) -> float:
        """A1 (1/cycle): given, or from the S-N point."""
        if self.a1 is not None:
            return float(self.a1)
        assert self.sn_point is not None
        return 1.0 / (self.sn_point.cycles * self.sn_point.strain_range**self.m1)


def fatigue_damage_errors(damage: Any) -> str | None:
    """The message of a ``damage`` section whose fatigue keys do not fit its model
    (None when they do)."""
    if damage.model == "fatigue":
        if damage.fatigue is None:
            return "[fatigue] damage.model fatigue needs the section damage.fatigue (m1, a1, ...)"
        for key in ("critical_stretch", "fracture_energy", "tensile_strength"):
            if getattr(damage, key) is not None:
                return f"[{key}] damage.model fatigue breaks bonds by remaining life: remove {key}"
        for key in ("weibull", "sed_softening"):
            if getattr(damage, key) is not None:
                return f"[{key}] does not combine with damage.model fatigue; remove it"
    elif damage.fatigue is not None:
        return "[fatigue] is used with damage.model fatigue only; set it or remove the section"
    return None


def fatigue_errors(deck: Any) -> Errors:
    """``solver.type: fatigue`` and ``damage.model: fatigue`` go together; the law's
    bonds must be plain bonds (no bond_law)."""
    fatigue_solver = deck.solver.type == "fatigue"
    fatigue_law = deck.damage.model == "fatigue"
    if fatigue_solver and not fatigue_law:
        return [
            (
                "damage.model",
                "solver.type fatigue needs damage.model: fatigue (with damage.fatigue: "
                "m1, a1, m2, a2)",
            )
        ]
    if fatigue_law and not fatigue_solver:
        return [
            (
                "solver.type",
                "damage.model fatigue consumes bond life per load cycle: it needs "
                "solver.type: fatigue (cycle jumping between static solves)",
            )
        ]
    if fatigue_law and deck.damage.bond_law != "brittle":
        return [("damage.bond_law", "fatigue breaks brittle bonds only; remove bond_law")]
    return []
