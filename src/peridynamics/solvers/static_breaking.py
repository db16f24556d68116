"""Bond breaking between the static solver's solves (:class:`StaticBreaking`, a base of
:class:`peridynamics.solvers.static.StaticSolver`): the stretch ratios of the breaker's
candidate pairs at an equilibrium, the pairs its scheme breaks, the next load level
(k / N, or the next breaking event of a scalable solution) and the breaking itself with
the update of the factorisation (:mod:`peridynamics.solvers.breaking`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.solvers.breaking import PairBreaker
from peridynamics.state import State

__all__ = ["StaticBreaking"]

_EVENT_MARGIN = 1e-9  # lambda_c is raised by this relative margin so the bond breaks


class StaticBreaking:
    """The breaking steps of a static solve (attributes set by the solver).

    Attributes
    ----------
    model : Evaluator
    breaker : PairBreaker or None
    system : TangentSystem
    stats : dict
    lam : float, the current load level.
    load_steps : int
    scalable, event_driven : bool
    """

    model: Any
    breaker: PairBreaker | None
    system: Any
    stats: dict[str, Any]
    lam: float
    load_steps: int
    scalable: bool
    event_driven: bool
    _ratio: NDArray[np.float64] | None
    _picked: NDArray[np.int64] | None
    _first_break: tuple[list[float], float] | None

    def _ratios(self, s: State, breaker: PairBreaker) -> NDArray[np.float64]:
        """l / l_c of the breaker's candidate pairs at ``s`` (kept until the state or
        the bond status changes): the stretch of the candidates alone when the force
        model gives it (``pair_stretch``), else of every bond."""
        if self._ratio is None:
            fm = self.model.force_model
            c = breaker.candidates
            pair = getattr(fm, "pair_stretch", None)
            stretch = pair(s, c) if pair is not None else fm.bond_stretch(s)[c]
            self._ratio = breaker.pair_ratios(stretch, s.intact)
        return self._ratio

    def _violations(self, s: State) -> bool:
        """Compute (and keep) the stretch ratios and the pairs to break of the
        equilibrium ``s``; True when a bond reached its critical stretch."""
        self._ratio = self._picked = None
        if self.breaker is None:
            return False
        self._picked = self._pick(s, self.breaker)
        return bool(len(self._picked))

    def _pick(self, s: State, breaker: PairBreaker) -> NDArray[np.int64]:
        """The pairs the breaker's scheme breaks at the equilibrium ``s``."""
        return breaker.pick(self._ratios(s, breaker))

    def _event_factor(self, s: State, breaker: PairBreaker) -> float:
        """The factor by which the solution ``s`` scales before the next bond breaks."""
        return breaker.factor(self._ratios(s, breaker))

    def _next_level(self, s: State) -> float:
        """The next load level: k / N, or the next breaking event when scalable."""
        k = math.floor(self.lam * self.load_steps + 1e-9) + 1
        level = min(k / self.load_steps, 1.0)
        if self.scalable and self.event_driven and self.breaker is not None and self.lam > 0:
            factor = self._event_factor(s, self.breaker)
            event = self.lam * factor * (1.0 + _EVENT_MARGIN)
            if event < level:
                level = event
        return level

    def _break_pending(self, s: State, breaker: PairBreaker) -> int:
        """Break the bonds the last solve left at or over their critical stretch (the
        breaker's scheme) and update the factorisation; returns the directed bonds
        broken."""
        pairs = self._picked
        if pairs is None:
            pairs = self._pick(s, breaker)
        self._ratio = self._picked = None
        both = breaker.both_directions(pairs)
        if self._first_break is None and len(pairs):
            b = self.model.bonds
            x = self.model.cloud.x
            mid = 0.5 * (x[b.bond_i[pairs]] + x[b.bond_j[pairs]])
            self._first_break = (mid.mean(axis=0).tolist(), self.lam)
        s.intact[both] = 0
        broken = len(both)
        s.bonds_broken += broken
        self.system.remove_pairs(s, pairs)
        self.stats["events"] += 1
        return broken
