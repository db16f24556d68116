"""Small-strain linear static solution of any force model.

``K u = V (b + f(0))`` with ``K = -d(V f)/du`` the tangent at the reference state
(N/m), ``V b`` the external force per point (N) and Dirichlet conditions on chosen
degrees of freedom; the tangent is the model's analytic one when it has one, else the
finite-difference tangent of :mod:`peridynamics.families.tangent`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike, NDArray

from peridynamics.families.tangent import finite_difference_tangent
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.families.base import ForceModel


def reference_state(model: ForceModel | Any) -> State:
    """A State at the reference configuration: zero u, v, force, body; ``intact`` from
    the bond list (pre-cracks broken); zero ``max_stretch``, zero fields of every further
    dof group (:meth:`~peridynamics.families.base.ForceModel.dofs`: a micropolar model's
    ``theta``, ``omega``, ``moment``, ``body_moment``, shape (n, components)) and every
    field the model declares (:meth:`~peridynamics.families.base.ForceModel.state_fields`).

    ``model``: a force model, or an evaluator (its ``force_model`` declares the fields:
    a micropolar model's rotations ``theta``, for example)."""
    model = getattr(model, "force_model", model)
    n, d = model.n_points, model.dim
    fields: dict[str, NDArray] = {
        "u": np.zeros((n, d)),
        "v": np.zeros((n, d)),
        "force": np.zeros((n, d)),
        "body": np.zeros((n, d)),
        "intact": np.array(model.bonds.bond_intact, dtype=np.uint8, copy=True),
        "max_stretch": np.zeros(n),
    }
    for group in model.dofs()[1:]:  # further dof groups (micropolar rotations)
        for name in (group.value, group.rate, group.force, group.body):
            fields[name] = np.zeros((n, group.components))
    for spec in model.state_fields():
        rows = {"point": n, "bond": model.bonds.n_bonds}.get(spec.where, spec.rows)
        shape = (rows,) if spec.components == 0 else (rows, spec.components)
        fields[spec.name] = np.zeros(shape, dtype=spec.dtype)
    state = State()
    for name, array in fields.items():
        state[name] = array
    return state


def solve_linear_static(
    model: ForceModel,
    fixed_dofs: ArrayLike,
    fixed_values: ArrayLike,
    external_force: ArrayLike,
    tangent: sp.spmatrix | None = None,
    method: str = "direct",
    rtol: float = 1e-10,
) -> NDArray[np.float64]:
    """Displacement (n, dim) (m) of the small-strain linear static problem.

    Parameters
    ----------
    model : ForceModel
        Any force model (its tangent at u = 0, or the finite-difference one).
    fixed_dofs : (n_fixed,) int
        Flat dof indices ``i * dim + c`` with a prescribed displacement.
    fixed_values : (n_fixed,) float or scalar
        Their displacements (m).
    external_force : (n, dim) float
        External body force density b (N/m^3); the load on a point is ``V_i b_i``.
    tangent : sparse (n dim, n dim), optional
        K = -d(V f)/du (N/m) to use instead of the model's.
    method : {"direct", "cg"}
        Sparse LU (SuperLU) of the free block, or conjugate gradients with a Jacobi
        preconditioner (the free block is symmetric positive definite for a stable
        model with rigid motion prevented). CG is much faster for 3-D state-based
        models, whose two-horizon coupling makes the LU fill-in large.
    rtol : float
        Relative residual of CG.

    Returns
    -------
    ndarray, shape (n, dim)
        u with ``u.flat[fixed_dofs] == fixed_values``.

    Raises
    ------
    ValueError
        Bad shapes or indices, or a singular system (rigid-body motion not prevented
        by the fixed dofs).
    """
    n, d = model.n_points, model.dim
    size = n * d
    fixed = np.asarray(fixed_dofs, dtype=np.intp).reshape(-1)
    values = np.broadcast_to(np.asarray(fixed_values, dtype=np.float64), fixed.shape)
    if fixed.size and (fixed.min() < 0 or fixed.max() >= size):
        raise ValueError(f"fixed_dofs must lie in 0..{size - 1} (i * dim + c)")
    if len(np.unique(fixed)) != fixed.size:
        raise ValueError("fixed_dofs has repeated entries")
    b = np.asarray(external_force, dtype=np.float64)
    if b.shape != (n, d):
        raise ValueError(f"external_force must have shape ({n}, {d}), got {b.shape}")
    state = reference_state(model)
    model.prepass(state)
    model.force(state)
    rhs = (model.cloud.volume[:, None] * (b + state.force)).reshape(-1)
    if tangent is None:
        tangent = model.tangent(state)
    if tangent is None:
        tangent = finite_difference_tangent(model, state)
    k = sp.csr_matrix(tangent)
    if k.shape != (size, size):
        raise ValueError(f"tangent must have shape ({size}, {size}), got {k.shape}")
    free_mask = np.ones(size, dtype=bool)
    free_mask[fixed] = False
    free = np.flatnonzero(free_mask)
    u = np.zeros(size)
    u[fixed] = values
    k_free = k[free]
    rhs_free = rhs[free] - k_free[:, fixed] @ u[fixed]
    k_ff, sol = _solve_free_block(k_free[:, free], rhs_free, method, rtol)
    scale = max(float(np.abs(rhs_free).max(initial=0.0)), 1e-300)
    residual = float(np.abs(k_ff @ sol - rhs_free).max(initial=0.0))
    tol = 1e-6 if method == "direct" else max(1e-6, 10.0 * rtol * np.sqrt(len(free)))
    if not np.all(np.isfinite(sol)) or residual > tol * scale:
        raise ValueError(
            "the static system is singular or ill-conditioned (residual "
            f"{residual:.3g} vs load {scale:.3g}); fix enough dofs to prevent rigid-body "
            "motion"
        )
    u[free] = sol
    return u.reshape(n, d)


def _solve_free_block(
    k_fb: sp.spmatrix, rhs_free: NDArray[np.float64], method: str, rtol: float
) -> tuple[sp.spmatrix, NDArray[np.float64]]:
    """The free block ``k_fb`` (as solved) and the solution of ``k_fb x = rhs_free`` by
    sparse LU (``"direct"``) or Jacobi-preconditioned CG (``"cg"``)."""
    if method == "direct":
        k_ff = sp.csc_matrix(k_fb)
        try:
            sol = spla.splu(k_ff).solve(rhs_free)
        except RuntimeError as exc:
            raise ValueError(
                f"the static system is singular ({exc}); fix enough dofs to prevent "
                "rigid-body motion"
            ) from None
    elif method == "cg":
        k_ff = sp.csr_matrix(k_fb)
        diag = k_ff.diagonal()
        if not np.all(diag > 0):
            raise ValueError(
                "the tangent has a non-positive diagonal entry: CG needs an SPD system"
            )
        sol, info = spla.cg(
            k_ff, rhs_free, rtol=rtol, maxiter=20 * max(len(rhs_free), 1), M=sp.diags(1.0 / diag)
        )
        if info != 0:
            raise ValueError(
                f"CG did not converge (info {info}): the system may be singular (fix enough "
                "dofs to prevent rigid-body motion); try method='direct'"
            )
    else:
        raise ValueError(f"unknown method {method!r}; use 'direct' or 'cg'")
    return k_ff, sol
