"""Thermo-mechanical coupling: a mechanical solver whose force model expands with the
temperature (:mod:`peridynamics.families.thermal`), the temperature conducted in
sub-steps of every mechanical step (``staggered``) or held (``prescribed``).

Staggered explicit coupling (docs/theory_thermal.md): the mechanical step dt_m and the
stable forward-Euler step of the conduction dt_h (times the safety factor) differ; every
mechanical step first advances the temperature from t to t + dt_m by ``n_sub =
ceil(dt_m / dt_h)`` equal sub-steps over the bonds intact at t (broken bonds do not
conduct), then writes the thermal strain of the new temperature, then takes the
mechanical step, whose force at t + dt_m reads it. The mechanics acts on the heat only
through the broken bonds: there is no thermo-elastic heating term (the fully coupled
model of Oterkus, Madenci & Agwai (2014b) has one). ``prescribed``:
no conduction; the temperature is the initial one with the held temperatures of
``thermal.conditions`` applied at every step (their time functions at the solver's
time).
"""

from __future__ import annotations

import math
from typing import Any

from peridynamics.solvers.base import StepResult
from peridynamics.state import State


class ThermoMechanicalSolver:
    """A mechanical solver with the temperature of the State advanced before each step.

    Parameters
    ----------
    mechanical : Solver
        The explicit, dynamic-relaxation or static solver; every attribute this class
        does not define is the mechanical solver's.
    force_model : ForceModel
        The thermal-expansion variant the mechanical solver's evaluator holds
        (``update_thermal_strain``).
    heat : HeatSolver, optional
        Its conduction operator, conditions and stable step (``staggered``); None:
        ``prescribed``.
    held : HeatSolver-like, optional
        ``prescribed``: what applies the held temperatures (``apply_temperatures``).
    """

    def __init__(self, mechanical: Any, force_model: Any, heat: Any = None, held: Any = None):
        self.mechanical = mechanical
        self.force_model = force_model
        self.heat = heat
        self.held = held if held is not None else heat
        self.coupling = "staggered" if heat is not None else "prescribed"
        self.n_sub = 1
        self.heat_step = math.inf
        if heat is not None:
            dt_m = float(mechanical.dt)
            self.n_sub = max(1, math.ceil(dt_m / heat.dt - 1e-12))
            self.heat_step = dt_m / self.n_sub

    def __getattr__(self, name: str) -> Any:
        if name == "mechanical":  # not set yet (copy, pickle): no recursion
            raise AttributeError(name)
        return getattr(self.mechanical, name)

    def _hold(self, state: State, t: float) -> None:
        if self.held is not None:
            self.held.apply_temperatures(state["T"], t)
        self.force_model.update_thermal_strain(state)

    def init(self) -> State:
        """The mechanical solver's State (``T`` the initial temperature, the held ones
        applied at t = 0, its thermal strain)."""
        s: State = self.mechanical.init()
        self._hold(s, s.t)
        if self.mechanical.last_good is not None:
            self.mechanical.last_good = s.copy()
        return s

    def step(self, state: State) -> StepResult:
        """Advance the temperature to the end of the step, then the mechanics."""
        if self.heat is not None:
            T, t, h = state["T"], state.t, self.heat_step
            for k in range(self.n_sub):
                self.heat.advance(T, state.intact, t + k * h, h, state["heat_in"])
            self.force_model.update_thermal_strain(state)
        else:
            self._hold(state, state.t)
        result: StepResult = self.mechanical.step(state)
        return result

    def describe(self) -> str:
        """The mechanical solver and the coupling."""
        text = str(self.mechanical.describe())
        if self.heat is None:
            return f"{text}; thermal expansion at the prescribed temperature"
        return (
            f"{text}; staggered heat conduction: {self.n_sub} sub-step(s) of "
            f"{self.heat_step:.4g} s per step (stable limit {self.heat.stable_time_step:.4g} s)"
        )

    def summary_fields(self, state: State) -> dict[str, Any]:
        """The mechanical solver's, the coupling and (staggered) the heat balance (J)."""
        out: dict[str, Any] = dict(self.mechanical.summary_fields(state))
        out["thermal_coupling"] = self.coupling
        if self.heat is not None:
            out["heat_sub_steps"] = self.n_sub
            out.update(self.heat.heat_balance(state))
        return out
