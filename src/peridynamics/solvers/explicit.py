"""Explicit dynamics: velocity Verlet (SED-PD (2021), eq. 12) and central difference
(Lu & Wang (2016), eq. 10).

Both integrators share one shape: ``init() -> State``, ``step(state) -> State``, the
generator ``irun(state, n_steps)`` and ``run(...)``. The stable step is the bound of
Silling & Askari (2005), ``dt_i = sqrt(2 rho / sum_k stiffness_k / |xi_k|)`` minimised
over points, lowered by the mass damping and the linear viscosity
(:mod:`peridynamics.evaluation.stability`); a user step above it is refused unless
``allow_unstable=True``. Implausible settings are warned about, naming their key
(:mod:`peridynamics.solvers.plausibility`).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from peridynamics.evaluation import Evaluator
from peridynamics.evaluation.stability import StableStep
from peridynamics.kernels import bond_based, integrators
from peridynamics.loading.conditions import (
    COMPONENTS,
    Fixed,
    InitialVelocity,
    PrescribedDisplacement,
    PrescribedVelocity,
)
from peridynamics.solvers.base import StepResult
from peridynamics.solvers.plausibility import unstable_advice, warn_implausible
from peridynamics.state import State

Integrator = Literal["velocity_verlet", "central_difference"]
INTEGRATORS: tuple[str, ...] = ("velocity_verlet", "central_difference")


class SimulationUnstable(RuntimeError):
    """Raised when the solution becomes non-finite or blows up.

    Attributes: step, time (s), point (index), coordinates (m), last_good (State).

    Examples
    --------
    >>> import peridynamics as pd
    >>> deck = pd.Deck.example("bar_wave_1d", {"solver.time_step": 1.0e-5,
    ...     "solver.allow_unstable": True, "solver.end_time": 1.0e-2})
    >>> try:
    ...     pd.Simulation(deck).run()
    ... except pd.SimulationUnstable as exc:
    ...     print("unstable at step", exc.step)  # doctest: +ELLIPSIS
    unstable at step ...
    """

    def __init__(
        self,
        message: str,
        step: int,
        time: float,
        point: int,
        coordinates: list[float],
        last_good: State | None,
    ) -> None:
        super().__init__(message)
        self.step = step
        self.time = time
        self.point = point
        self.coordinates = coordinates
        self.last_good = last_good


class UnstableTimeStep(ValueError):
    """A user time step above the stable limit."""


@dataclass
class ExplicitSolver:
    """Explicit time integration of a :class:`~peridynamics.evaluation.evaluator.Evaluator`.

    Parameters
    ----------
    model : Evaluator
    time_step : float, optional
        dt (s); default ``safety_factor * stable_time_step``.
    integrator : {"velocity_verlet", "central_difference"}
    constraints : kinematic conditions (prescribed displacement / velocity, fixed).
    initial_velocities : conditions applied once at t = 0.
    safety_factor : float
        Fraction of the stable step used when ``time_step`` is not given.
    allow_unstable : bool
        Accept a ``time_step`` above the stable limit.
    blowup_factor : float
        A displacement (less the mean displacement) larger than
        ``blowup_factor * model size`` stops the run.
    max_stretch : float
        An intact bond stretched more than this stops the run (integration blew up).
    check_every : int
        Steps between finiteness / blow-up checks.
    steps, end_time : int, float, optional
        Length of the run (at most one): ``done`` is true after ``steps`` steps or once
        ``end_time`` (s) is reached; with neither the run ends only when the caller
        stops stepping.

    Examples
    --------
    >>> import numpy as np
    >>> import peridynamics as pd
    >>> grid = np.meshgrid(np.arange(10), np.arange(5), indexing="ij")
    >>> x = np.stack(grid, -1).reshape(-1, 2) * 1e-3  # m
    >>> cloud = pd.PointCloud(x=x, volume=np.full(50, 1e-9), spacing=1e-3, plane="stress")
    >>> bonds = pd.build_bonds(cloud, 3.015e-3)
    >>> model = pd.Evaluator(cloud, bonds, pd.BondBasedMaterial(70e9, 2700.0))
    >>> solver = pd.ExplicitSolver(model, safety_factor=0.8)
    >>> state = solver.init()
    >>> state.v[:, 0] = np.linspace(-1.0, 1.0, 50)  # m/s: the plate is stretched
    >>> for _ in range(10):
    ...     result = solver.step(state)
    >>> state.step, bool(state.t > 0)
    (10, True)
    """

    model: Evaluator
    time_step: float | None = None
    integrator: Integrator = "velocity_verlet"
    constraints: Sequence[PrescribedDisplacement | PrescribedVelocity | Fixed] = ()
    initial_velocities: Sequence[InitialVelocity] = ()
    safety_factor: float = 0.8
    allow_unstable: bool = False
    blowup_factor: float = 1.0
    max_stretch: float = 1.0
    check_every: int = 10
    steps: int | None = None
    end_time: float | None = None

    def __post_init__(self) -> None:
        if self.integrator not in INTEGRATORS:
            raise ValueError(f"unknown integrator {self.integrator!r}; use one of {INTEGRATORS}")
        if not 0 < self.safety_factor <= 1:
            raise ValueError("safety_factor must be in (0, 1]")
        step = getattr(self.model, "stable_step", None)
        self.stable_step: StableStep = (
            step() if step is not None else StableStep(self.model.stable_time_step())
        )
        self.stable_time_step = self.stable_step.value
        if self.time_step is None:
            self.dt = self.safety_factor * self.stable_time_step
        else:
            if not self.time_step > 0:
                raise ValueError(f"time_step must be > 0 s, got {self.time_step}")
            if self.time_step > self.stable_time_step and not self.allow_unstable:
                raise UnstableTimeStep(
                    f"solver.time_step = {self.time_step:.6g} s is above the stable limit "
                    f"{self.stable_time_step:.6g} s (Silling & Askari 2005{self._lowered()}); "
                    "use a smaller time_step, leave it out to get "
                    f"{self.safety_factor} x the limit, or set allow_unstable: true"
                )
            self.dt = float(self.time_step)
        self._inv_mass = self._inverse_mass()
        # further dof groups (micropolar rotations): value, rate, force, body, 1/inertia
        self._extra = [
            (g, np.ascontiguousarray((1.0 / self.model.inertia(k))[:, None]))
            for k, g in enumerate(self.model.force_model.dofs()[1:], start=1)
        ]
        self._blowup_limit = self.blowup_factor * self.model.cloud.size
        self._rigid = getattr(self.model, "rigid", None)
        if self._rigid is not None:
            self._rigid.time_step = self.dt  # the friction law stops a slip in one step
        self._friction = bool(getattr(self.model, "has_friction", False))
        if self._friction:
            self.model.time_step = self.dt
        self.last_good: State | None = None
        self._committed_step = -1  # the step whose positions the damage law last saw
        if self.steps is not None and self.end_time is not None:
            raise ValueError("give at most one of steps and end_time")
        self.n_steps: int | None = (
            self.steps if self.end_time is None else self.steps_for(self.end_time)
        )
        warn_implausible(self)

    def _lowered(self) -> str:
        """``", lowered by KEY ..."`` when damping or viscosity lowers the stable step."""
        key = self.stable_step.limited_by()
        if key is None:
            return ""
        return (
            f", lowered from {self.stable_step.elastic:.6g} s by {key}: damping ratio "
            f"{self.stable_step.xi:.3g} of the fastest mode"
        )

    def _inverse_mass(self) -> np.ndarray:
        """1 / rho of each point (kg/m^3)^-1, shape (n, 1) (every component of a point
        has the same mass, read once per point); (n, dim) with 0 on the components a
        velocity condition prescribes, so that neither the forces nor the damping move
        them: u advances by dt v_prescribed exactly, whatever the damping."""
        inv = (1.0 / self.model.density)[:, None]
        held = [c for c in self.constraints if isinstance(c, PrescribedVelocity)]
        if not held:
            return np.ascontiguousarray(inv)
        d = self.model.dim
        full = np.repeat(inv, d, axis=1)
        for c in held:
            for name in c.values:
                comp = COMPONENTS.get(name, d)
                if comp < d:
                    full[c.nodes, comp] = 0.0
        return np.ascontiguousarray(full)

    # -- life cycle --------------------------------------------------------------
    def init(self) -> State:
        """State at t = 0: initial velocities, constraints, forces."""
        m = self.model
        s = m.new_state()
        for iv in self.initial_velocities:
            iv.apply_initial(s.v)
        self._apply_constraints(s, 0.0)
        self._fix_rotations(s)
        m.evaluate(s, commit=True)
        m.external_force(0.0, s.body)
        if self.integrator == "central_difference":
            # u(-dt) from a Taylor step so that u(dt) = u0 + dt v0 + dt^2/2 a0
            a0 = (s.force + s.body) * self._inv_mass
            s.u_prev[:] = s.u - self.dt * s.v + 0.5 * self.dt**2 * a0
        self.last_good = s.copy()
        self.warm_up(m.dim)
        return s

    def resume(self, state: State) -> None:
        """Continue from a State read from a checkpoint."""
        self.model.on_restore(state)
        self.last_good = state.copy()
        self.warm_up(self.model.dim)

    def done(self, state: State) -> bool:
        """True after the run's steps (never without a run length)."""
        return self.n_steps is not None and state.step >= self.n_steps

    def total_steps(self) -> int:
        """Steps of the whole run (0 without a run length)."""
        return self.n_steps or 0

    def describe(self) -> str:
        """dt, stable limit (and the key that lowered it) and number of steps."""
        key = self.stable_step.limited_by()
        by = f", lowered by {key}" if key is not None else ""
        return (
            f"dt = {self.dt:.4g} s (stable limit {self.stable_time_step:.4g} s{by}), "
            f"{self.total_steps()} steps"
        )

    def summary_fields(self, state: State) -> dict[str, Any]:
        """Time step and stable limit (s)."""
        return {"time_step_s": self.dt, "stable_time_step_s": self.stable_time_step}

    def warm_up(self, d: int) -> None:
        """Compile (or load from cache) the step kernels on tiny arrays of the same types,
        so that timings of the run measure stepping, not JIT compilation."""
        u, v, f, b = (np.zeros((1, d)) for _ in range(4))
        inv = np.ones((1, 1))  # the same array layout as in the run
        if self.integrator == "velocity_verlet":
            integrators.kick_drift(u, v, f, b, inv, 0.0)
            integrators.kick(v, f, b, inv, 0.0)
        else:
            integrators.central_difference(u, np.zeros((1, d)), v, f, b, inv, 1.0)
            integrators.end_of_step_velocity(u, np.zeros((1, d)), v, f, b, inv, 1.0)
        bond_based.first_bad_point(u, v, np.zeros(d), 1.0)

    def _fix_rotations(self, s: State) -> None:
        """theta = omega = 0 where a fixed condition clamps the rotation (micropolar)."""
        if self._extra:
            for c in self.constraints:
                if isinstance(c, Fixed):
                    c.apply_rotation(s["theta"], s["omega"])

    def _apply_constraints(self, s: State, t: float) -> None:
        for c in self.constraints:
            if isinstance(c, PrescribedVelocity) and t == 0.0:
                c.set_velocity(s.v, 0.0)
            elif not isinstance(c, PrescribedVelocity):
                c.apply(s.u, s.v, t, self.dt)

    def step(self, s: State) -> StepResult:
        """Advance one step in place.

        Both integrators leave ``v`` at the new time t + dt: velocity Verlet by its second
        half kick, central difference by v = (u+ - u)/dt + dt/2 a+ (the same value, so
        kinetic energy and velocity probes agree between the two). Damage is committed
        at every step (the evaluation at the new positions).
        """
        m, dt, inv = self.model, self.dt, self._inv_mass
        t_new = (s.step + 1) * dt
        if self.integrator == "velocity_verlet":
            integrators.kick_drift(s.u, s.v, s.force, s.body, inv, dt)
        else:  # v holds the mid-step velocity (u+ - u)/dt after this call
            integrators.central_difference(s.u, s.u_prev, s.v, s.force, s.body, inv, dt)
        for g, inv_g in self._extra:  # rotations: velocity Verlet for either integrator
            integrators.kick_drift(s[g.value], s[g.rate], s[g.force], s[g.body], inv_g, dt)
        rigid = self._rigid
        if rigid is not None:  # rigid bodies: velocity Verlet on their momenta
            rigid.half_kick(s, dt)
            rigid.drift(s, s.t, dt)
        for c in self.constraints:  # positions at t + dt
            c.apply(s.u, s.v, t_new, dt)
        self._fix_rotations(s)
        broken = m.evaluate(s, commit=True)
        m.external_force(t_new, s.body)
        if self.integrator == "velocity_verlet":
            integrators.kick(s.v, s.force, s.body, inv, dt)
        else:
            integrators.end_of_step_velocity(s.u, s.u_prev, s.v, s.force, s.body, inv, dt)
        for g, inv_g in self._extra:
            integrators.kick(s[g.rate], s[g.force], s[g.body], inv_g, dt)
        if rigid is not None:
            rigid.half_kick(s, dt)
        if self._friction:
            m.add_friction_work(s, dt)
        self._fix_rotations(s)
        for c in self.constraints:  # velocities at t + dt
            if isinstance(c, PrescribedVelocity):
                c.set_velocity(s.v, t_new)
            else:
                c.apply(s.u, s.v, t_new, dt)
        s.step += 1
        s.t = t_new
        self._committed_step = s.step
        if s.step % self.check_every == 0:
            self.check(s)
        return StepResult(broken=broken)

    def check(self, s: State) -> None:
        """Stop with :class:`SimulationUnstable` if the solution blew up; else remember
        the state as the last good one.

        Blown up means: a non-finite displacement or velocity; an intact bond stretched
        by more than ``max_stretch`` (100 % by default: bonds of real materials break at
        well under 1 %); or a displacement, less the mean (rigid translation) displacement,
        larger than ``blowup_factor`` times the model size.
        """
        limit = self._blowup_limit
        comm = self.model.comm
        own = comm.owned  # ghost rows are other ranks' points
        total = np.zeros(s.u.shape[1])
        integrators.column_sums(s.u[own], total)
        shift = comm.sum_array(total) / comm.sum(float(len(s.u[own])))
        k = int(bond_based.first_bad_point(s.u[own], s.v[own], shift, limit))
        if s.step == self._committed_step:  # damage committed at these positions
            self.model.max_stretch_after_commit(s, self.max_stretch)
        else:
            self.model.force_model.update_max_stretch(s, self.max_stretch)
        stretch = s.max_stretch[own]
        smax = comm.max(float(stretch.max()) if stretch.size else 0.0)
        if k < 0 and smax > self.max_stretch and stretch.size:
            k = int(np.argmax(stretch)) if stretch.max() > self.max_stretch else -1
        if comm.size > 1 and comm.any(k >= 0) and k < 0:
            raise SimulationUnstable(
                f"the run went unstable at step {s.step}, t = {s.t:.6g} s on another MPI "
                "rank (its message says where)",
                s.step,
                s.t,
                -1,
                [],
                self.last_good,
            )
        if k >= 0:
            nonfinite = ~(np.isfinite(s.u).all(axis=1) & np.isfinite(s.v).all(axis=1))
            if nonfinite.any():  # report a point that is really non-finite
                k = int(np.argmax(nonfinite))
            coords = self.model.cloud.x[k].tolist()
            mag = float(np.abs(s.u[k] - shift).max())
            if nonfinite.any():
                what = "a non-finite displacement or velocity"
            elif mag > limit:
                what = (
                    f"|u - mean(u)| = {mag:.3g} m (limit {limit:.3g} m = "
                    f"{self.blowup_factor} x model size)"
                )
            else:
                what = (
                    f"an intact bond stretched by {s.max_stretch[k]:.3g} (limit "
                    f"{self.max_stretch:.3g})"
                )
            raise SimulationUnstable(
                f"the run went unstable at step {s.step}, t = {s.t:.6g} s: point {k} at "
                f"{coords} has {what}. {unstable_advice(self)}"
                + (
                    "; the quadratic viscosity is not in that limit (it grows with the "
                    "strain rate): lower material.viscosity.quadratic."
                    if getattr(getattr(self.model, "viscosity", None), "quadratic", 0) > 0
                    else "."
                ),
                step=s.step,
                time=s.t,
                point=k,
                coordinates=coords,
                last_good=self.last_good,
            )
        self.last_good = s.snapshot(self.last_good)

    def irun(self, s: State, n_steps: int) -> Iterator[State]:
        """Yield the state after each of ``n_steps`` steps."""
        for _ in range(n_steps):
            self.step(s)
            yield s

    def run(self, s: State, n_steps: int) -> State:
        """Advance ``n_steps`` steps, check the final state, and return it."""
        for _ in self.irun(s, n_steps):
            pass
        if s.step % self.check_every:
            self.check(s)
        return s

    def steps_for(self, end_time: float) -> int:
        """Number of steps to reach ``end_time`` (s): the smallest n with n dt >= end_time."""
        return int(np.ceil(end_time / self.dt - 1e-9))
