"""The tangent system of a static solve decomposed over MPI ranks
(:class:`DistributedTangentSystem`, used by
:class:`peridynamics.solvers.static_distributed.DistributedStaticSolver`).

Each rank assembles the rows of its owned points from its local model's tangent (the
force on a point depends on its own bond family, and on its neighbours' families where
the model reads them: the rank holds those as ghosts), keeps the columns of its owned
free dofs (K_oo) and of its ghosts' free dofs (K_og), and solves K_ff dq = P_f by
preconditioned conjugate gradients over all ranks:

- the product K_ff x of a rank is K_oo x_o + K_og x_g, with the ghost part x_g filled
  from its owners by one halo exchange;
- the dot products are sums over the ranks (one Allreduce each);
- the preconditioner is block Jacobi with one smoothed-aggregation AMG V-cycle per rank
  (pyamg, of the rank's diagonally scaled K_oo, with the rigid-body modes of its points
  as near-null space).

A block-Jacobi V-cycle is symmetric and positive definite for a symmetric positive
definite K_ff, so CG applies (Saad (2003), "Iterative methods for sparse linear
systems", section 9.2 on preconditioned CG; section 12 on block preconditioners); its
iteration count grows slowly with the number of ranks, since the coupling between the
ranks' blocks is left to CG. The matrix is rebuilt at every Newton iteration of a
nonlinear model. After a bond-breaking event a linear model's matrix is reassembled and
the old hierarchy kept as preconditioner until CG needs twice its first iteration count
(no Woodbury update across ranks).
"""

from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.evaluation import Evaluator
from peridynamics.solvers.amg import AMGSolver, rigid_modes
from peridynamics.solvers.direct import SingularSystem
from peridynamics.state import State

#: iterations of the distributed CG before a solve is declared failed
MAX_ITERATIONS = 5000


class DistributedTangentSystem:
    """K_ff of the owned free dofs of a rank and its distributed CG.

    Parameters
    ----------
    model : Evaluator
        The rank's local model (points numbered [owned | ghost]).
    width : int
        Dofs per point.
    fixed : (n_local width,) bool
        Eliminated dofs of the local points.
    tolerance : float
        Newton tolerance; CG solves to 1 % of it (relative residual).
    stats : dict
        Counters shared with the solver (``factorizations``, ``factorization_s``,
        ``linear_solve_s``, ``pinned_points``, ``cg_iterations``).

    Attributes
    ----------
    free : (n_free,) flat local indices of the owned free dofs.
    method_used : str, ``"distributed CG + block AMG"``.
    """

    def __init__(
        self,
        model: Evaluator,
        width: int,
        fixed: NDArray[np.bool_],
        tolerance: float,
        stats: dict[str, float],
    ) -> None:
        self.model = model
        self.comm = model.comm
        self.width = width
        self.fixed = fixed
        self.rtol = 0.01 * tolerance
        self.stats = stats
        stats.setdefault("cg_iterations", 0)
        n_owned = self.comm.n_owned
        self.n_owned = int(model.n_points if n_owned is None else n_owned)
        self.linear_model = bool(getattr(model.force_model, "linear", False))
        self.free = np.zeros(0, dtype=np.int64)
        self._ghost_free = np.zeros(0, dtype=np.int64)
        self._k_oo: sp.csr_matrix | None = None
        self._k_og: sp.csr_matrix | None = None
        self._amg: AMGSolver | None = None
        self._built = False  # every rank rebuilds together (collective)
        self._stale = False  # bonds broke: reassemble, keep the hierarchy
        self._base_iterations = 0  # CG iterations of the first solve with a hierarchy
        self.method_used = "distributed CG + block AMG"

    def invalidate(self) -> None:
        """Drop the matrix: the next solve assembles it at its state."""
        self._built = False

    def refactor(self, s: State, keep_preconditioner: bool = False) -> None:
        """Assemble the owned rows at ``s``, pin owned dofs without stiffness, agree on
        the ghosts' free dofs with their owners, and build the rank's AMG hierarchy;
        ``keep_preconditioner``: keep the hierarchy of the last matrix when no rank's
        free dofs changed (bonds broke in a linear model)."""
        t0 = time.perf_counter()
        changed = self._assemble(s)
        if not keep_preconditioner or changed:
            x = self.model.cloud.x[: self.n_owned]
            modes = rigid_modes(x, self.width)[self.free]
            failed = ""
            try:
                self._amg = AMGSolver(self._k_oo, modes, rtol=self.rtol) if len(self.free) else None
            except Exception as exc:  # a rank whose block cannot be coarsened
                failed = f"{type(exc).__name__}: {exc}"
            if self.comm.any(bool(failed)):
                raise SingularSystem(
                    f"the multigrid set-up failed on a rank ({failed or 'another'})"
                )
            self._base_iterations = 0
            self.stats["factorizations"] += 1
        self._built, self._stale = True, False
        self.stats["factorization_s"] += time.perf_counter() - t0

    def _assemble(self, s: State) -> bool:
        """K_oo and K_og at ``s`` (owned rows); True when the free dofs changed on some
        rank."""
        n_local, w = self.model.n_points, self.width
        k = sp.csr_matrix(self.model.tangent(s))
        if k.shape != (n_local * w, n_local * w):
            raise ValueError(f"the tangent has shape {k.shape}, expected {n_local * w} square")
        rows = k[: self.n_owned * w]
        diag = rows.diagonal()
        owned_free = ~self.fixed[: self.n_owned * w] & (diag > 0)
        pinned = ~self.fixed[: self.n_owned * w] & ~(diag > 0)
        self.stats["pinned_points"] = self.comm.sum(
            float(len(np.unique(np.flatnonzero(pinned) // w)))
        )
        flags = np.zeros((n_local, w))
        flags[: self.n_owned] = owned_free.reshape(-1, w)
        self.comm.exchange(flags)  # the owners' decision for the ghosts
        free = np.flatnonzero(owned_free)
        ghost_free = self.n_owned * w + np.flatnonzero(flags.reshape(-1)[self.n_owned * w :] > 0.5)
        changed = not (
            np.array_equal(free, self.free) and np.array_equal(ghost_free, self._ghost_free)
        )
        self.free, self._ghost_free = free, ghost_free
        owned_rows = rows[free]
        self._k_oo = owned_rows[:, free].tocsr()
        self._k_og = owned_rows[:, ghost_free].tocsr()
        return bool(self.comm.any(changed))

    def _product(self, x: NDArray[np.float64], field: NDArray[np.float64]) -> NDArray[np.float64]:
        """K_ff x on this rank's owned free dofs (``field``: scratch (n_local, width))."""
        assert self._k_oo is not None and self._k_og is not None
        flat = field.reshape(-1)
        flat[:] = 0.0
        flat[self.free] = x
        self.comm.exchange(field)
        return np.asarray(self._k_oo @ x + self._k_og @ flat[self._ghost_free])

    def _dot(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
        return float(self.comm.sum(float(np.dot(a, b))))

    def solve(
        self, s: State, p: NDArray[np.float64], negligible: float = 0.0
    ) -> NDArray[np.float64]:
        """K_ff^-1 P_f of the owned free dofs, by CG over all ranks (module docstring)."""
        t0 = time.perf_counter()
        if not self._built or not self.linear_model:
            self.refactor(s)
        elif self._stale:
            self.refactor(s, keep_preconditioner=True)
        amg = self._amg
        d = amg.d if amg is not None else np.ones(0)
        field = np.zeros((self.model.n_points, self.width))
        b = d * p[self.free]  # the scaled system D K D y = D P, x = D y
        y = np.zeros_like(b)
        r = b.copy()
        z = amg.precond @ r if amg is not None else r.copy()
        direction = z.copy()
        rz = self._dot(r, z)
        stop = self.rtol * math.sqrt(self._dot(b, b))
        iterations = 0
        while math.sqrt(self._dot(r, r)) > stop:
            if iterations >= MAX_ITERATIONS or not math.isfinite(rz):
                raise SingularSystem(
                    f"distributed CG did not converge in {iterations} iterations: the system "
                    "may be singular (rigid-body motion not prevented?)"
                )
            ad = d * self._product(d * direction, field)
            curvature = self._dot(direction, ad)
            if not curvature > 0:
                raise SingularSystem("distributed CG met a non-positive curvature: K_ff singular")
            alpha = rz / curvature
            y += alpha * direction
            r -= alpha * ad
            z = amg.precond @ r if amg is not None else r.copy()
            rz_new = self._dot(r, z)
            direction = z + (rz_new / rz) * direction
            rz = rz_new
            iterations += 1
        self.stats["cg_iterations"] += iterations
        if self._base_iterations == 0:
            self._base_iterations = max(iterations, 1)
        elif iterations > 2 * self._base_iterations:  # the hierarchy has aged: rebuild
            self._built = False
        self.stats["linear_solve_s"] += time.perf_counter() - t0
        return np.asarray(d * y)

    def remove_pairs(self, s: State, bonds: NDArray[np.int64]) -> None:
        """Bonds broke: the next solve reassembles the matrix; a linear model keeps the
        multigrid hierarchy of the old one as preconditioner until CG needs twice the
        iterations it needed with a fresh one (as the serial iterative solver)."""
        if self.linear_model:
            self._stale = True
        else:
            self._built = False
