"""Sparse linear solvers of the static solver, and their re-use after bonds break.

Every solver works on the free-free block K_ff of a symmetric positive definite
tangent, symmetrically scaled by its diagonal (A = D K D, D = diag(K)^-1/2: the
displacement rows (N/m) and the rotation rows (N m) of a micropolar model differ by
many orders of magnitude, which would otherwise cost the factorisation its accuracy).

* :class:`DirectSolver`: MKL PARDISO's supernodal Cholesky with a METIS ordering
  (:mod:`peridynamics.solvers.pardiso`) when the optional ``mkl`` wheel is installed
  (``pip install peridynamics[pardiso]``), else SuperLU (``scipy.sparse.linalg.splu``)
  with the minimum-degree ordering of A^T + A and no pivoting (symmetric mode); the
  environment variable ``PERIDYNAMICS_DIRECT_SOLVER`` (``pardiso`` or ``superlu``)
  forces one. At the micropolar L-panel's paper size (90 000 dofs) PARDISO factors
  in a fifth of SuperLU's time and solves a block of 64 right-hand sides for 0.03 s a
  column against SuperLU's 0.4 s (``docs/performance.md``).
* :class:`AMGSolver`: conjugate gradients preconditioned by smoothed-aggregation
  algebraic multigrid (pyamg, Olson & Schroder 2018) with the rigid-body modes as
  near-null space, for large ones.

Re-use when bonds break (the stiffness loses a few pair matrices, K = K0 - dK):

* direct: the factorisation of K0 is kept and the solution corrected by the
  Sherman-Morrison-Woodbury identity over the set S of dofs the broken pairs touch,
  ``(K0 - E D E^T)^-1 = K0^-1 + Z (I - D Z_S)^-1 D E^T K0^-1`` with ``Z = K0^-1 E``
  (E the unit columns of S, D = dK restricted to S): each newly touched dof costs one
  solve with the old factors (with PARDISO, a block of solves: the points next to the
  newly touched ones are solved for in advance, :data:`PREFETCH_DOFS`), each event a
  rank-p update of the capacitance inverse and one product with Z. K is refactored
  when the correction has cost as much as the factorisation, or |S| reaches a memory
  budget (:class:`UpdatedDirect`).
* iterative: the multigrid hierarchy of K0 preconditions CG on K0 - dK, warm started
  (``UpdatedIterative``); it is rebuilt when CG needs twice the iterations it
  needed at the rebuild.
"""

from __future__ import annotations

import time

import numpy as np
from numpy.typing import NDArray

from peridynamics.solvers.amg import AMGSolver, rigid_modes
from peridynamics.solvers.direct import (
    PIVOT_TOLERANCE,
    DirectSolver,
    SingularSystem,
    UnconstrainedModel,
    _scaled,
    _scaling,
    direct_backend,
)

__all__ = [
    "PIVOT_TOLERANCE", "AMGSolver", "DirectSolver", "SingularSystem", "UnconstrainedModel",
    "UpdatedDirect", "_scaled", "_scaling", "choose", "direct_backend", "rigid_modes",
]  # fmt: skip

#: free dofs above which ``linear_solver: auto`` picks the iterative solver (measured:
#: the SuperLU factorisation of a 2-D micropolar model with 96 000 free dofs and 28
#: neighbours takes 9 s, its fill grows faster than linearly)
AUTO_DIRECT_LIMIT = 250_000
LINEAR_SOLVERS: tuple[str, ...] = ("auto", "direct", "iterative")
#: memory for the Woodbury columns Z of :class:`UpdatedDirect` (bytes)
UPDATE_MEMORY = 2 * 2**30
#: events between recomputations of the capacitance inverse of :class:`UpdatedDirect`
REFRESH_EVENTS = 200
#: largest |S| of :class:`UpdatedDirect` (its three dense |S| x |S| arrays: 384 MiB)
MAX_RANK = 4096
#: dofs :class:`UpdatedDirect` solves for in advance with each block of new columns
#: (PARDISO only: a block of 64 right-hand sides costs about 10 single solves)
PREFETCH_DOFS = 48
#: look-ahead columns :class:`UpdatedDirect` keeps until they are touched
CACHE_COLUMNS = 512


class UpdatedDirect:
    """A direct factorisation of K0 corrected for removed pair stiffnesses (Woodbury).

    With S the dofs the removed stiffness touches, Z = K0^-1 E_S (n_free x |S|), G = Z_S
    (its rows on S, kept as a dense |S| x |S| array) and D the removed stiffness on S,
    the capacitance C = I - D G is kept as an explicit inverse H = C^-1 that every event
    updates in O(|S|^2 k) instead of refactoring C in O(|S|^3):

    * new dofs (k of them) border C with [[C, -D g], [0, I]] (g = G[S_old, new]), whose
      inverse is [[H, H D g], [0, I]];
    * the event's stiffness D_e on its p dofs R changes C by -E_R (D_e G[R, :]), a
      rank-p update: H <- H + H[:, R] (I - B H[:, R])^-1 B H with B = D_e G[R, :]
      (Sherman-Morrison-Woodbury); a singular (I - B H[:, R]) means the body fell apart.

    A right-hand side that lives on S (up to ``negligible``) is solved without the
    factors: K0^-1 b = Z b_S, so (K0 - dK)^-1 b = Z (b_S + H D G b_S), one product
    with Z. When the factorisation solves a block of right-hand sides cheaply
    (``base.batch``: PARDISO), the columns of newly touched dofs are solved for
    together with those of the up to :data:`PREFETCH_DOFS` untouched dofs most coupled
    to them (the points ahead of the crack tip, likely touched by the next events),
    which wait in a cache of :data:`CACHE_COLUMNS` columns until they are touched.

    H is recomputed from C every :data:`REFRESH_EVENTS` events against round-off. The
    arrays are preallocated to ``max_rank``; once the time spent on the correction since
    the factorisation exceeds the factorisation's own time (or |S| reaches
    ``max_rank``), :attr:`full` asks for a refactorisation.

    Parameters
    ----------
    base : DirectSolver of K0_ff.
    n_free : int
    factor_time : float
        Wall time of the factorisation of K0 (s).
    max_rank : int, optional
        Largest |S| (default: :data:`UPDATE_MEMORY` / (8 n_free), at most
        :data:`MAX_RANK` and n_free).

    Attributes
    ----------
    column_solves : int
        Columns of Z in use (solved for, or taken from the cache), over all events.
    prefetched : int
        Columns solved for in advance; ``cache_hits`` of them were used.
    """

    def __init__(
        self,
        base: DirectSolver,
        n_free: int,
        factor_time: float = 0.0,
        max_rank: int | None = None,
    ) -> None:
        self.base = base
        self.n_free = n_free
        self.factor_time = float(factor_time)
        budget = min(UPDATE_MEMORY // (8 * max(n_free, 1)), MAX_RANK, n_free)
        self.max_rank = max_rank or max(min(16, n_free), budget)
        self.slot = np.full(n_free, -1, dtype=np.int64)  # position of a dof in S
        self.dofs = np.zeros(self.max_rank, dtype=np.int64)
        self.z = np.zeros((n_free, 0), order="F")  # grown to max_rank columns on first use
        self.g = np.zeros((0, 0))
        self.delta = np.zeros((0, 0))
        self.h = np.zeros((0, 0))
        self.rank = 0
        self.column_solves = 0
        self.prefetched = 0
        self.cache_hits = 0
        self.events = 0
        self.overhead = 0.0  # s spent on the correction (not on solves with K0)
        batch = bool(getattr(base, "batch", False)) and n_free > 4 * PREFETCH_DOFS
        self.lookahead = PREFETCH_DOFS if batch else 0
        self.cache = np.zeros((n_free, 0), order="F")
        self.cache_slot = np.full(n_free, -1, dtype=np.int64)
        self.cache_dof = np.full(CACHE_COLUMNS if batch else 0, -1, dtype=np.int64)
        self.cache_next = 0

    @property
    def full(self) -> bool:
        """True when a refactorisation is due (|S| at ``max_rank``, or the correction
        has cost more than the factorisation)."""
        return self.rank >= self.max_rank or self.overhead > self.factor_time

    def _columns(self, new: NDArray[np.int64]) -> NDArray[np.float64]:
        """K0^-1 E_new (n_free, len(new)): from the cache, the rest solved for together
        with the look-ahead columns (which go to the cache)."""
        out = np.empty((self.n_free, len(new)), order="F")
        where = self.cache_slot[new]
        hit = where >= 0
        if hit.any():
            out[:, hit] = self.cache[:, where[hit]]
            self.cache_slot[new[hit]] = -1
            self.cache_dof[where[hit]] = -1
            self.cache_hits += int(hit.sum())
        miss = new[~hit]
        if not len(miss):
            return out
        ahead = self._ahead(new)
        rhs = np.concatenate([miss, ahead])
        e = np.zeros((self.n_free, len(rhs)), order="F")
        e[rhs, np.arange(len(rhs))] = 1.0
        sol = self.base.solve(e)
        out[:, ~hit] = sol[:, : len(miss)]
        if len(ahead):
            self._store(ahead, sol[:, len(miss) :])
        return out

    def _ahead(self, new: NDArray[np.int64]) -> NDArray[np.int64]:
        """Up to ``lookahead`` dofs neither in S nor cached, most coupled to ``new``
        (ties: the lower index)."""
        if not self.lookahead:
            return np.zeros(0, dtype=np.int64)
        score = np.asarray(self.base.pattern[new].sum(axis=0)).ravel()
        score[new] = 0
        score[self.slot >= 0] = 0
        score[self.cache_slot >= 0] = 0
        cand = np.flatnonzero(score)
        if len(cand) > self.lookahead:
            cand = cand[np.argsort(-score[cand], kind="stable")[: self.lookahead]]
        return np.sort(cand)

    def _store(self, dofs: NDArray[np.int64], cols: NDArray[np.float64]) -> None:
        """Put look-ahead columns in the cache (a ring: the oldest are dropped)."""
        size = len(self.cache_dof)
        if self.cache.shape[1] == 0:
            self.cache = np.zeros((self.n_free, size), order="F")
        for j, dof in enumerate(dofs):
            c = self.cache_next
            self.cache_next = (c + 1) % size
            if self.cache_dof[c] >= 0:
                self.cache_slot[self.cache_dof[c]] = -1
            self.cache[:, c] = cols[:, j]
            self.cache_dof[c] = dof
            self.cache_slot[dof] = c
        self.prefetched += len(dofs)

    def remove(self, dofs: NDArray[np.int64], blocks: NDArray[np.float64]) -> None:
        """Remove pair stiffnesses: ``blocks`` (m, p, p) on free-dof indices ``dofs``
        (m, p), -1 for a constrained dof (its rows and columns are dropped).

        Raises
        ------
        OverflowError
            When the new dofs do not fit in ``max_rank`` (refactor first).
        SingularSystem
            When the stiffness without these pairs is singular.
        """
        used = np.unique(dofs[dofs >= 0])
        new = used[self.slot[used] < 0]
        r0, r1 = self.rank, self.rank + len(new)
        if r1 > self.max_rank:
            raise OverflowError("the Woodbury correction is full: refactor")
        if self.z.shape[1] == 0:
            mr = self.max_rank
            self.z = np.zeros((self.n_free, mr), order="F")
            self.g = np.zeros((mr, mr))
            self.delta = np.zeros((mr, mr))
            self.h = np.zeros((mr, mr))
        if len(new):
            self.slot[new] = np.arange(r0, r1)
            self.dofs[r0:r1] = new
            self.z[:, r0:r1] = self._columns(new)
            self.column_solves += len(new)
        t0 = time.perf_counter()
        if len(new):  # G gains rows and columns; border H: [[H, H D g], [0, I]]
            self.g[:r1, r0:r1] = self.z[self.dofs[:r1], r0:r1]
            self.g[r0:r1, :r0] = self.z[new, :r0]
            if r0:
                g = self.g[:r0, r0:r1]
                self.h[:r0, r0:r1] = self.h[:r0, :r0] @ (self.delta[:r0, :r0] @ g)
            self.h[r0:r1, :r1] = 0.0
            self.h[r0:r1, r0:r1] = np.eye(r1 - r0)
            self.rank = r1
        # the event's removed stiffness on its slots R
        pos = np.where(dofs >= 0, self.slot[np.maximum(dofs, 0)], -1)
        rset = np.unique(pos[pos >= 0])
        local = np.full(self.max_rank, -1, dtype=np.int64)
        local[rset] = np.arange(len(rset))
        m, p = dofs.shape
        rows = np.broadcast_to(pos[:, :, None], (m, p, p)).ravel()
        cols = np.broadcast_to(pos[:, None, :], (m, p, p)).ravel()
        ok = (rows >= 0) & (cols >= 0)
        d_e = np.zeros((len(rset), len(rset)))
        np.add.at(d_e, (local[rows[ok]], local[cols[ok]]), blocks.ravel()[ok])
        self.delta[np.ix_(rset, rset)] += d_e
        r = self.rank
        self.events += 1
        if self.events % REFRESH_EVENTS == 0:
            self._refresh()
        else:
            b = d_e @ self.g[rset, :r]  # (p, r)
            hr = self.h[:r, rset]  # (r, p)
            small = np.eye(len(rset)) - b @ hr
            try:
                upd = np.linalg.solve(small, b @ self.h[:r, :r])
            except np.linalg.LinAlgError:
                upd = np.full((len(rset), r), np.nan)
            if not np.all(np.isfinite(upd)) or np.linalg.cond(small) > 1e12:
                raise SingularSystem(
                    "the stiffness became singular after bonds broke: a part of the body "
                    "is free to move"
                )
            self.h[:r, :r] += hr @ upd
        self.overhead += time.perf_counter() - t0

    def _refresh(self) -> None:
        """H = C^-1 recomputed from C = I - D G (against accumulated round-off)."""
        r = self.rank
        cap = np.eye(r) - self.delta[:r, :r] @ self.g[:r, :r]
        try:
            self.h[:r, :r] = np.linalg.inv(cap)
        except np.linalg.LinAlgError:
            raise SingularSystem(
                "the stiffness became singular after bonds broke: a part of the body is "
                "free to move"
            ) from None

    def solve(self, b: NDArray[np.float64], negligible: float = 0.0) -> NDArray[np.float64]:
        """(K0 - dK)^-1 b, shape (n_free,).

        When the part of ``b`` outside the touched dofs S has a norm <= ``negligible``
        (the residual right after bonds broke: the removed stiffness times the old
        solution, on the broken pairs' dofs only, plus the round-off of the last
        solve), K0^-1 b is taken as Z b_S (no solve with the factors; one product with
        Z in all); what is left out is at most ``negligible`` in the next residual."""
        r = self.rank
        if r == 0:
            return self.base.solve(b)
        s = self.dofs[:r]
        inside = False
        if negligible > 0.0:
            outside = b.copy()
            outside[s] = 0.0
            # no BLAS dot (np.linalg.norm): it wakes OpenBLAS's threads, which then spin
            # against Numba's workers in the next force evaluation
            inside = float(np.sqrt(np.sum(np.square(outside)))) <= negligible
        if inside:
            t0 = time.perf_counter()
            bs = b[s]
            w = self.h[:r, :r] @ (self.delta[:r, :r] @ (self.g[:r, :r] @ bs))
            out = self.z[:, :r] @ (bs + w)
            self.overhead += time.perf_counter() - t0
            return out
        y = self.base.solve(b)
        t0 = time.perf_counter()
        w = self.h[:r, :r] @ (self.delta[:r, :r] @ y[s])
        out = y + self.z[:, :r] @ w
        self.overhead += time.perf_counter() - t0
        return out


def choose(method: str, n_free: int) -> str:
    """``auto`` -> ``direct`` below :data:`AUTO_DIRECT_LIMIT` free dofs, else
    ``iterative``."""
    if method not in LINEAR_SOLVERS:
        raise ValueError(f"solver.linear_solver must be one of {LINEAR_SOLVERS}, got {method!r}")
    if method == "auto":
        return "direct" if n_free <= AUTO_DIRECT_LIMIT else "iterative"
    return method
