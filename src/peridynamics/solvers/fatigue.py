"""Fatigue by cycle jumping: the remaining-life law of
:mod:`peridynamics.damage.fatigue` driven from one static equilibrium at the peak load to
the next.

Every bond loses A eps^m of its remaining life lambda per load cycle, eps = |1 - R| |s+|
its cyclic strain (Silling & Askari (2014), eqs 1-3). Under constant-amplitude cycling
between the peak load (the deck's loads and prescribed displacements at pseudo-time
1) and R times it, a linear-elastic body's bond strains are R times their peak values
at the valley, so one static solve at the peak gives every eps. A step of this solver:

1. at the peak equilibrium, the cycles each intact bond has left,
   n_b = lambda_b / (A eps_b^m), and their smallest n_min (a Numba pass over the
   bonds, :func:`peridynamics.kernels.fatigue.fatigue_rates`);
2. a jump of dN = min(n_min, ``max_increment``, cycles left to ``max_cycles``): every
   intact bond's life falls by dN A eps^m
   (:func:`peridynamics.kernels.fatigue.advance_life`), N += dN;
3. the bond that reached lambda = 0 breaks, and with it every bond whose n_b is within
   ``batch_tolerance`` of dN (their life is set to 0: they break up to that fraction of
   dN early);
4. a new static equilibrium at the peak load with these bonds gone (Newton, the tangent
   updated as in :mod:`peridynamics.solvers.static`).

A bond's phase (I or II) and so its A and m are decided at each equilibrium, from the
local damage of its end points. 10^6 cycles cost as many static solves as breaking
events, not 10^6 dynamic periods. The first steps load the body to the peak in
``load_steps`` levels (the static solver); the run ends at ``max_cycles``, when no intact
bond is loaded (the crack has cut the body under displacement control) or when the body
falls apart (a singular system under load control: final failure).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.damage.fatigue import RemainingLifeLaw
from peridynamics.evaluation import Evaluator
from peridynamics.loading.conditions import Kinematic
from peridynamics.solvers import linear as lin
from peridynamics.solvers.base import StepResult
from peridynamics.solvers.static import StaticSolver
from peridynamics.state import State

#: the State field of the cycle count N (one entry)
CYCLES = "fatigue_cycles"


class FatigueSolver(StaticSolver):
    """Cycle jumping between static equilibria at the peak load (module docstring).

    Parameters
    ----------
    model : Evaluator
        Its damage law must be the remaining-life law (``damage.model: fatigue``).
    constraints : sequence of Kinematic
        Fixed and prescribed displacements (at their peak value).
    load_ratio : float
        R = valley / peak of the load, in [-1, 1).
    max_cycles : float
        The run ends at this N (cycles, > 0).
    batch_tolerance : float
        Bonds whose cycles to failure are within this fraction of the jump break with
        the first one (>= 0).
    max_increment : float
        Largest jump dN (cycles; inf: only breaking events end a jump).
    load_steps, tolerance, max_iterations, max_cutbacks, linear_solver, max_solves
        As :class:`~peridynamics.solvers.static.StaticSolver` (the load steps to the
        peak; Newton at every equilibrium).
    """

    def __init__(
        self,
        model: Evaluator,
        constraints: Sequence[Kinematic] = (),
        load_ratio: float = 0.0,
        max_cycles: float = 1.0e6,
        batch_tolerance: float = 0.0,
        max_increment: float = math.inf,
        load_steps: int = 1,
        tolerance: float = 1e-8,
        max_iterations: int = 20,
        max_cutbacks: int = 6,
        linear_solver: str = "auto",
        max_solves: int = 1_000_000,
    ) -> None:
        law = model.damage_law
        if not isinstance(law, RemainingLifeLaw):
            raise ValueError(
                "[damage.model] solver.type fatigue needs the remaining-life law: set "
                "damage.model: fatigue with its damage.fatigue section"
            )
        if not (-1.0 <= load_ratio < 1.0):
            raise ValueError(f"[load_ratio] must be in [-1, 1), got {load_ratio}")
        if not (max_cycles > 0 and math.isfinite(max_cycles)):
            raise ValueError(f"[max_cycles] must be a finite value > 0, got {max_cycles}")
        if not (batch_tolerance >= 0 and math.isfinite(batch_tolerance)):
            raise ValueError(f"[batch_tolerance] must be >= 0, got {batch_tolerance}")
        if not max_increment > 0:
            raise ValueError(f"[max_increment] must be > 0 (cycles), got {max_increment}")
        super().__init__(
            model, constraints, load_steps=load_steps, tolerance=tolerance,
            max_iterations=max_iterations, max_cutbacks=max_cutbacks, proportional=True,
            linear_solver=linear_solver, event_driven=False, max_solves=max_solves,
        )  # fmt: skip
        self.law = law
        self.load_ratio = float(load_ratio)
        self.max_cycles = float(max_cycles)
        self.batch_tolerance = float(batch_tolerance)
        self.max_increment = float(max_increment)
        self.reverse = model.bonds.reverse_index()
        self.cycles = 0.0
        self._end: str | None = None  # why the run ended before max_cycles
        self.final_failure = False  # the body fell apart (the end of its fatigue life)
        self.stats.update(increments=0, fatigue_broken=0, jump_s=0.0, first_break_cycles=-1.0)

    # -- life cycle -------------------------------------------------------------------------
    def init(self) -> State:
        """The State at rest with ``fatigue_life`` = 1 and ``fatigue_cycles`` = 0."""
        s = super().init()
        self.law.init_state(s)
        s[CYCLES] = np.zeros(1)
        self.last_good = s.copy()
        return s

    def resume(self, state: State) -> None:
        """Continue from a checkpoint: N and the remaining lives are read back."""
        if CYCLES not in state:
            raise ValueError("the checkpoint has no cycle count (not a fatigue run)")
        super().resume(state)
        self.cycles = float(state[CYCLES][0])

    def done(self, state: State) -> bool:
        """Peak reached and: max_cycles reached, nothing loaded, failure or max_solves."""
        if self._failed is not None or self._end is not None or state.step >= self.max_solves:
            return True
        return self.lam >= 1.0 - 1e-12 and self.cycles >= self.max_cycles

    def total_steps(self) -> int:
        """The load steps to the peak (a lower bound: every breaking event adds one)."""
        return self.load_steps

    # -- one step ---------------------------------------------------------------------------
    def _step(self, s: State) -> StepResult:
        if self.lam < 1.0 - 1e-12:  # loading to the peak: the static solver's steps
            result = super()._step(s)
            s.t = self.cycles
            return result
        t0 = time.perf_counter()
        bonds = self._jump(s)
        s[CYCLES][0] = self.cycles
        s.t = self.cycles
        s.step += 1
        if bonds is None:  # max_cycles (or the cap) reached with nothing broken
            self.check(s)
            return StepResult(accepted=True, converged=True, residual=0.0)
        broken = self.law.commit(s)  # the bonds of the proposal, both directions
        self.stats["fatigue_broken"] += broken
        if self.stats["first_break_cycles"] < 0:
            self.stats["first_break_cycles"] = self.cycles
        pairs = bonds[self.model.bonds.bond_i[bonds] < self.model.bonds.bond_j[bonds]]
        events = ["bonds_broken"]
        try:
            self.system.remove_pairs(s, pairs)
            converged, iterations, residual = self._equilibrium(s, 1.0)
        except lin.SingularSystem as exc:
            self._end = f"final failure: the body fell apart at N = {self.cycles:.6g} ({exc})"
            converged, iterations, residual = False, 0, float("nan")
            events.append("failed")
        self.stats["solves"] += 1
        self.stats["newton_iterations"] += iterations
        if not converged and self._end is None:
            self._end = (
                f"final failure: Newton did not converge at the peak load after bonds broke "
                f"at N = {self.cycles:.6g} (residual {residual:.3g}): the remaining ligament "
                "cannot carry the peak load"
            )
            events.append("not_converged")
        s.v[...] = 0.0
        self.stats["jump_s"] += time.perf_counter() - t0
        if self._end is None:
            self.check(s)
        else:
            self.final_failure = True
        return StepResult(
            accepted=True, converged=converged, residual=residual, broken=broken,
            iterations=iterations, events=tuple(events),
        )  # fmt: skip

    def _jump(self, s: State) -> NDArray[np.int64] | None:
        """Advance N to the next breaking event (or the cap, or max_cycles) and return
        the directed bonds that fail there (both directions of each pair; proposed by the
        law, which commits them), or None."""
        fm = self.model.force_model
        damage = self.model.point_damage(s.intact)
        n_min = self.law.rates(s, fm.bond_stretch(s), damage, self.load_ratio)
        if not math.isfinite(n_min):
            self._end = "no intact bond is loaded at the peak: nothing can fail"
            return None
        left = self.max_cycles - self.cycles
        dn = min(n_min, left, self.max_increment)
        self.stats["increments"] += 1
        self.law.advance(s, dn)
        self.cycles = self.max_cycles if dn == left else self.cycles + dn
        if n_min > dn:
            return None
        batch = np.flatnonzero(self.law.cycles <= dn * (1.0 + self.batch_tolerance))
        both = np.unique(np.concatenate([batch, self.reverse[batch]]))
        self.law.spend(s, both)
        self.law.trial(s)
        return np.flatnonzero(self.law.proposed)

    # -- report -------------------------------------------------------------------------------
    def describe(self) -> str:
        """Load ratio, max cycles, linear solver."""
        return (
            f"fatigue (cycle jumping between static solves), R = {self.load_ratio:g}, "
            f"up to {self.max_cycles:.4g} cycles, linear solver {self.linear_solver}"
        )

    def summary_fields(self, state: State) -> dict[str, Any]:
        """Solver entries of ``summary.json``: the static solver's, and ``solver``
        ("fatigue"), ``cycles`` (N reached), ``max_cycles``, ``load_ratio``,
        ``increments`` (cycle jumps), ``fatigue_bonds_broken`` (directed bonds),
        ``first_break_cycles`` (N of the first broken bond, None without one),
        ``time_per_increment_s``, ``final_failure`` (the body fell apart or could not carry
        the peak load: the end of its life, not a failure of the solver), ``end`` (why the
        run ended)."""
        out = super().summary_fields(state)
        st = self.stats
        n = int(st["increments"])
        first = float(st["first_break_cycles"])
        if self._failed is not None:
            end = self._failed
        elif self._end is not None:
            end = self._end
        elif self.cycles >= self.max_cycles:
            end = "max_cycles reached"
        else:
            end = f"N = {self.cycles:.6g} reached"
        out.update(
            solver="fatigue",
            cycles=self.cycles,
            max_cycles=self.max_cycles,
            load_ratio=self.load_ratio,
            increments=n,
            fatigue_bonds_broken=int(st["fatigue_broken"]),
            first_break_cycles=first if first >= 0 else None,
            time_per_increment_s=float(st["jump_s"] / n) if n else None,
            final_failure=self.final_failure,
            end=end,
            message=end,
        )
        return out
