"""Heat-conduction solvers (docs/theory_thermal.md): explicit forward Euler with its
own stable step (:class:`HeatSolver`, ``solver.type: heat``) and the steady state by
one sparse solve (:class:`SteadyHeatSolver`, ``solver.type: heat_steady``).

The temperature is the State field ``T`` (n,) (K); the rest of the State is the
mechanical model's at rest (the mechanics is not stepped: thermo-mechanical coupling
is not implemented yet), so frames and observers read it as in any run. Bonds broken
in ``intact`` conduct no heat.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from peridynamics.evaluation.heat import HeatConduction
from peridynamics.kernels import heat as kernels
from peridynamics.loading.thermal import (
    Convection,
    HeatSource,
    MirroredTemperature,
    PrescribedTemperature,
)
from peridynamics.solvers.base import StepResult
from peridynamics.solvers.explicit import SimulationUnstable
from peridynamics.state import State

F = NDArray[np.float64]
#: a held temperature: constant on its set, or a mirrored fictitious layer
Held = PrescribedTemperature | MirroredTemperature


class _HeatBase:
    """What both heat solvers share: the conduction operator, the conditions, the
    State with ``T`` and the heat bookkeeping."""

    def __init__(
        self,
        conduction: HeatConduction,
        model: Any = None,
        initial_temperature: float = 0.0,
        temperatures: Sequence[Held] = (),
        sources: Sequence[HeatSource] = (),
        convection: Sequence[Convection] = (),
    ) -> None:
        self.conduction = conduction
        self.model = model
        self.initial_temperature = float(initial_temperature)
        self.temperatures = list(temperatures)
        self.sources = list(sources)
        self.convection = list(convection)
        self.last_good: State | None = None
        n = conduction.n_points
        held = [c.nodes for c in self.temperatures]
        self._held = np.unique(np.concatenate(held)) if held else np.zeros(0, np.intp)
        self._free = np.setdiff1d(np.arange(n), self._held)
        self._conv_diag = np.zeros(n)  # h / l per point (W/(m^3 K))
        for c in self.convection:
            np.add.at(self._conv_diag, c.nodes, c.coefficient)

    def new_state(self) -> State:
        """The mechanical model's State at rest (or bonds only) plus ``T`` and the
        heat supplied through the sources ``heat_in`` (1,) (J)."""
        if self.model is not None:
            s: State = self.model.new_state()
        else:
            s = State(intact=self.conduction.bonds.bond_intact.copy())
        s["T"] = np.full(self.conduction.n_points, self.initial_temperature)
        s["heat_in"] = np.zeros(1)
        return s

    def apply_temperatures(self, temperature: F, t: float) -> None:
        """Hold the prescribed temperatures at time ``t`` (s); mirrored layers three
        times (a corner's mirror is another layer's point, resolved in 2-D by the
        second pass and in 3-D by the third)."""
        mirrored = any(isinstance(c, MirroredTemperature) for c in self.temperatures)
        for _ in range(3 if mirrored else 1):
            for c in self.temperatures:
                c.apply(temperature, t)

    def source(self, temperature: F, t: float, out: F) -> F:
        """Sources and convection at time ``t`` (s), W/m^3 (n,), into ``out``."""
        out[:] = 0.0
        for c in self.sources:
            c.add_to(out, t)
        for cv in self.convection:
            cv.add_to(out, temperature, t)
        return out

    def check(self, state: State) -> None:
        """Raise :class:`SimulationUnstable` on a non-finite temperature; else keep the
        state as the last good one."""
        bad = np.flatnonzero(~np.isfinite(state["T"]))
        if len(bad):
            p = int(bad[0])
            where = [float(c) for c in self.conduction.cloud.x[p]]
            raise SimulationUnstable(
                f"non-finite temperature at step {state.step}",
                state.step, state.t, p, where, self.last_good,
            )  # fmt: skip
        self.last_good = state.snapshot(self.last_good)

    def resume(self, state: State) -> None:
        """Continue from a State read from a checkpoint."""
        self.last_good = state.copy()

    def heat_balance(self, state: State) -> dict[str, float]:
        """Stored heat sum V rho c (T - T0) and the heat supplied by the sources (J)."""
        stored = self.conduction.heat_content(state["T"], self.initial_temperature)
        return {"heat_stored_J": stored, "heat_in_J": float(state["heat_in"][0])}


class HeatSolver(_HeatBase):
    """Transient conduction by forward Euler (``solver.type: heat``).

    ``T^{n+1} = T^n + dt (L T^n + s(t_n, T^n)) / (rho c)`` on the free points, then the
    prescribed temperatures at ``t_{n+1}``. The step is ``time_step`` or
    ``safety_factor`` times :meth:`HeatConduction.stable_time_step` (with convection);
    a given step above the bound is refused unless ``allow_unstable``.

    Parameters
    ----------
    conduction : HeatConduction
    model : the mechanical Evaluator whose State the run carries (or None).
    initial_temperature : float, K.
    temperatures, sources, convection : the conditions.
    time_step : float, optional, s.
    safety_factor : float, in (0, 1].
    end_time : float, optional, s; or ``steps``.
    steps : int, optional.
    allow_unstable : bool
    """

    def __init__(
        self,
        conduction: HeatConduction,
        model: Any = None,
        initial_temperature: float = 0.0,
        temperatures: Sequence[Held] = (),
        sources: Sequence[HeatSource] = (),
        convection: Sequence[Convection] = (),
        time_step: float | None = None,
        safety_factor: float = 0.9,
        end_time: float | None = None,
        steps: int | None = None,
        allow_unstable: bool = False,
    ) -> None:
        super().__init__(conduction, model, initial_temperature, temperatures, sources, convection)
        intact = conduction.bonds.bond_intact
        self.stable_time_step = conduction.stable_time_step(intact, self._conv_diag)
        if time_step is not None and time_step > self.stable_time_step and not allow_unstable:
            raise ValueError(
                f"[time_step] {time_step:.4g} s is above the stable limit "
                f"{self.stable_time_step:.4g} s of forward Euler (rho c / sum G); lower it, "
                "omit it, or set allow_unstable: true"
            )
        self.dt = float(
            time_step if time_step is not None else safety_factor * self.stable_time_step
        )
        if steps is None:
            if end_time is None:
                raise ValueError("[end_time] give end_time (s) or steps")
            steps = max(1, math.ceil(end_time / self.dt - 1e-9))
            if time_step is None:  # the step that ends the run at end_time exactly
                self.dt = end_time / steps
        self.n_steps = int(steps)
        n = conduction.n_points
        self._rate, self._src = np.zeros(n), np.zeros(n)

    def init(self) -> State:
        """The State at t = 0: the initial temperature and the prescribed ones."""
        s = self.new_state()
        self.apply_temperatures(s["T"], 0.0)
        kernels.warm_up()
        self.last_good = s.copy()
        return s

    def step(self, state: State) -> StepResult:
        """One forward-Euler step of ``dt``."""
        self.advance(state["T"], state.intact, state.t, self.dt, state["heat_in"])
        state.t += self.dt
        state.step += 1
        return StepResult()

    def advance(self, T: F, intact: NDArray[np.uint8], t: float, dt: float, heat_in: F) -> None:
        """One forward-Euler step of ``dt`` (s) from ``t`` of the temperature ``T`` (n,)
        (K) in place, the prescribed temperatures then held at ``t + dt``; adds the
        heat the sources supplied (J) to ``heat_in`` (1,). The thermo-mechanical
        coupling sub-cycles the conduction with it."""
        c = self.conduction
        c.rate(T, intact, self._rate)
        self.source(T, t, self._src)
        self._src[self._held] = 0.0
        self._rate[self._held] = 0.0
        heat_in[0] += dt * float(np.dot(c.cloud.volume, self._src))
        kernels.euler_update(T, self._rate, self._src, c.inv_capacity, dt, T)
        self.apply_temperatures(T, t + dt)

    def done(self, state: State) -> bool:
        """True after the run's steps."""
        return state.step >= self.n_steps

    def total_steps(self) -> int:
        """Steps of the whole run."""
        return self.n_steps

    def describe(self) -> str:
        """Time step, stable limit and steps."""
        return (
            f"heat conduction (forward Euler): dt = {self.dt:.4g} s "
            f"(stable limit {self.stable_time_step:.4g} s), {self.n_steps} steps"
        )

    def summary_fields(self, state: State) -> dict[str, Any]:
        """Time step, stable limit (s) and the heat balance (J)."""
        return {
            "time_step_s": self.dt,
            "stable_time_step_s": self.stable_time_step,
            **self.heat_balance(state),
        }


class SteadyHeatSolver(_HeatBase):
    """The steady state in one step (``solver.type: heat_steady``): the conditions'
    time functions at pseudo-time t = 1 (as the static solvers' full load), then

        -V L T - V s(T) = 0

    on the free points with the prescribed temperatures eliminated: ``diag(V) L`` is
    symmetric and, with convection on the diagonal, the system is symmetric positive
    definite when some temperature is held or some surface convects (else the
    temperature is fixed up to a constant and it is refused). SciPy's sparse direct
    solver (SuperLU) solves it.
    """

    def init(self) -> State:
        """The State before the solve (T = the initial temperature)."""
        s = self.new_state()
        self.last_good = s.copy()
        return s

    def step(self, state: State) -> StepResult:
        """Solve for the steady temperature at pseudo-time 1."""
        c, t = self.conduction, 1.0
        T = state["T"]
        self.apply_temperatures(T, t)
        v = c.cloud.volume
        a = (sp.diags(v) @ (-c.matrix(state.intact))).tocsr() + sp.diags(v * self._conv_diag)
        src = np.zeros(c.n_points)
        for s in self.sources:
            s.add_to(src, t)
        for cv in self.convection:  # the ambient part; h/l T is on the diagonal
            src[cv.nodes] += cv.coefficient * cv.ambient_at(t)
        rhs = v * src
        free, held = self._free, self._held
        if len(held) == 0 and not np.any(self._conv_diag > 0):
            raise ValueError(
                "[solver.type] a steady state needs a prescribed temperature or convection"
            )
        if any(isinstance(c, MirroredTemperature) for c in self.temperatures):
            residual = self._solve_with_mirrors(a, rhs, T, t)
        else:
            a_ff = a[free][:, free].tocsc()
            rhs_f = rhs[free] - a[free][:, held] @ T[held]
            T[free] = spla.spsolve(a_ff, rhs_f)
            residual = _relative(a_ff @ T[free] - rhs_f, rhs_f)
        state.t, state.step = t, state.step + 1
        return StepResult(converged=True, residual=residual)

    def _solve_with_mirrors(self, a: sp.csr_matrix, rhs: F, T: F, t: float) -> float:
        """All points as unknowns: the conduction rows of the free points and one
        constraint row per held point (``T_i = T_b``, or ``T_i + T_m = 2 T_b`` for a
        mirrored layer; the last condition on a point wins); SuperLU on the
        (non-symmetric) system. Returns the relative residual."""
        n = len(T)
        rows: dict[int, tuple[list[int], list[float], float]] = {}
        for c in self.temperatures:
            tb = c.temperature(t)
            if isinstance(c, MirroredTemperature):
                for i, m in zip(c.nodes.tolist(), c.mirror.tolist(), strict=True):
                    rows[i] = ([i], [1.0], tb) if i == m else ([i, m], [1.0, 1.0], 2 * tb)
            else:
                for i in c.nodes.tolist():
                    rows[i] = ([i], [1.0], tb)
        held = np.fromiter(rows, dtype=np.intp, count=len(rows))
        keep = np.ones(n, bool)
        keep[held] = False
        body = sp.diags(keep.astype(float)) @ a  # the conduction rows of the free points
        r = [i for i in rows for _ in rows[i][0]]
        cols = [j for i in rows for j in rows[i][0]]
        vals = [v for i in rows for v in rows[i][1]]
        m = (body + sp.csr_matrix((vals, (r, cols)), shape=(n, n))).tocsc()
        b = np.where(keep, rhs, 0.0)
        b[held] = [rows[i][2] for i in held.tolist()]
        T[:] = spla.spsolve(m, b)
        return _relative(m @ T - b, b)

    def done(self, state: State) -> bool:
        """True after the solve."""
        return state.step >= 1

    def total_steps(self) -> int:
        """One solve."""
        return 1

    def describe(self) -> str:
        """One line."""
        return f"steady heat conduction: one sparse solve, {len(self._free)} free points"

    def summary_fields(self, state: State) -> dict[str, Any]:
        """The stored heat relative to the initial temperature (J)."""
        return {"heat_stored_J": self.heat_balance(state)["heat_stored_J"]}


def _relative(residual: F, rhs: F) -> float:
    """|residual| / |rhs| (|rhs| at least 1e-300)."""
    return float(np.linalg.norm(residual) / max(float(np.linalg.norm(rhs)), 1e-300))
