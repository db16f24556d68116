"""Adaptive dynamic relaxation (ADR) to static equilibrium, after Kilic & Madenci (2010).

Kilic & Madenci (2010), "An adaptive dynamic relaxation method for quasi-static
simulations using the peridynamic theory", Theor. Appl. Fract. Mech. 53:194-204,
section 3; the same equations are printed in PD zero-energy modes (n.d.), eqs 14-15.
(The equation numbers of Kilic & Madenci's paper could not be checked here, so the
equations are named below by what they are and numbered (ADR-1)...(ADR-6).)

The static problem ``f_int(U) + b = 0`` (force densities, N/m^3) is solved as the
steady state of a fictitious damped motion with a fictitious time step dt = 1::

  (ADR-1) pseudo-dynamics   Lambda U'' + c^n Lambda U' = F^n = f_int(U^n) + b,
  (ADR-2) fictitious density  lambda_ii >= 1/4 dt^2 sum_j |K_ij|,
  (ADR-3) damping           c^n = 2 sqrt( (U^n^T 1K^n U^n) / (U^n^T U^n) ),
  (ADR-4) local stiffness   1K^n_ii = -(F_i^n - F_i^{n-1}) / (lambda_ii dt U'_i^{n-1/2}),
  (ADR-5) velocity, displacement  U'^{n+1/2} = ((2 - c^n dt) U'^{n-1/2} + 2 dt F^n / lambda)
                                         / (2 + c^n dt),
                            U^{n+1} = U^n + dt U'^{n+1/2},
  (ADR-6) first step        U'^{1/2} = dt F^0 / (2 lambda).

Here ``K_ij = -dF_i/dU_j`` is the stiffness of the force density and U' the fictitious
velocity (kept by the solver, never in ``state.v``, so that mass damping and viscous
bond forces of the model, which read ``state.v``, stay zero in a static solve).

Fictitious density (ADR-2). It is built from the force model's per-point stiffness
bound K_i (:meth:`peridynamics.families.base.ForceModel.stiffness_bound`, the same bound
that gives the explicit step dt_i = sqrt(2 rho / K_i)) as

    lambda_i = density_factor / 4 * dt^2 * K_i     (density_factor = 4 by default).

For PMB, K_i = sum_k g_k / |xi_k| and the row sum of the stiffness at u = 0 of component a
is sum_j |K_ij| <= sum_k (g_k/|xi_k|) 2 |e_a| sum_b |e_b| <= (1 + sqrt(d)) K_i for unit
bond directions e (the maximum of |e_a| ||e||_1 over unit vectors is (1 + sqrt d)/2).
By Gershgorin every eigenvalue omega^2 of Lambda^-1 K is <= 4 (1 + sqrt d) /
(density_factor dt^2), so the central-difference update (ADR-5) is stable (omega dt < 2)
for density_factor > 1 + sqrt(d): 2, 2.41, 2.73 in 1-, 2-, 3-D. For any other family
the contract of ``stiffness_bound`` (dt = sqrt(2 rho/K) stable, i.e. omega^2 <= 2 K/rho)
needs density_factor > 2. The default 4 clears both (margin 1.46 in 3-D PMB, 2 on the
contract) at a cost of sqrt(4 / 2.73) = 1.2 in iterations against the tightest choice;
Madenci & Oterkus use 5 with the same K_i. The bound is that of the undamaged model:
broken bonds and SED softening only lower the stiffness. Contact forces are not in it.

Damping (ADR-3, ADR-4): the Rayleigh quotient of the local diagonal stiffness over the
free dofs; dofs whose U'^{n-1/2} is 0 contribute 0; c = 0 when U^T U = 0 or the quotient
is negative, and c dt is clamped to 1.9 (< 2, where (2 - c dt) would change sign), as
in Madenci & Oterkus' code.

Convergence: the equilibrium residual over the free dofs, relative to the load,

    ||V (f_int + b)||_free <= tolerance * max(||V b||_free, ||R||_fixed, P_max, tiny),

with V the point volumes and R = -V (f_int + b) the reaction forces (N) at the
constrained dofs: relative to the applied load whether it is a force or a prescribed
displacement. P_max is the largest load norm max(||V b||, ||R||) of the earlier load
steps: once a body has failed and carries (almost) no load, its residual is measured
against the load it carried, not against the round-off left in the broken body (which
would never converge). ``tiny`` is the smallest positive float: an unloaded body is
converged at u = 0 at once.

Load stepping: load step k = 1..N is the pseudo-time t_k = k/N * ``load_time``. Body
forces are ``model.external_force(t_k)`` and prescribed displacements their value at
t_k (time functions evaluated at t_k); with ``proportional=True`` (default) both are
multiplied by lambda_k = k/N as well, so that constant loads ramp up in N equal steps
(with time functions that already ramp, use ``proportional=False``). One ``step()`` is
one whole load step: ADR to equilibrium, then the damage law's trial and commit at the
converged displacement (:meth:`peridynamics.evaluation.evaluator.Evaluator.commit_damage`); when
bonds
broke, ADR re-converges at the same load and damage is committed again, up to
``max_damage_rounds`` times. Each equilibrium solve restarts ADR from U' = 0 (ADR-6) at
the current displacement; with ``extrapolate=True`` the free dofs of a new load step
start from the linear extrapolation 2 u_{k-1} - u_{k-2} (``state.u_prev`` holds
u_{k-2} between steps; exact for a linear elastic response).

Non-convergence is not an exception: a solve that reaches ``max_iterations`` (per
equilibrium solve) ends the load step with ``StepResult(converged=False)``, the event
``"not_converged"`` and no damage committed in that step; the summary lists the load
steps and says so in ``message``. With ``stop_on_failure=True`` the run then ends
(:meth:`ADRSolver.done`). A non-finite solution raises
:class:`~peridynamics.solvers.explicit.SimulationUnstable` from :meth:`ADRSolver.check`.

One equilibrium solve (ADR-2...ADR-6 and the convergence test) is
:class:`peridynamics.solvers.adr_relaxation.Relaxation`; its Numba loops are
:mod:`peridynamics.kernels.adr`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.evaluation import Evaluator
from peridynamics.loading.conditions import Kinematic, PrescribedVelocity
from peridynamics.solvers.adr_relaxation import Relaxation, fictitious_density, flat
from peridynamics.solvers.base import StepResult
from peridynamics.solvers.explicit import SimulationUnstable
from peridynamics.state import State

#: fictitious time step of ADR (s); Kilic & Madenci (2010) take dt = 1
FICTITIOUS_TIME_STEP = 1.0


class ADRSolver:
    """Quasi-static solver: adaptive dynamic relaxation with load stepping and damage.

    See the module docstring for the equations (Kilic & Madenci 2010) and the choices.

    Parameters
    ----------
    model : Evaluator
    constraints : sequence of PrescribedDisplacement or Fixed
        Kinematic conditions; their dofs are held at the prescribed value (scaled by
        k/N when ``proportional``) with zero fictitious velocity. Prescribed velocities
        have no meaning in a static run and are refused.
    load_steps : int
        N >= 1 load steps; one :meth:`step` is one load step.
    tolerance : float
        Relative residual of equilibrium, in (0, 1).
    max_iterations : int
        ADR iterations allowed per equilibrium solve (the load step's first solve and
        each re-solve after bonds broke).
    proportional : bool
        Multiply body forces and prescribed displacements by k/N at load step k.
    max_damage_rounds : int
        Damage commits per load step (>= 1), each followed by a re-solve when bonds
        broke; when bonds would still break after the last re-solve the step ends with
        the event ``"damage_unsettled"`` (the proposal is left uncommitted).
    load_time : float
        Pseudo-time of the last load step: time functions are evaluated at
        t_k = k/N * load_time (s of the time functions' clock).
    density_factor : float
        lambda_i = density_factor / 4 * dt^2 * K_i (module docstring); > 2.
    extrapolate : bool
        Start each load step from 2 u_{k-1} - u_{k-2} (free dofs).
    stop_on_failure : bool
        End the run after a load step that did not converge.

    Attributes
    ----------
    lam : (n dim,) fictitious density lambda_ii per dof (kg/m^3 for dt = 1 s).
    free : (n dim,) uint8 free-dof mask.
    last_good : State or None
        The state after the last checked load step.
    """

    def __init__(
        self,
        model: Evaluator,
        constraints: Sequence[Kinematic] = (),
        load_steps: int = 1,
        tolerance: float = 1e-8,
        max_iterations: int = 200_000,
        proportional: bool = True,
        max_damage_rounds: int = 50,
        load_time: float = 1.0,
        density_factor: float = 4.0,
        extrapolate: bool = True,
        stop_on_failure: bool = False,
    ) -> None:
        if int(load_steps) != load_steps or load_steps < 1:
            raise ValueError(f"load_steps must be an integer >= 1, got {load_steps}")
        if not 0.0 < tolerance < 1.0:
            raise ValueError(f"tolerance must be in (0, 1), got {tolerance}")
        if int(max_iterations) != max_iterations or max_iterations < 1:
            raise ValueError(f"max_iterations must be an integer >= 1, got {max_iterations}")
        if int(max_damage_rounds) != max_damage_rounds or max_damage_rounds < 1:
            raise ValueError(f"max_damage_rounds must be an integer >= 1, got {max_damage_rounds}")
        if not (load_time > 0 and math.isfinite(load_time)):
            raise ValueError(f"load_time must be a finite value > 0, got {load_time}")
        if not (density_factor > 2.0 and math.isfinite(density_factor)):
            raise ValueError(
                f"density_factor must be a finite value > 2 (stability), got {density_factor}"
            )
        for c in constraints:
            if isinstance(c, PrescribedVelocity):
                raise ValueError(
                    "a prescribed velocity has no meaning in a static (adr) run; prescribe "
                    "the displacement instead"
                )
        if len(model.force_model.dofs()) > 1:
            raise ValueError(
                f"adaptive dynamic relaxation integrates displacements only; the "
                f"{model.force_model.name!r} model has rotations: use solver.type static "
                "(or explicit)"
            )
        self.model = model
        self.constraints = tuple(constraints)
        self.load_steps = int(load_steps)
        self.tolerance = float(tolerance)
        self.max_iterations = int(max_iterations)
        self.proportional = bool(proportional)
        self.max_damage_rounds = int(max_damage_rounds)
        self.load_time = float(load_time)
        self.density_factor = float(density_factor)
        self.extrapolate = bool(extrapolate)
        self.stop_on_failure = bool(stop_on_failure)
        self.dt = FICTITIOUS_TIME_STEP
        self.last_good: State | None = None

        n, d = model.n_points, model.dim
        self.lam = fictitious_density(model, self.density_factor, self.dt)
        # constrained dofs: those any condition writes (probed on a NaN array)
        probe = np.full((n, d), np.nan)
        self._apply(probe, self.load_time)
        self.free = np.isnan(probe).reshape(-1).astype(np.uint8)
        self._relaxation = Relaxation(
            model, self.lam, self.free, self.dt, self.tolerance, self.max_iterations
        )

    # -- loads ---------------------------------------------------------------------
    def _apply(self, u: NDArray[np.float64], t: float) -> None:
        """Write every constraint's displacement at pseudo-time t into ``u``."""
        scratch = np.zeros_like(u)
        dt = self.load_time / self.load_steps
        for c in self.constraints:
            c.apply(u, scratch, t, dt)

    def load_factor(self, k: int) -> float:
        """lambda_k = k/N with ``proportional``, else 1."""
        return k / self.load_steps if self.proportional else 1.0

    def pseudo_time(self, k: int) -> float:
        """t_k = k/N * load_time."""
        return k / self.load_steps * self.load_time

    def _set_loads(self, s: State, k: int) -> None:
        """Body force and constrained-dof targets of load step k."""
        t, lam = self.pseudo_time(k), self.load_factor(k)
        self.model.external_force(t, s.body)
        if lam != 1.0:
            np.multiply(s.body, lam, out=s.body)
        target = np.zeros_like(s.u)
        self._apply(target, t)
        np.multiply(target.reshape(-1), lam, out=self._relaxation.target)

    # -- life cycle ----------------------------------------------------------------
    def init(self) -> State:
        """State at load step 0: u = 0 (constrained dofs at their step-0 value), the
        internal force evaluated, per-load-step histories allocated."""
        s = self.model.new_state()
        self._add_history(s)
        self._set_loads(s, 0)
        fixed = self.free == 0
        flat(s.u)[fixed] = self._relaxation.target[fixed]
        s.u_prev[...] = s.u
        self.model.evaluate(s, commit=False)
        self._relaxation.warm_up()
        self.last_good = s.copy()
        return s

    def _add_history(self, s: State) -> None:
        n = self.load_steps
        s["adr_iterations"] = np.zeros(n, dtype=np.int64)
        s["adr_residual"] = np.full(n, np.nan)
        s["adr_converged"] = np.zeros(n, dtype=np.uint8)
        s["adr_load_norm"] = np.zeros(n)

    def resume(self, state: State) -> None:
        """Continue from a State read from a checkpoint (load steps restart ADR from
        U' = 0, so nothing else is needed to continue bit for bit)."""
        for name in ("adr_iterations", "adr_residual", "adr_converged", "adr_load_norm"):
            if name not in state or state[name].shape != (self.load_steps,):
                raise ValueError(
                    f"the checkpoint has no ADR history for {self.load_steps} load steps"
                )
        self.model.on_restore(state)
        self._relaxation.warm_up()
        self.last_good = state.copy()

    def done(self, state: State) -> bool:
        """All load steps taken (or, with ``stop_on_failure``, one did not converge)."""
        if state.step >= self.load_steps:
            return True
        if self.stop_on_failure and state.step > 0:
            return not bool(state["adr_converged"][: state.step].all())
        return False

    def total_steps(self) -> int:
        """N, the number of load steps."""
        return self.load_steps

    def relax(self, s: State, floor: float = 0.0) -> tuple[int, float, bool]:
        """ADR from U' = 0 at ``s.u`` to equilibrium under the current loads
        (:meth:`peridynamics.solvers.adr_relaxation.Relaxation.relax`)."""
        return self._relaxation.relax(s, floor)

    def step(self, s: State) -> StepResult:
        """Take load step k = ``s.step + 1``: equilibrium by ADR, then damage rounds.

        ``s.step`` becomes k, ``s.t`` the pseudo-time t_k; ``s.u_prev`` keeps the
        displacement of load step k - 1; ``s.v`` stays 0 (static solution).
        """
        k = s.step + 1
        if k > self.load_steps:
            raise ValueError(f"all {self.load_steps} load steps are done")
        self._set_loads(s, k)
        u = flat(s.u)
        if self.extrapolate and k > 1:
            guess = 2.0 * u - flat(s.u_prev)
            s.u_prev[...] = s.u
            np.copyto(u, guess, where=self.free == 1)
        else:
            s.u_prev[...] = s.u
        hist = s["adr_load_norm"]
        floor = float(hist[: k - 1].max()) if k > 1 else 0.0
        iterations, residual, converged = self.relax(s, floor)
        floor = max(
            floor, self._relaxation.load_norm
        )  # re-solves after damage: against this load too
        broken = 0
        events: list[str] = []
        if converged:
            settled = False
            for _ in range(self.max_damage_rounds):
                nb = self.model.commit_damage(s)
                broken += nb
                if self.model.comm.sum(float(nb)) == 0:
                    settled = True
                    break
                iters, residual, converged = self.relax(s, floor)
                iterations += iters
                if not converged:
                    break
            more = self.model.damage_law.trial(s) > 0
            if converged and not settled and self.model.comm.any(more):
                events.append("damage_unsettled")  # more bonds would break at this load
        if not converged:
            events.append("not_converged")
        s.v[...] = 0.0
        s.step = k
        s.t = self.pseudo_time(k)
        s["adr_iterations"][k - 1] = iterations
        s["adr_residual"][k - 1] = residual
        s["adr_converged"][k - 1] = converged
        hist[k - 1] = max(floor, self._relaxation.load_norm)
        self.check(s)
        return StepResult(
            accepted=True,
            converged=converged,
            residual=residual,
            broken=broken,
            iterations=iterations,
            events=tuple(events),
        )

    # -- checks and summary -------------------------------------------------------
    def check(self, s: State) -> None:
        """Raise :class:`SimulationUnstable` when the displacement or force is not finite
        (the fictitious density was too small, e.g. with stiff contact); else keep the
        state as the last good one."""
        own = self.model.comm.owned
        bad = ~(np.isfinite(s.u[own]).all(axis=1) & np.isfinite(s.force[own]).all(axis=1))
        if self.model.comm.any(bool(bad.any())):
            k = int(np.argmax(bad))
            coords = self.model.cloud.x[k].tolist()
            raise SimulationUnstable(
                f"adaptive dynamic relaxation diverged in load step {s.step} "
                f"(pseudo-time {s.t:.6g}): point {k} at {coords} has a non-finite "
                "displacement or force. Check the loads, the contact stiffness and the "
                "boundary conditions (a body free to move as a rigid body); in the Python "
                f"API a larger ADRSolver(density_factor=...) (now {self.density_factor}) "
                "damps harder.",
                step=s.step,
                time=s.t,
                point=k,
                coordinates=coords,
                last_good=self.last_good,
            )
        self.last_good = s.snapshot(self.last_good)

    def describe(self) -> str:
        """Load steps and tolerance."""
        return (
            f"adaptive dynamic relaxation, {self.load_steps} load step"
            f"{'s' if self.load_steps != 1 else ''}, tolerance {self.tolerance:.3g}"
        )

    def summary_fields(self, state: State) -> dict[str, Any]:
        """Solver entries of ``summary.json``.

        Keys: ``solver`` ("adr"), ``load_steps`` (N), ``load_steps_done``,
        ``iterations`` (total ADR iterations), ``iterations_per_load_step`` (list),
        ``residual`` (final relative residual of the last load step done),
        ``max_residual`` (largest final relative residual over the load steps),
        ``converged`` (every load step done converged), ``not_converged_load_steps``
        (list of k), ``tolerance``, ``message``, ``time_step_s`` (None: no physical
        time step) and ``fictitious_time_step`` (1.0).
        """
        done = min(state.step, self.load_steps)
        its = [int(i) for i in state["adr_iterations"][:done]]
        res = state["adr_residual"][:done]
        conv = state["adr_converged"][:done].astype(bool)
        failed = [int(k) + 1 for k in np.flatnonzero(~conv)]
        if failed:
            message = (
                f"ADR did not reach the tolerance {self.tolerance:g} within "
                f"{self.max_iterations} iterations in load step(s) {failed[:10]}"
                + (" ..." if len(failed) > 10 else "")
                + "; raise max_iterations, use more load steps or a looser tolerance"
            )
        elif done < self.load_steps:
            message = f"{done} of {self.load_steps} load steps done"
        else:
            message = f"all {self.load_steps} load steps converged"
        return {
            "solver": "adr",
            "load_steps": self.load_steps,
            "load_steps_done": done,
            "iterations": int(sum(its)),
            "iterations_per_load_step": its,
            "residual": float(res[-1]) if done else None,
            "max_residual": float(np.nanmax(res)) if done and np.isfinite(res).any() else None,
            "converged": bool(conv.all()) if done else False,
            "not_converged_load_steps": failed,
            "tolerance": self.tolerance,
            "message": message,
            "time_step_s": None,
            "fictitious_time_step": self.dt,
        }
