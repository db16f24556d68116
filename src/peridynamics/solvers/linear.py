"""Sparse linear solvers of the static solver, and their re-use after bonds break.

Every solver works on the free-free block K_ff of a symmetric positive definite
tangent, symmetrically scaled by its diagonal (A = D K D, D = diag(K)^-1/2: the
displacement rows (N/m) and the rotation rows (N m) of a micropolar model differ by
many orders of magnitude, which would otherwise cost the factorisation its accuracy).

* :class:`DirectSolver`: SuperLU (``scipy.sparse.linalg.splu``) with the minimum-degree
  ordering of A^T + A and no pivoting (symmetric mode), for moderate sizes.
* :class:`AMGSolver`: conjugate gradients preconditioned by smoothed-aggregation
  algebraic multigrid (pyamg, Olson & Schroder 2018) with the rigid-body modes as
  near-null space, for large ones.

Re-use when bonds break (the stiffness loses a few pair matrices, K = K0 - dK):

* direct: the factorisation of K0 is kept and the solution corrected by the
  Sherman-Morrison-Woodbury identity over the set S of dofs the broken pairs touch,
  ``(K0 - E D E^T)^-1 = K0^-1 + Z (I - D Z_S)^-1 D E^T K0^-1`` with ``Z = K0^-1 E``
  (E the unit columns of S, D = dK restricted to S): each newly touched dof costs one
  solve with the old factors, each event one dense solve of size |S|. K is
  refactored when |S| reaches a memory budget (:class:`UpdatedDirect`).
* iterative: the multigrid hierarchy of K0 preconditions CG on K0 - dK, warm started
  (``UpdatedIterative``); it is rebuilt when CG needs twice the iterations it
  needed at the rebuild.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

#: free dofs above which ``linear_solver: auto`` picks the iterative solver (measured:
#: the SuperLU factorisation of a 2-D micropolar model with 96 000 free dofs and 28
#: neighbours takes 9 s, its fill grows faster than linearly)
AUTO_DIRECT_LIMIT = 250_000
LINEAR_SOLVERS: tuple[str, ...] = ("auto", "direct", "iterative")
#: smallest admissible pivot of the diagonally scaled factorisation
PIVOT_TOLERANCE = 1e-10
#: memory for the Woodbury columns Z of :class:`UpdatedDirect` (bytes)
UPDATE_MEMORY = 2 * 2**30
#: events between recomputations of the capacitance inverse of :class:`UpdatedDirect`
REFRESH_EVENTS = 200
#: largest |S| of :class:`UpdatedDirect` (its two dense |S| x |S| arrays: 256 MiB)
MAX_RANK = 4096


class SingularSystem(ValueError):
    """The free block is singular: a part of the body can move without resistance."""


def _scaling(k: sp.csr_matrix) -> NDArray[np.float64]:
    diag = k.diagonal()
    if not np.all(diag > 0):
        bad = int(np.argmin(diag))
        raise SingularSystem(
            f"the stiffness has a non-positive diagonal entry at free dof {bad} ({diag[bad]:.3g}): "
            "a point or rotation without stiffness, or an unstable model"
        )
    return 1.0 / np.sqrt(diag)


def _scaled(k: sp.csr_matrix, d: NDArray[np.float64]) -> sp.csr_matrix:
    """D K D for D = diag(d)."""
    dm = sp.diags(d)
    return sp.csr_matrix(dm @ k @ dm)


class DirectSolver:
    """SuperLU of the diagonally scaled K_ff (module docstring)."""

    name = "direct"

    def __init__(self, k: sp.csr_matrix) -> None:
        self.d = _scaling(k)
        a = _scaled(k, self.d).tocsc()
        try:
            self.lu = spla.splu(
                a, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                options={"SymmetricMode": True},
            )  # fmt: skip
        except RuntimeError as exc:
            raise SingularSystem(f"the stiffness is singular ({exc})") from None
        # the scaled matrix has a unit diagonal: a pivot many orders below 1 means a
        # (numerically) singular system, e.g. a body free to move as a rigid body
        pivots = np.abs(self.lu.U.diagonal())
        if not np.all(np.isfinite(pivots)) or pivots.min(initial=1.0) < PIVOT_TOLERANCE:
            raise SingularSystem(
                f"the stiffness is singular (smallest scaled pivot {pivots.min():.3g}): a "
                "part of the body can move freely; constrain the rigid-body motion"
            )
        self.fill = int(self.lu.L.nnz + self.lu.U.nnz)

    def solve(self, b: NDArray[np.float64]) -> NDArray[np.float64]:
        """K^-1 b for b of shape (m,) or (m, k)."""
        d = self.d if b.ndim == 1 else self.d[:, None]
        return d * self.lu.solve(np.ascontiguousarray(d * b))


class AMGSolver:
    """CG preconditioned by smoothed-aggregation AMG of the scaled K_ff."""

    name = "iterative"

    def __init__(self, k: sp.csr_matrix, near_null: NDArray[np.float64], rtol: float) -> None:
        try:
            import pyamg
        except ImportError:  # pragma: no cover - pyamg is a dependency
            raise ImportError(
                "solver.linear_solver iterative needs pyamg: pip install pyamg"
            ) from None
        self.d = _scaling(k)
        self.a = _scaled(k, self.d)
        b = near_null / self.d[:, None]
        b /= np.linalg.norm(b, axis=0)
        self.ml = pyamg.smoothed_aggregation_solver(self.a, B=b, symmetry="hermitian")
        self.precond = self.ml.aspreconditioner(cycle="V")
        self.rtol = rtol
        self.iterations = 0

    def solve_with(
        self, operator: Any, b: NDArray[np.float64], x0: NDArray[np.float64] | None = None
    ) -> NDArray[np.float64]:
        """K^-1 b by CG for K = ``operator``, an unscaled sparse matrix or a function
        x -> K x, preconditioned by the hierarchy of the matrix this solver was built
        with (the scaling is applied here)."""
        d = self.d
        apply = operator if callable(operator) else operator.__matmul__
        op = spla.LinearOperator(self.a.shape, matvec=lambda y: d * apply(d * y))
        return self._cg(op, b, x0)

    def _cg(
        self, op: Any, b: NDArray[np.float64], x0: NDArray[np.float64] | None
    ) -> NDArray[np.float64]:
        """CG on the scaled operator ``op``; returns the unscaled solution."""
        d = self.d
        count = [0]

        def tick(_: Any) -> None:
            count[0] += 1

        y0 = None if x0 is None else x0 / d
        y, info = spla.cg(
            op, d * b, x0=y0, rtol=self.rtol, maxiter=2000, M=self.precond, callback=tick
        )
        self.iterations = count[0]
        if info != 0 or not np.all(np.isfinite(y)):
            raise SingularSystem(
                f"CG with the multigrid preconditioner did not converge (info {info}): the "
                "system may be singular; try solver.linear_solver direct"
            )
        return d * y

    def solve(self, b: NDArray[np.float64]) -> NDArray[np.float64]:
        """K^-1 b (b of shape (m,)) for the matrix the solver was built with."""
        return self._cg(self.a, b, None)


class UpdatedDirect:
    """A direct factorisation of K0 corrected for removed pair stiffnesses (Woodbury).

    With S the dofs the removed stiffness touches, Z = K0^-1 E_S (n_free x |S|), G = Z_S
    (its rows on S) and D the removed stiffness on S, the capacitance C = I - D G is
    kept as an explicit inverse H = C^-1 that every event updates in O(|S|^2 k) instead
    of refactoring C in O(|S|^3):

    * new dofs (k of them) border C with [[C, -D g], [0, I]] (g = G[S_old, new]), whose
      inverse is [[H, H D g], [0, I]];
    * the event's stiffness D_e on its p dofs R changes C by -E_R (D_e G[R, :]), a
      rank-p update: H <- H + H[:, R] (I - B H[:, R])^-1 B H with B = D_e G[R, :]
      (Sherman-Morrison-Woodbury); a singular (I - B H[:, R]) means the body fell apart.

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
        self.delta = np.zeros((0, 0))
        self.h = np.zeros((0, 0))
        self.rank = 0
        self.column_solves = 0
        self.events = 0
        self.overhead = 0.0  # s spent on the correction (not on solves with K0)

    @property
    def full(self) -> bool:
        """True when a refactorisation is due (|S| at ``max_rank``, or the correction
        has cost more than the factorisation)."""
        return self.rank >= self.max_rank or self.overhead > self.factor_time

    def _g(self, rows: NDArray[np.int64], cols: slice) -> NDArray:
        """G[rows, cols] = Z[dofs[rows], cols] (a gather of the needed entries only)."""
        c = np.arange(cols.start, cols.stop)
        return self.z[np.ix_(self.dofs[rows], c)]

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
            self.delta = np.zeros((mr, mr))
            self.h = np.zeros((mr, mr))
        if len(new):
            self.slot[new] = np.arange(r0, r1)
            self.dofs[r0:r1] = new
            e = np.zeros((self.n_free, len(new)))
            e[new, np.arange(len(new))] = 1.0
            self.z[:, r0:r1] = self.base.solve(e)
            self.column_solves += len(new)
        t0 = time.perf_counter()
        if len(new):  # border H: [[H, H D g], [0, I]]
            if r0:
                g = self._g(np.arange(r0), slice(r0, r1))
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
            b = d_e @ self._g(rset, slice(0, r))  # (p, r)
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
        cap = np.eye(r) - self.delta[:r, :r] @ self._g(np.arange(r), slice(0, r))
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
        solve), K0^-1 b is taken from the columns Z (no solve with the factors); what
        is left out is at most ``negligible`` in the next residual."""
        r = self.rank
        s = self.dofs[:r]
        if r and negligible > 0.0:
            outside = b.copy()
            outside[s] = 0.0
            rest = float(np.linalg.norm(outside))
            y = self.z[:, :r] @ b[s] if rest <= negligible else self.base.solve(b)
        else:
            y = self.base.solve(b)
        if r == 0:
            return y
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


def rigid_modes(x: NDArray[np.float64], width: int) -> NDArray[np.float64]:
    """Rigid-body modes (n width, n_modes) of points ``x`` (n, dim) with ``width`` dofs
    per point: translations and rotations (2-D: one; 3-D: three); a micropolar model's
    rotation dof (width = dim + 1 in 2-D) turns with the body."""
    n, dim = x.shape
    c = x - x.mean(axis=0)
    modes = []
    for a in range(dim):
        m = np.zeros((n, width))
        m[:, a] = 1.0
        modes.append(m)
    if dim == 2:
        m = np.zeros((n, width))
        m[:, 0], m[:, 1] = -c[:, 1], c[:, 0]
        if width > 2:
            m[:, 2] = 1.0
        modes.append(m)
    elif dim == 3:
        for a, b in ((0, 1), (1, 2), (2, 0)):
            m = np.zeros((n, width))
            m[:, a], m[:, b] = -c[:, b], c[:, a]
            modes.append(m)
    out = np.stack([m.reshape(-1) for m in modes], axis=1)
    scale = math.sqrt(n)
    return out / scale
