"""The free-free tangent of a static solve and its linear solver, kept across Newton
iterations and bond-breaking events (:class:`TangentSystem`; the solver itself is
:class:`peridynamics.solvers.static.StaticSolver`).

The tangent of the model is assembled at a state, dofs without stiffness are pinned
(a point whose bonds all broke, a micropolar rotation with k_t = k_phi = 0), the
free-free block is factored (``direct``) or given a multigrid hierarchy
(``iterative``), and bond-breaking events are passed on as removed pair stiffnesses
(:class:`peridynamics.solvers.linear.UpdatedDirect`: Woodbury; iterative: the old
hierarchy preconditions the updated operator). Nonlinear models refactor at every
Newton iteration.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.evaluation import Evaluator
from peridynamics.solvers import linear as lin
from peridynamics.state import State


class TangentSystem:
    """K_ff of a static solve and its (re-used) linear solver.

    Parameters
    ----------
    model : Evaluator
    width : int
        Dofs per point (all dof groups of the force model).
    fixed : (n width,) bool
        Eliminated dofs (fixed or prescribed).
    method : {"auto", "direct", "iterative"}
    tolerance : float
        Newton tolerance (the iterative solver solves to 1 % of it).
    reuse : bool
        Keep the factorisation across bond-breaking events (linear models).
    stats : dict
        Counters shared with the solver (``factorizations``, ``factorization_s``,
        ``update_column_solves``, ``linear_solve_s``, ``pinned_points``).

    Attributes
    ----------
    free : (n_free,) indices of the free dofs of the current factorisation.
    free_pos : (n width,) position of each dof among the free ones (-1: not free).
    method_used : str, ``direct`` or ``iterative`` once factored.
    """

    def __init__(
        self,
        model: Evaluator,
        width: int,
        fixed: NDArray[np.bool_],
        method: str,
        tolerance: float,
        reuse: bool,
        stats: dict[str, float],
    ) -> None:
        self.model = model
        self.width = width
        self.fixed = fixed
        self.method = method
        self.tolerance = tolerance
        self.reuse = reuse
        self.stats = stats
        self.linear_model = bool(getattr(model.force_model, "linear", False))
        self.factor: Any = None
        self.free = np.zeros(0, dtype=np.int64)
        self.free_pos = np.zeros(0, dtype=np.int64)
        self.removed: list[sp.coo_matrix] = []
        self.k0: sp.csr_matrix | None = None
        self._amg_base = 0
        self._columns_before = 0
        self.method_used = ""

    def invalidate(self) -> None:
        """Drop the factorisation: the next solve refactors at its state."""
        self.factor = None

    def refactor(self, s: State) -> None:
        """Assemble the tangent at ``s``, pin dofs without stiffness, factor K_ff."""
        t0 = time.perf_counter()
        k = sp.csr_matrix(self.model.tangent(s))
        size = self.model.n_points * self.width
        if k.shape != (size, size):
            raise ValueError(f"the tangent has shape {k.shape}, expected ({size}, {size})")
        diag = k.diagonal()
        free_mask = ~self.fixed & (diag > 0)
        pinned = (~self.fixed) & ~(diag > 0)
        self.stats["pinned_points"] = int(len(np.unique(np.flatnonzero(pinned) // self.width)))
        self.free = np.flatnonzero(free_mask)
        self.free_pos = np.full(size, -1, dtype=np.int64)
        self.free_pos[self.free] = np.arange(len(self.free))
        k_ff = k[self.free][:, self.free].tocsr()
        method = lin.choose(self.method, len(self.free))
        self.method_used = method
        if method == "direct":
            t1 = time.perf_counter()
            base = lin.DirectSolver(k_ff)
            self.factor = lin.UpdatedDirect(base, len(self.free), time.perf_counter() - t1)
        else:
            modes = lin.rigid_modes(self.model.cloud.x, self.width)[self.free]
            self.factor = lin.AMGSolver(k_ff, modes, rtol=0.01 * self.tolerance)
            self.k0 = k_ff
            self._amg_base = 0
        self.removed = []
        if isinstance(self.factor, lin.UpdatedDirect):
            self._columns_before = int(self.stats["update_column_solves"])
        self.stats["factorizations"] += 1
        self.stats["factorization_s"] += time.perf_counter() - t0

    def solve(
        self, s: State, p: NDArray[np.float64], negligible: float = 0.0
    ) -> NDArray[np.float64]:
        """K_ff^-1 P_free (the Newton correction of the free dofs); a part of P outside
        the dofs touched by broken bonds below ``negligible`` (N) may be left to the
        next Newton iteration (:meth:`UpdatedDirect.solve`)."""
        t0 = time.perf_counter()
        if self.factor is None or not self.linear_model:
            self.refactor(s)
        f = self.factor
        rhs = p[self.free]
        if isinstance(f, lin.UpdatedDirect):
            out = f.solve(rhs, negligible)
        else:
            if self.removed:
                removed = sp.csr_matrix(sum(self.removed[1:], self.removed[0]))
                out = f.solve_with(lambda x: self.k0 @ x - removed @ x, rhs)
            else:
                out = f.solve_with(self.k0, rhs)
            if self._amg_base == 0:
                self._amg_base = max(f.iterations, 1)
            elif f.iterations > 2 * self._amg_base:
                self.factor = None  # rebuild the hierarchy at the next solve
        self.stats["linear_solve_s"] += time.perf_counter() - t0
        return out

    def remove_pairs(self, s: State, bonds: NDArray[np.int64]) -> None:
        """Tell the factorisation that the pairs ``bonds`` lost their stiffness."""
        fm = self.model.force_model
        if not (self.linear_model and self.reuse) or self.factor is None:
            self.factor = None
            return
        b = self.model.bonds
        w = self.width
        comp = np.arange(w)
        dofs = np.concatenate(
            [b.bond_i[bonds, None] * w + comp, b.bond_j[bonds, None] * w + comp], axis=1
        ).astype(np.int64)
        local = self.free_pos[dofs]
        blocks = fm.pair_stiffness(bonds)  # type: ignore[attr-defined]
        f = self.factor
        if isinstance(f, lin.UpdatedDirect):
            if f.full or f.rank + local.size > f.max_rank:
                self.factor = None  # refactor with these bonds gone
                return
            f.remove(local, blocks)
            self.stats["update_column_solves"] = self._columns_before + f.column_solves
        else:
            m, p = local.shape
            rows = np.broadcast_to(local[:, :, None], (m, p, p)).ravel()
            cols = np.broadcast_to(local[:, None, :], (m, p, p)).ravel()
            ok = (rows >= 0) & (cols >= 0)
            n_free = len(self.free)
            self.removed.append(
                sp.coo_matrix((blocks.ravel()[ok], (rows[ok], cols[ok])), shape=(n_free, n_free))
            )
        # a point left without stiffness makes the system singular: refactor (pins it)
        touched = np.unique(np.concatenate([b.bond_i[bonds], b.bond_j[bonds]]))
        alive = _intact_count(b.offsets, s.intact, touched)
        if np.any(alive == 0) and np.any(~self.fixed.reshape(-1, w)[touched].all(axis=1)):
            self.factor = None


def _intact_count(
    offsets: NDArray[np.int64], intact: NDArray[np.uint8], points: NDArray[np.int64]
) -> NDArray[np.int64]:
    """Intact bonds of the families of ``points`` (m,), shape (m,): their bond ranges
    only, not the whole list."""
    start = offsets[points]
    count = offsets[points + 1] - start
    first = np.cumsum(count) - count  # position of each family in the gathered bonds
    idx = np.repeat(start - first, count) + np.arange(int(count.sum()))
    got = np.zeros(len(points), dtype=np.int64)
    np.add.at(got, np.repeat(np.arange(len(points)), count), intact[idx] != 0)
    return got
