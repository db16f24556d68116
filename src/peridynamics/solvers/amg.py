"""The iterative solver of the static solver's free-free tangent: conjugate gradients
preconditioned by smoothed-aggregation algebraic multigrid (pyamg, Olson & Schroder
2018) with the rigid-body modes (:func:`rigid_modes`) as near-null space
(:mod:`peridynamics.solvers.linear` describes its re-use after bonds break).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from peridynamics.solvers.direct import SingularSystem, _scaled, _scaling


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
