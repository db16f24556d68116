"""The direct factorisation of the static solver's free-free tangent
(:class:`DirectSolver`) and the helpers every linear solver of
:mod:`peridynamics.solvers.linear` shares: the diagonal scaling and
:class:`SingularSystem`.

Backends (:func:`direct_backend`): MKL PARDISO's supernodal Cholesky with a METIS
ordering (:mod:`peridynamics.solvers.pardiso`) when the optional ``mkl`` wheel is
installed (``pip install peridynamics[pardiso]``), else SuperLU
(``scipy.sparse.linalg.splu``) with the minimum-degree ordering of A^T + A and no
pivoting (symmetric mode); the environment variable ``PERIDYNAMICS_DIRECT_SOLVER``
(``pardiso`` or ``superlu``) forces one.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from peridynamics.solvers import pardiso

#: smallest admissible pivot of the diagonally scaled factorisation
PIVOT_TOLERANCE = 1e-10


class SingularSystem(ValueError):
    """The free block is singular: a part of the body can move without resistance."""


class UnconstrainedModel(SingularSystem):
    """The stiffness is singular before any load level was reached and before any bond
    broke: the deck does not hold the rigid-body motion of the body (or of a part of
    it). ``path`` names the deck key to fix, as
    :class:`~peridynamics.build.errors.SetupError` does."""

    def __init__(self, detail: str) -> None:
        self.path = "boundary_conditions"
        self.message = (
            "the static stiffness is singular before any load is applied: the body, or a "
            "part of it, can move as a rigid body. Hold the rigid-body motions with 'fixed' "
            "conditions on point sets (2-D: both components at one point and one more "
            "component at a second point; 3-D: three points), or use solver.type: adr, "
            f"which needs no such support under balanced loads (the linear solver: {detail})"
        )
        super().__init__(f"{self.path}: {self.message}")


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


def direct_backend(backend: str = "auto") -> str:
    """``pardiso`` or ``superlu``: ``auto`` takes ``PERIDYNAMICS_DIRECT_SOLVER`` when
    set, else PARDISO when MKL loads."""
    given = backend
    if backend == "auto":
        backend = os.environ.get("PERIDYNAMICS_DIRECT_SOLVER", "auto").strip().lower()
    if backend == "auto":
        return "pardiso" if pardiso.available() else "superlu"
    if backend not in ("pardiso", "superlu"):
        if given == "auto":  # from the environment
            raise ValueError(
                f"PERIDYNAMICS_DIRECT_SOLVER={backend!r}: use pardiso, superlu or auto "
                "(or unset it)"
            )
        raise ValueError(f"direct backend must be pardiso or superlu, got {backend!r}")
    return backend


class DirectSolver:
    """A direct factorisation of the diagonally scaled K_ff (module docstring).

    Attributes
    ----------
    backend : ``pardiso`` or ``superlu`` (:func:`direct_backend`).
    fill : int
        Entries of the stored factors (SuperLU: L and U; PARDISO: L).
    batch : bool
        True when a block of right-hand sides costs much less per column than one
        (PARDISO), so that :class:`UpdatedDirect` solves for columns in advance.
    pattern : csr_matrix
        The sparsity of K_ff (unit entries), for the look-ahead of :class:`UpdatedDirect`.
    """

    name = "direct"

    def __init__(self, k: sp.csr_matrix, backend: str = "auto") -> None:
        self.d = _scaling(k)
        a = _scaled(k, self.d)
        self.backend = direct_backend(backend)
        self.batch = self.backend == "pardiso"
        self.pattern = sp.csr_matrix(
            (np.ones(len(a.indices), dtype=np.int8), a.indices, a.indptr), shape=a.shape
        )
        self.lu: Any
        if self.backend == "pardiso":
            try:
                self.lu = pardiso.PardisoCholesky(a)
            except pardiso.PardisoError as exc:
                raise SingularSystem(f"the stiffness is singular or indefinite ({exc})") from None
            pivots = self.lu.pivots()
            self.fill = int(self.lu.fill)
        else:
            try:
                self.lu = spla.splu(
                    a.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                    options={"SymmetricMode": True},
                )  # fmt: skip
            except RuntimeError as exc:
                raise SingularSystem(f"the stiffness is singular ({exc})") from None
            pivots = np.abs(self.lu.U.diagonal())
            self.fill = int(self.lu.L.nnz + self.lu.U.nnz)
        # the scaled matrix has a unit diagonal: a pivot many orders below 1 means a
        # (numerically) singular system, e.g. a body free to move as a rigid body
        if not np.all(np.isfinite(pivots)) or pivots.min(initial=1.0) < PIVOT_TOLERANCE:
            raise SingularSystem(
                f"the stiffness is singular (smallest scaled pivot {pivots.min():.3g}): a "
                "part of the body can move freely; constrain the rigid-body motion"
            )

    def solve(self, b: NDArray[np.float64]) -> NDArray[np.float64]:
        """K^-1 b for b of shape (m,) or (m, k)."""
        d = self.d if b.ndim == 1 else self.d[:, None]
        return d * self.lu.solve(np.ascontiguousarray(d * b))
