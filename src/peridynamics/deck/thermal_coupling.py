"""The deck's checks of thermo-mechanical coupling (``thermal.expansion`` with a
mechanical solver; docs/theory_thermal.md): what runs it, and what is refused by key."""

from __future__ import annotations

from typing import Any

from peridynamics.deck.types import Errors

#: the mechanical solvers that run the coupling
COUPLED_SOLVERS = ("explicit", "adr", "static")


def coupling_of(deck: Any) -> str | None:
    """``staggered`` or ``prescribed`` for a deck with ``thermal.expansion`` and a
    mechanical solver (``thermal.coupling``, default ``staggered`` with the explicit
    solver and ``prescribed`` with the quasi-static ones); None otherwise."""
    th = deck.thermal
    if th is None or th.expansion is None or deck.solver.type in ("heat", "heat_steady"):
        return None
    if th.coupling is not None:
        return str(th.coupling)
    return "staggered" if deck.solver.type == "explicit" else "prescribed"


def _family_errors(deck: Any) -> Errors:
    """The family must declare thermal expansion; no variant the damage section picks.
    (The registry is imported here, not at the top: importing the deck must not import
    the families and their Numba kernels, which would lengthen the command line's
    start-up.)"""
    from peridynamics.families.registry import FAMILIES

    model = deck.material.model
    family = FAMILIES.get(model)
    if family is None or family.thermal is None:
        have = sorted({f.name for f in FAMILIES.values() if f.thermal is not None})
        return [
            (
                "thermal.expansion",
                f"material.model {model} has no thermal expansion; use one of {have}",
            )
        ]
    if deck.dim == 1:
        return [("thermal.expansion", "thermal expansion runs in 2-D and 3-D")]
    dmg = deck.damage
    errors: Errors = []
    if dmg.bond_law != "brittle" or dmg.sed_softening is not None:
        key = "damage.bond_law" if dmg.bond_law != "brittle" else "damage.sed_softening"
        errors.append((key, "thermal expansion runs with brittle bonds (bond_law brittle)"))
    if dmg.model not in ("critical_stretch", "none"):
        errors.append(
            ("damage.model", "thermal expansion breaks bonds by critical_stretch (or none)")
        )
    return errors


def _solver_errors(deck: Any, coupling: str) -> Errors:
    s = deck.solver
    errors: Errors = []
    if s.type not in COUPLED_SOLVERS:
        return [("solver.type", f"thermal expansion runs with {', '.join(COUPLED_SOLVERS)}")]
    if s.type == "explicit":
        if s.method != "pd" or s.hybrid is not None:
            errors.append(("solver.method", "thermal expansion runs with method pd, no hybrid"))
        if s.backend != "numba":
            errors.append(("solver.backend", "thermal expansion runs on the numba backend"))
        if s.precision != "float64":
            errors.append(("solver.precision", "thermal expansion runs in float64"))
    elif coupling == "staggered":
        errors.append(
            (
                "thermal.coupling",
                f"staggered conduction needs solver.type explicit; solver.type {s.type} "
                "runs coupling: prescribed (the temperature held, no conduction)",
            )
        )
    return errors


def coupling_errors(deck: Any) -> Errors:
    """A ``thermal`` section with a mechanical solver: ``thermal.expansion`` given, a
    family that declares thermal expansion, a solver that runs the coupling, a single
    body."""
    th = deck.thermal
    if th.expansion is None:
        return [
            (
                "thermal.expansion",
                "a thermal section with a mechanical solver couples through thermal "
                "expansion: give expansion (1/K), or use solver.type heat / heat_steady",
            )
        ]
    coupling = coupling_of(deck)
    assert coupling is not None
    errors = _family_errors(deck) + _solver_errors(deck, coupling)
    if getattr(deck, "bodies", None):
        errors.append(("bodies", "thermal expansion runs with a single body"))
    return errors
