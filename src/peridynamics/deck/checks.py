"""Checks that need several sections of a deck, in the order they are reported.

Each section's module owns its checks (a model family's are the ``deck_errors`` of its
schema); :func:`cross_check` runs them in turn and gathers the (key path, message)
pairs.
"""

from __future__ import annotations

from peridynamics.deck.bodies import bodies_errors
from peridynamics.deck.cracks import notch_errors, precrack_errors
from peridynamics.deck.damage import no_fail_errors
from peridynamics.deck.derived import derived_errors
from peridynamics.deck.geometry import geometry_set_names, hole_errors
from peridynamics.deck.loading import condition_errors
from peridynamics.deck.output import crack_tracking_errors, output_errors, probe_errors
from peridynamics.deck.regions import node_set_errors, node_set_names
from peridynamics.deck.schema import Deck
from peridynamics.deck.solver import solver_errors
from peridynamics.deck.thermal import thermal_errors
from peridynamics.deck.types import Errors


def cross_check(deck: Deck) -> Errors:
    """Checks that need several sections: dimensions, node-set names, the model family
    against the damage law and the solver, outputs, bodies, derived quantities."""
    sets = node_set_names(deck) | geometry_set_names(deck.geometry)
    errors: Errors = []
    errors += node_set_errors(deck, sets)
    errors += hole_errors(deck)
    errors += deck.material.deck_errors(deck)
    errors += no_fail_errors(deck, sets)
    errors += condition_errors(deck, sets)
    errors += precrack_errors(deck)
    errors += output_errors(deck, sets)
    errors += solver_errors(deck)
    errors += thermal_errors(deck, sets)
    errors += probe_errors(deck, sets)
    errors += crack_tracking_errors(deck, sets)
    errors += notch_errors(deck)
    errors += bodies_errors(deck, geometry_set_names(deck.geometry))
    return errors + derived_errors(deck)
