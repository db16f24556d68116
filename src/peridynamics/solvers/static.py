"""Implicit static solver: Newton iterations on the unbalanced force, load stepping
with cut-back, and bond breaking between solves (sequentially linear for linear
models).

Equations (Zhou, Zhu & Li (n.d.), eqs 13-20). The total potential energy
``E(q) = sum_i W_i V_i - sum_i b_i . q_i V_i`` of the degrees of freedom q (the
displacement, and the rotation of a micropolar model) is stationary at equilibrium:
the unbalanced force ``P = V (f_int(q) + b)`` vanishes at the free dofs. Newton's method
solves ``K dq = P`` with the tangent ``K = d^2 E / dq^2`` of the force model
(:meth:`peridynamics.families.base.ForceModel.tangent`; the coloured finite-difference
tangent for a model without one), assembled bond-wise with no Python loop over bonds
(:mod:`peridynamics.families.assembly`). Prescribed displacements are imposed by
elimination: their dofs take the prescribed value and leave the system, whose free
block is solved by a direct or an iterative solver (:mod:`peridynamics.solvers.linear`,
chosen by size unless ``linear_solver`` says otherwise).

Load stepping: load level lambda in (0, 1]; body forces and prescribed displacements
are their value at the pseudo-time ``t = lambda * load_time``, times lambda when
``proportional`` (load control: forces; displacement control: prescribed
displacements). The levels are k / N (``load_steps`` = N). A level whose Newton
iterations do not converge within ``max_iterations`` is cut back (the increment
halved, up to ``max_cutbacks`` times); a level that still fails ends the run
(``not_converged``).

Bond breaking between solves (:mod:`peridynamics.solvers.breaking`): after every
converged solve the intact bonds whose axial stretch reached the critical stretch are
found; scheme C breaks the N_b most stretched of them, and the next step solves again
at the same load. The load is raised only after a solve that breaks nothing. For a
linear model (micropolar) under proportional loading the solution scales with lambda,
so the next level is the smaller of the next k / N and the level lambda_c at which the
next bond reaches its critical stretch (``event_driven``): the load-displacement curve
then has every peak of its saw-tooth exactly.

Re-use after bonds break (``reuse_factorization``, linear models): the stiffness loses
the pair matrices of the broken bonds; the direct solver corrects the old
factorisation by the Woodbury identity and refactors only when the correction grows
past its memory budget; the iterative solver keeps the multigrid hierarchy of the old
matrix as preconditioner. Without re-use every event refactors. Points left without
any intact bond are pinned at their displacement (they carry no stiffness); a body
that falls apart (a singular system) ends the run with the event ``failed``.

One :meth:`StaticSolver.step` is one equilibrium solve (a new load level, or the same
level after bonds broke): histories record every solve, which is the
load-displacement curve with its events.

Path-dependent laws (``material.plasticity``): every evaluation reads the committed
history and proposes a trial one; the force model's history is committed
(:meth:`~peridynamics.families.base.ForceModel.commit_history`) on a converged solve
only, never inside the Newton iterations. A cut-back or a failed level therefore starts
again from the last commit, and the tangent (finite differences for correspondence, on a
copy of the state) perturbs the displacement about that committed history. A force
model with ``newton_line_search = True`` (the elastic-plastic LPS) has its Newton steps
backtracked (:mod:`peridynamics.solvers.static_line_search`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.damage.critical_stretch import CriticalStretchLaw
from peridynamics.evaluation import Evaluator
from peridynamics.loading.conditions import Kinematic
from peridynamics.loading.time_functions import Constant
from peridynamics.solvers import linear as lin
from peridynamics.solvers.base import StepResult
from peridynamics.solvers.blas_threads import blas_threads
from peridynamics.solvers.breaking import PairBreaker
from peridynamics.solvers.static_breaking import StaticBreaking
from peridynamics.solvers.static_checks import check_arguments, check_damage, check_finite
from peridynamics.solvers.static_dofs import StaticDofs, norm
from peridynamics.solvers.static_line_search import backtrack
from peridynamics.solvers.static_report import summary_fields
from peridynamics.solvers.tangent_system import TangentSystem
from peridynamics.state import State

#: OpenBLAS threads during a solve: its many small BLAS calls (SuperLU's triangular
#: solves, the Woodbury products) ran up to 6x faster with one thread than with two on
#: a shared 2-core machine, and leave Numba's force passes alone
BLAS_THREADS = 1


class StaticSolver(StaticDofs, StaticBreaking):
    """Newton static solver with load stepping and bond breaking (module docstring).

    Parameters
    ----------
    model : Evaluator
    constraints : sequence of PrescribedDisplacement or Fixed
        Eliminated dofs. A :class:`~peridynamics.loading.conditions.Fixed` without
        components (or with ``"rotation"``) also fixes a micropolar rotation.
    load_steps : int
        N >= 1: load levels k / N.
    tolerance : float
        Relative residual ||P_free|| / max(||V b_free||, ||reactions||, earlier peak).
    max_iterations : int
        Newton iterations per solve.
    max_cutbacks : int
        Halvings of a load increment that did not converge.
    proportional : bool
        Multiply loads and prescribed displacements by lambda.
    load_time : float
        Pseudo-time of lambda = 1 (s of the time functions' clock).
    linear_solver : {"auto", "direct", "iterative"}
    breaking : {"A", "B", "C"}
        Bond-breaking scheme (:mod:`peridynamics.solvers.breaking`).
    bonds_per_event : int
        N_b of scheme C.
    event_driven : bool
        Raise the load to the next breaking event (linear models, proportional loads).
    reuse_factorization : bool
        Keep the factorisation (or preconditioner) across bond-breaking events.
    max_solves : int
        Safety limit on the number of solves (steps).
    """

    def __init__(
        self,
        model: Evaluator,
        constraints: Sequence[Kinematic] = (),
        load_steps: int = 10,
        tolerance: float = 1e-8,
        max_iterations: int = 20,
        max_cutbacks: int = 6,
        proportional: bool = True,
        load_time: float = 1.0,
        linear_solver: str = "auto",
        breaking: str = "C",
        bonds_per_event: int = 4,
        event_driven: bool = True,
        reuse_factorization: bool = True,
        max_solves: int = 1_000_000,
    ) -> None:
        check_arguments(
            constraints, load_steps, tolerance, max_iterations, max_cutbacks, load_time,
            linear_solver, max_solves,
        )  # fmt: skip
        self.model = model
        self.constraints = tuple(constraints)
        self.load_steps = int(load_steps)
        self.tolerance = float(tolerance)
        self.max_iterations = int(max_iterations)
        self.max_cutbacks = int(max_cutbacks)
        self.proportional = bool(proportional)
        self.load_time = float(load_time)
        self.linear_solver = linear_solver
        self.event_driven = bool(event_driven)
        self.reuse = bool(reuse_factorization)
        self.max_solves = int(max_solves)
        self.last_good: State | None = None

        fm = model.force_model
        self.groups = fm.dofs()
        self.width = sum(g.components for g in self.groups)
        self.fixed = self._fixed_dofs()
        self._volume = np.repeat(np.asarray(model.cloud.volume, dtype=np.float64), self.width)
        law = model.damage_law
        check_damage(model)
        self.breaker: PairBreaker | None = None
        if isinstance(law, CriticalStretchLaw) and law.active:
            self.breaker = PairBreaker(model.bonds, law.point_s0, breaking, bonds_per_event)
        self.scheme = breaking
        self.linear_model = bool(getattr(fm, "linear", False))
        self.line_search = bool(getattr(fm, "newton_line_search", False))
        functions = [getattr(c, "function", Constant()) for c in self.constraints]
        functions += [getattr(b, "function", Constant()) for b in model.body_forces]
        self.scalable = (
            self.linear_model
            and self.proportional
            and all(isinstance(f, Constant) for f in functions)
            and model.contact is None
        )
        # solver state (rebuilt on resume)
        self.lam = 0.0
        self._pending = False
        self._failed: str | None = None
        self._peak_ref = 0.0
        self._ratio: NDArray[np.float64] | None = None  # l / l_c of the candidates
        self._picked: NDArray[np.int64] | None = None  # the pairs to break next
        self._first_break: tuple[list[float], float] | None = None
        self.stats: dict[str, float] = {
            "solves": 0,
            "newton_iterations": 0,
            "cutbacks": 0,
            "factorizations": 0,
            "factorization_s": 0.0,
            "events": 0,
            "event_s": 0.0,
            "update_column_solves": 0,
            "linear_solve_s": 0.0,
            "pinned_points": 0,
            "line_search_halvings": 0,
        }
        self.system = TangentSystem(
            model, self.width, self.fixed, linear_solver, self.tolerance, self.reuse, self.stats
        )

    # -- life cycle -------------------------------------------------------------------------
    def init(self) -> State:
        """State at lambda = 0 (u = 0), with the load level stored in the State."""
        s = self.model.new_state()
        s["static_load_factor"] = np.zeros(1)
        self.model.evaluate(s, commit=False)
        self.last_good = s.copy()
        return s

    def resume(self, state: State) -> None:
        """Continue from a State read from a checkpoint: the load level is read back,
        the factorisation rebuilt from the bond status, pending breaks re-detected."""
        if "static_load_factor" not in state:
            raise ValueError("the checkpoint has no static load level (not a static run)")
        self.model.on_restore(state)
        self.lam = float(state["static_load_factor"][0])
        self.system.invalidate()
        self._set_loads(state, self.lam)
        self.model.evaluate(state, commit=False)
        self._pending = self._violations(state)
        self.last_good = state.copy()

    def done(self, state: State) -> bool:
        """Final load reached with nothing left to break, a failure, or max_solves."""
        if self._failed is not None or state.step >= self.max_solves:
            return True
        return self.lam >= 1.0 - 1e-12 and not self._pending

    def total_steps(self) -> int:
        """N (a lower bound: events add solves)."""
        return self.load_steps

    # -- one solve ---------------------------------------------------------------------------
    def _equilibrium(self, s: State, lam: float) -> tuple[bool, int, float]:
        """Newton iterations at level lam from the current state."""
        target = self._set_loads(s, lam)
        q = self._gather(s).reshape(-1)
        q[self.fixed] = target[self.fixed]
        self._scatter(q.reshape(-1, self.width), s)
        self.model.evaluate(s, commit=False)
        body = np.concatenate([s[g.body] for g in self.groups], axis=1).reshape(-1)
        load = self._norm(self._volume * body, ~self.fixed)
        it = 0
        while True:
            p = self._unbalanced(s)
            free = self.system.free if len(self.system.free) else np.flatnonzero(~self.fixed)
            ref = max(load, self._norm(p, self.fixed), self._peak_ref, 1e-300)
            residual = self._norm(p, free) / ref
            if not math.isfinite(residual):
                return False, it, float("nan")
            if residual <= self.tolerance:
                self._peak_ref = max(self._peak_ref, ref)
                return True, it, residual
            if it >= self.max_iterations:
                return False, it, residual
            try:
                dq = self.system.solve(s, p, 0.1 * self.tolerance * ref)
            except lin.SingularSystem as exc:
                if it == 0 and self.lam == 0.0 and s.bonds_broken == 0:
                    raise lin.UnconstrainedModel(str(exc)) from exc  # a set-up error
                raise
            it += 1
            if self.line_search:  # the step halved until ||P|| falls (static_line_search)
                r0 = self._norm(p, self.system.free)
                self.stats["line_search_halvings"] += backtrack(self, s, dq, r0)
                continue
            q = self._gather(s).reshape(-1)
            q[self.system.free] += dq
            self._scatter(q.reshape(-1, self.width), s)
            self.model.evaluate(s, commit=False)

    def _norm(self, v: NDArray[np.float64], where: NDArray) -> float:
        """The norm of ``v[where]`` (``where``: a mask or indices of the flat dofs); a
        decomposed solver sums over every rank's owned dofs."""
        return norm(v[where])

    def step(self, s: State) -> StepResult:
        """One equilibrium solve: break bonds first when the last solve left violations
        (same load), else raise the load to the next level. Runs with
        :data:`BLAS_THREADS` OpenBLAS threads (:mod:`peridynamics.solvers.blas_threads`)."""
        with blas_threads(BLAS_THREADS):
            return self._step(s)

    def _step(self, s: State) -> StepResult:
        t0 = time.perf_counter()
        events: list[str] = []
        broken = 0
        if self._pending and self.breaker is not None:
            broken = self._break_pending(s, self.breaker)
            events.append("bonds_broken")
            target = self.lam
        else:
            target = self._next_level(s)
        saved = self._gather(s).copy()
        lam0 = self.lam
        cut = 0
        try:
            while True:
                if self.scalable and lam0 > 0 and not broken:  # the solution scales with lam
                    q = saved * (target / lam0)
                    self._scatter(q, s)
                converged, iterations, residual = self._equilibrium(s, target)
                self.stats["newton_iterations"] += iterations
                if converged or broken or cut >= self.max_cutbacks:
                    break
                cut += 1
                self.stats["cutbacks"] += 1
                events.append("cut_back")
                target = lam0 + 0.5 * (target - lam0)
                self._scatter(saved, s)
        except lin.UnconstrainedModel:  # a set-up error, not a failed level
            raise
        except lin.SingularSystem as exc:
            self._failed = str(exc)
            self._scatter(saved, s)
            self._set_loads(s, lam0)
            self.model.evaluate(s, commit=False)
            converged, iterations, residual = False, 0, float("nan")
            events.append("failed")
        self.stats["solves"] += 1
        if not converged and "failed" not in events:  # back to the last equilibrium
            self._scatter(saved, s)
            self._set_loads(s, lam0)
            self.model.evaluate(s, commit=False)
        if converged:
            self.lam = target
            # the accepted equilibrium's history becomes the committed one (never inside
            # Newton: a cut-back or a failed level restarts from the last commit)
            self.model.force_model.commit_history(s, fresh=True)
            self._pending = self._violations(s)
        elif self._failed is None:
            self._failed = (
                f"Newton did not converge at load level {target:.6g} after {cut} cut-backs "
                f"(residual {residual:.3g}); use more load_steps, more max_iterations or a "
                "looser tolerance"
            )
            events.append("not_converged")
        if broken:
            self.stats["event_s"] += time.perf_counter() - t0
        s["static_load_factor"][0] = self.lam
        s.step += 1
        s.t = self.lam * self.load_time
        s.v[...] = 0.0
        self.check(s)
        return StepResult(
            accepted=True,
            converged=converged,
            residual=residual,
            broken=broken,
            iterations=iterations,
            events=tuple(events),
        )

    # -- checks and summary -------------------------------------------------------------------
    def check(self, s: State) -> None:
        """Raise :class:`SimulationUnstable` on a non-finite solution; else keep the state
        as the last good one."""
        check_finite(self._gather(s), self.model.cloud.x, s, self.last_good)
        self.last_good = s.snapshot(self.last_good)

    def describe(self) -> str:
        """Load steps, scheme, linear solver."""
        return (
            f"static (Newton), {self.load_steps} load step"
            f"{'s' if self.load_steps != 1 else ''}, breaking scheme {self.scheme}, "
            f"linear solver {self.linear_solver}"
        )

    def summary_fields(self, state: State) -> dict[str, Any]:
        """Solver entries of ``summary.json``
        (:func:`peridynamics.solvers.static_report.summary_fields`)."""
        return summary_fields(self, state)
