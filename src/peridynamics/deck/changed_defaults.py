"""Defaults that changed: a deck that leaves such a key out gets other results than it
did before the change, so the run says so, naming the key (``note: ...`` on stderr and
``notices`` in ``summary.json``). One line per change in ``CHANGED_DEFAULTS``; the
changelog tells the whole story."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from peridynamics.deck.schema import Deck


@dataclass(frozen=True)
class ChangedDefault:
    """A default that changed: ``applies(deck)`` is true when the deck relies on it."""

    key: str
    since: str
    message: str
    applies: Callable[[Deck], bool]


def _unset_surface_correction(deck: Deck) -> bool:
    return "surface_correction" not in deck.discretisation.model_fields_set


def _automatic_step_with_damping(deck: Deck) -> bool:
    solver = deck.solver
    return getattr(solver, "time_step", None) is None and float(getattr(solver, "damping", 0.0)) > 0


def _spectral_family(deck: Deck) -> bool:
    """A single-body LPS deck, or correspondence without damage: its bound comes from
    the Lanczos estimate (:mod:`peridynamics.evaluation.spectral`)."""
    model = getattr(deck.material, "model", None)
    if getattr(deck, "bodies", None) or model not in ("lps", "correspondence"):
        return False
    damage = getattr(deck, "damage", None)
    breaks = damage is not None and getattr(damage, "model", "none") != "none"
    return model == "lps" or not breaks


def _spectral_explicit_step(deck: Deck) -> bool:
    solver = deck.solver
    return (
        _spectral_family(deck)
        and getattr(solver, "type", "explicit") == "explicit"
        and getattr(solver, "time_step", None) is None
    )


def _spectral_adr_density(deck: Deck) -> bool:
    return _spectral_family(deck) and getattr(deck.solver, "type", None) == "adr"


CHANGED_DEFAULTS = (
    ChangedDefault(
        "discretisation.surface_correction",
        "0.1.0",
        "defaults to true (the nominal Young's modulus at surfaces too); decks written "
        "before it relied on false: set discretisation.surface_correction: false to keep "
        "their results",
        _unset_surface_correction,
    ),
    ChangedDefault(
        "solver.time_step",
        "0.2.0",
        "the automatic step now includes solver.damping in the stable limit (a smaller "
        "step than before for this damped deck); give solver.time_step to fix it",
        _automatic_step_with_damping,
    ),
    ChangedDefault(
        "solver.time_step",
        "0.2.0",
        "the automatic step of an LPS or correspondence deck now comes from a Lanczos "
        "estimate of the highest frequency (1/sqrt(1.25) = 0.89 of the critical step "
        "before safety_factor): 1.1 (LPS) to 3 (correspondence, 3-D) times longer than "
        "before; give solver.time_step to fix it",
        _spectral_explicit_step,
    ),
    ChangedDefault(
        "solver.tolerance",
        "0.2.0",
        "dynamic relaxation of an LPS or correspondence deck now takes its fictitious "
        "density from a Lanczos estimate of the largest eigenvalue (up to 1.25 over it, "
        "before 1.4-12 times): fewer iterations, and the converged fields move within "
        "solver.tolerance; tighten solver.tolerance to compare with earlier results",
        _spectral_adr_density,
    ),
)


def notices(deck: Deck) -> list[str]:
    """One line per changed default the deck relies on (``key: ...``)."""
    return [
        f"{c.key} {c.message} (changed in {c.since}; CHANGELOG.md)"
        for c in CHANGED_DEFAULTS
        if c.applies(deck)
    ]
