"""The implicit static solver decomposed over MPI ranks (``mpiexec -n N peridynamics
run`` with ``solver.type: static``).

The same Newton iterations, load stepping, cut-backs and bond-breaking schemes as
:class:`peridynamics.solvers.static.StaticSolver` (docs/theory_static.md), run by every
rank on its owned points:

- the residual norms sum over every rank's owned dofs;
- the Newton correction solves the owned rows of the tangent by conjugate gradients
  over all ranks, preconditioned by one multigrid V-cycle per rank
  (:class:`peridynamics.solvers.tangent_distributed.DistributedTangentSystem`);
- bond breaking picks the pairs of the whole body: each pair is a candidate on one rank
  only (the rank that owns its end point of the lower global id), every rank offers its
  own scheme's choice with the pair's l / l_c, end points' global ids and midpoint, and
  every rank then takes the same N_b largest of all (ties broken by the global ids) and
  breaks the directed bonds of those pairs that it holds;
- the next breaking event's load factor is the smallest over the ranks.

The solution agrees with the serial run to the Newton tolerance (the linear solver is
iterative), not bit for bit.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.evaluation import Evaluator
from peridynamics.solvers.breaking import PairBreaker
from peridynamics.solvers.explicit import SimulationUnstable
from peridynamics.solvers.static import StaticSolver
from peridynamics.solvers.static_checks import check_finite
from peridynamics.solvers.tangent_distributed import DistributedTangentSystem
from peridynamics.state import State


class DistributedStaticSolver(StaticSolver):
    """:class:`~peridynamics.solvers.static.StaticSolver` on one rank of a decomposed
    run (module docstring); the arguments are the serial solver's (``linear_solver``
    and ``reuse_factorization`` are not used: the solve is always the distributed CG,
    rebuilt after every bond-breaking event)."""

    def __init__(self, model: Evaluator, *args: Any, **kwargs: Any) -> None:
        super().__init__(model, *args, **kwargs)
        self.comm = model.comm
        n_owned = self.comm.n_owned
        self.n_owned = int(model.n_points if n_owned is None else n_owned)
        self._owned = np.zeros(model.n_points * self.width, dtype=bool)
        self._owned[: self.n_owned * self.width] = True
        self.system = DistributedTangentSystem(  # type: ignore[assignment]
            model, self.width, self.fixed, self.tolerance, self.stats
        )
        self.linear_solver = "distributed CG + block AMG"
        gid = np.asarray(model.cloud.global_ids, dtype=np.int64)
        self._gid = gid
        b = model.bonds
        self._n_keys = np.int64(self.comm.max(float(gid.max(initial=0))) + 1)
        keys = gid[b.bond_i].astype(np.int64) * self._n_keys + gid[b.bond_j]
        self._key_order = np.argsort(keys, kind="stable")
        self._keys = keys[self._key_order]
        self._picked_pairs = np.zeros((0, 2), dtype=np.int64)
        self._picked_mids = np.zeros((0, model.dim))
        if self.breaker is not None:
            self._own_candidates(self.breaker)

    def _own_candidates(self, breaker: PairBreaker) -> None:
        """One candidate per pair over all ranks: the bond of the owned family of the
        end point with the lower global id."""
        b, law = self.model.bonds, self.model.damage_law
        s0 = law.point_s0  # type: ignore[attr-defined]
        threshold = 0.5 * (s0[b.bond_i] + s0[b.bond_j])
        owned = np.arange(b.n_bonds) < self.model.owned_bonds
        rep = owned & (self._gid[b.bond_i] < self._gid[b.bond_j]) & np.isfinite(threshold)
        breaker.candidates = np.flatnonzero(rep)
        breaker.inv_threshold = 1.0 / threshold[breaker.candidates]

    # -- global reductions -----------------------------------------------------------------
    def _norm(self, v: NDArray[np.float64], where: NDArray) -> float:
        mask = np.zeros(v.size, dtype=bool)
        mask[where] = True
        mask &= self._owned
        return math.sqrt(self.comm.sum(float(np.sum(np.square(v[mask])))))

    def _event_factor(self, s: State, breaker: PairBreaker) -> float:
        return float(self.comm.min(breaker.factor(self._ratios(s, breaker))))

    def _pick(self, s: State, breaker: PairBreaker) -> NDArray[np.int64]:
        """The local directed bonds of the pairs picked over all ranks (module
        docstring); the pairs themselves in ``_picked_pairs`` (global ids)."""
        r = self._ratios(s, breaker)
        mine = breaker.pick(r)
        pos = np.searchsorted(breaker.candidates, mine)
        b, x = self.model.bonds, self.model.cloud.x
        offer = (
            r[pos],
            self._gid[b.bond_i[mine]],
            self._gid[b.bond_j[mine]],
            0.5 * (x[b.bond_i[mine]] + x[b.bond_j[mine]]),
        )
        parts = self.comm.gather_objects(offer)  # type: ignore[attr-defined]
        ratio = np.concatenate([p[0] for p in parts])
        gi = np.concatenate([p[1] for p in parts]).astype(np.int64)
        gj = np.concatenate([p[2] for p in parts]).astype(np.int64)
        mids = np.concatenate([p[3] for p in parts]).reshape(-1, self.model.dim)
        order = np.lexsort((gj, gi, -ratio))  # largest ratio first, then by ids
        if breaker.scheme != "A":
            order = order[: 1 if breaker.scheme == "B" else breaker.per_event]
        self._picked_pairs = np.stack([gi[order], gj[order]], axis=1)
        self._picked_mids = mids[order]
        return self._local_bonds(self._picked_pairs)

    def _local_bonds(self, pairs: NDArray[np.int64]) -> NDArray[np.int64]:
        """The directed bonds of this rank between the points of ``pairs`` (global ids,
        (m, 2)), in either direction."""
        n = self._n_keys
        keys = np.concatenate([pairs[:, 0] * n + pairs[:, 1], pairs[:, 1] * n + pairs[:, 0]])
        if len(self._keys) == 0 or len(keys) == 0:
            return np.zeros(0, dtype=np.int64)
        pos = np.minimum(np.searchsorted(self._keys, keys), len(self._keys) - 1)
        hit = self._keys[pos] == keys
        return np.unique(self._key_order[pos[hit]]).astype(np.int64)

    def _violations(self, s: State) -> bool:
        self._ratio = self._picked = None
        if self.breaker is None:
            return False
        self._picked = self._pick(s, self.breaker)
        return bool(len(self._picked_pairs))

    def _break_pending(self, s: State, breaker: PairBreaker) -> int:
        """Break the directed bonds of the picked pairs this rank holds; returns the
        directed bonds broken over all ranks (owned families)."""
        bonds = self._picked
        if bonds is None:
            bonds = self._pick(s, breaker)
        self._ratio = self._picked = None
        if self._first_break is None and len(self._picked_mids):
            self._first_break = (self._picked_mids.mean(axis=0).tolist(), self.lam)
        s.intact[bonds] = 0
        owned = int(np.count_nonzero(bonds < self.model.owned_bonds))
        s.bonds_broken += owned
        self.system.remove_pairs(s, bonds)
        self.stats["events"] += 1
        return int(self.comm.sum(float(owned)))

    def check(self, s: State) -> None:
        """Raise :class:`SimulationUnstable` on every rank when a rank's solution is not
        finite; else keep the state as the last good one."""
        q = self._gather(s)[: self.n_owned]
        if self.comm.any(not bool(np.isfinite(q).all())):
            check_finite(q, self.model.cloud.x[: self.n_owned], s, self.last_good)
            raise SimulationUnstable(  # on the ranks whose own points are finite
                f"the static solution is not finite on another rank after solve {s.step}: "
                "check the constraints (rigid-body motion must be prevented)",
                step=s.step, time=s.t, point=-1, coordinates=[], last_good=self.last_good,
            )  # fmt: skip
        self.last_good = s.snapshot(self.last_good)

    def describe(self) -> str:
        return super().describe() + f" over {self.comm.size} ranks"

    def summary_fields(self, state: State) -> dict[str, Any]:
        """The serial solver's entries, and ``cg_iterations`` (all solves) and
        ``ranks``."""
        out = super().summary_fields(state)
        out["cg_iterations"] = int(self.stats.get("cg_iterations", 0))
        out["ranks"] = int(self.comm.size)
        return out
