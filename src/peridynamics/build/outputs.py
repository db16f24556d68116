"""What the outputs of a run know of its deck: :func:`run_options` turns the deck into
the plain :class:`~peridynamics.io.observers.base.RunOptions` the observers read (the
outputs import no deck)."""

from __future__ import annotations

import numpy as np

from peridynamics import deck as dk
from peridynamics.io.observers.base import Blast, RunOptions


def can_break_bonds(deck: dk.Deck) -> bool:
    """True when some bond of the deck's model can break: a damage model other than
    ``none`` for the deck or a body, or a bonded interface."""
    if deck.damage.model != "none":
        return True
    if any(b.damage is not None and b.damage.model != "none" for b in deck.bodies):
        return True
    return any(
        i.type == "bonded" and (i.critical_stretch is not None or i.fracture_energy is not None)
        for i in deck.interfaces
    )


def deck_blasts(deck: dk.Deck) -> tuple[Blast, ...]:
    """The blast loads of the deck's boundary conditions, in deck order."""
    blasts: list[Blast] = []
    for spec in deck.boundary_conditions:
        fn = getattr(spec, "time_function", None)
        if fn is not None and fn.type == "blast":
            blasts.append(Blast(fn.charge_kg, fn.standoff_m, fn.shape, fn.delay))
    return tuple(blasts)


def run_options(deck: dk.Deck) -> RunOptions:
    """The deck's name, output section and the plain values the observers need."""
    speed = None
    if deck.output.wave_comparison is not None:  # the d'Alembert wave speed sqrt(E / rho)
        mat = deck.material
        speed = float(np.sqrt(mat.youngs_modulus / mat.density))
    return RunOptions(
        name=deck.name,
        output=deck.output,
        static=deck.solver.type in ("adr", "static", "fatigue"),
        can_break=can_break_bonds(deck),
        wave_speed=speed,
        blasts=deck_blasts(deck),
    )
