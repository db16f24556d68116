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
        "0.1.0",
        "the automatic step now includes solver.damping in the stable limit (a smaller "
        "step than before for this damped deck); give solver.time_step to fix it",
        _automatic_step_with_damping,
    ),
)


def notices(deck: Deck) -> list[str]:
    """One line per changed default the deck relies on (``key: ...``)."""
    return [
        f"{c.key} {c.message} (changed in {c.since}; CHANGELOG.md)"
        for c in CHANGED_DEFAULTS
        if c.applies(deck)
    ]
