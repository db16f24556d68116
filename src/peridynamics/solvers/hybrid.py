"""Hybrid explicit solvers: run a cheap scheme while the body is elastic, then switch to
the fracture-capable peridynamic model (Lu & Wang (2016), section 3.3: PD1 -> PD3, FDM -> PD3).

The switching rule is an object (any rule with ``should_switch(state, first, second)``),
not a special case inside a solver. The two models share the points, so the transfer of
u, v (and the central-difference history u(t - dt)) is exact; the bonds of the second
model start intact.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from peridynamics.evaluation import Evaluator
from peridynamics.solvers.base import StepResult
from peridynamics.solvers.explicit import ExplicitSolver
from peridynamics.state import State


class SwitchingRule(Protocol):
    """Decides, after each step of the first solver, whether to switch."""

    def should_switch(self, state: State, first: Evaluator, second: Evaluator) -> bool:
        """True to hand the state over to the second model now."""
        ...


@dataclass
class SwitchAtStretch:
    """Switch when the largest tensile stretch reaches ``fraction`` x the smallest
    critical stretch of the second model (Lu & Wang (2016), section 3.3: 0.9 s0). For a
    finite-difference first model the stretch is Delta u / dx between neighbours."""

    fraction: float = 0.9
    _cached: tuple[Evaluator, float] | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not 0 < self.fraction <= 1:
            raise ValueError("the switching fraction must be in (0, 1]")

    def should_switch(self, state: State, first: Evaluator, second: Evaluator) -> bool:
        if self._cached is None or self._cached[0] is not second:  # once per model
            self._cached = (second, self.threshold(second))
        limit = self._cached[1]
        return bool(np.isfinite(limit) and state.max_stretch.max() >= limit)

    def threshold(self, second: Evaluator) -> float:
        """``fraction`` x the smallest finite critical stretch of ``second`` (inf when
        nothing in it can break)."""
        finite = second.point_s0[np.isfinite(second.point_s0)]
        return float(self.fraction * finite.min()) if finite.size else float("inf")


class HybridSolver:
    """Step ``first`` until ``rule`` fires, then ``second`` (same points, same dt).

    The exposed state always carries the second model's bond flags; while the first
    model runs, its own (never broken) flags are kept aside. ``state.phase`` is 0 before
    and 1 after the switch, so checkpoints resume in the right phase.
    """

    #: named events of its step results (a capability: the run loop records them)
    step_events: tuple[str, ...] = ("switched",)

    def __init__(self, first: ExplicitSolver, second: ExplicitSolver, rule: SwitchingRule) -> None:
        if first.model.n_points != second.model.n_points:
            raise ValueError("hybrid solvers need the same points in both models")
        if first.dt != second.dt or first.integrator != second.integrator:
            raise ValueError("hybrid solvers need the same time step and integrator")
        self.first, self.second, self.rule = first, second, rule
        self.dt = second.dt
        self.integrator = second.integrator
        self.stable_time_step = min(first.stable_time_step, second.stable_time_step)
        self.check_every = second.check_every
        self.model = second.model
        self._first_intact = first.model.bonds.bond_intact.copy()
        self.switch_time: float | None = None

    @property
    def last_good(self) -> State | None:
        return self.second.last_good

    @last_good.setter
    def last_good(self, value: State | None) -> None:
        self.second.last_good = value

    @property
    def n_steps(self) -> int | None:
        return self.second.n_steps

    def init(self) -> State:
        """State at t = 0 from the first solver, with the second model's bond flags."""
        s = self.first.init()
        self._first_intact = s.intact
        s.intact = self.second.model.bonds.bond_intact.copy()
        s.phase = 0
        self.second.last_good = s.copy()
        self.second.warm_up(self.model.dim)
        return s

    def resume(self, state: State) -> None:
        """Continue from a checkpoint (in the phase it was written in)."""
        self.second.resume(state)

    def step(self, s: State) -> StepResult:
        """One step of the active solver; switch when the rule says so."""
        if s.phase == 1:
            return self.second.step(s)
        own, s.intact = s.intact, self._first_intact
        try:
            result = self.first.step(s)
            self.first.model.force_model.update_max_stretch(s)  # the first model's bonds
        finally:
            self._first_intact, s.intact = s.intact, own
        if self.rule.should_switch(s, self.first.model, self.second.model):
            self._switch(s)
            result.events = (*result.events, "switched")
        return result

    def _switch(self, s: State) -> None:
        """Hand over: forces of the second model at the same u (its bonds intact)."""
        m = self.second.model
        m.evaluate(s, commit=True)
        m.external_force(s.t, s.body)
        s.phase = 1
        self.switch_time = s.t

    def check(self, s: State) -> None:
        """Stability check of the active solver."""
        (self.second if s.phase == 1 else self.first).check(s)

    def done(self, s: State) -> bool:
        return self.second.done(s)

    def total_steps(self) -> int:
        return self.second.total_steps()

    def describe(self) -> str:
        """dt, stable limit and number of steps of the hybrid run."""
        return self.second.describe()

    def summary_fields(self, s: State) -> dict[str, Any]:
        """Time step, stable limit, and when the hybrid switched."""
        return {
            "time_step_s": self.dt,
            "stable_time_step_s": self.stable_time_step,
            "switch_time_s": self.switch_time,
            "switched": s.phase == 1,
        }

    def steps_for(self, end_time: float) -> int:
        """Number of steps to reach ``end_time``."""
        return self.second.steps_for(end_time)
