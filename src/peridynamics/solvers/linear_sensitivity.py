"""Sensitivities of the small-strain linear static solution to model parameters
(E, nu, ...): the direct and the adjoint method on the factorised free block.

The free rows of ``K(p) u = r(p)`` (``r = V (b + f(0))``, u prescribed on the fixed dofs)
give, differentiated with respect to a parameter p_k,

    K_ff du_f/dp_k = dr_f/dp_k - (dK/dp_k u)_f           (direct: one solve per p_k)

and the reactions on the fixed dofs ``R = (K u - r)_c`` give
``dR/dp_k = (dK/dp_k u - dr/dp_k)_c + K_cf du_f/dp_k``. For one scalar output
``J = g . u + a . R`` the adjoint ``K_ff^T lam = g_f + K_cf^T a`` (one solve whatever the
number of parameters) gives ``dJ/dp_k = lam . (dr_f/dp_k - (dK/dp_k u)_f) + a .
(dK/dp_k u - dr/dp_k)_c``. Both reuse the one LU factorisation of K_ff.

``dK/dp_k`` is the central difference of the model's assembled tangent at
``p_k (1 +- h)``: the tangent of the peridynamic models is linear in their moduli
(PMB: the bond constant c ~ E; LPS: the bulk and shear terms), so for a parameter that
enters linearly (E) the difference is exact up to round-off, and for one that enters
through a smooth function (nu) its error is O(h^2) (h = 1e-5: ~1e-10 relative). It is
the "semi-analytic" direct method: no finite difference of the solution itself.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike, NDArray

from peridynamics.families.tangent import finite_difference_tangent
from peridynamics.solvers.linear_static import reference_state

if TYPE_CHECKING:
    from peridynamics.families.base import ForceModel


@dataclass
class Sensitivities:
    """The solution at p and its derivatives.

    Attributes
    ----------
    u : (n, dim) float
        Displacement (m).
    reactions : (n_fixed,) float
        Reaction force on each fixed dof, ``(K u - r)_c`` (N).
    du_dp : (n_params, n, dim) float
        du/dp_k (m per unit of p_k).
    dreactions_dp : (n_params, n_fixed) float
        dR/dp_k (N per unit of p_k).
    """

    u: NDArray[np.float64]
    reactions: NDArray[np.float64]
    du_dp: NDArray[np.float64]
    dreactions_dp: NDArray[np.float64]


def _system(model: ForceModel, b: NDArray[np.float64]) -> tuple[sp.csr_matrix, NDArray]:
    """The tangent K (N/m) and the load vector r = V (b + f(0)) (N) of a model."""
    state = reference_state(model)
    model.prepass(state)
    model.force(state)
    rhs = (model.cloud.volume[:, None] * (b + state.force)).reshape(-1)
    k = model.tangent(state)
    if k is None:
        k = finite_difference_tangent(model, state)
    return sp.csr_matrix(k), rhs


def linear_static_sensitivities(
    model_at: Callable[[NDArray[np.float64]], ForceModel],
    params: Sequence[float],
    fixed_dofs: ArrayLike,
    fixed_values: ArrayLike,
    external_force: ArrayLike,
    rel_step: float = 1e-5,
    adjoint: tuple[ArrayLike, ArrayLike] | None = None,
) -> tuple[Sensitivities, NDArray[np.float64] | None]:
    """The linear static solution at ``params`` and its derivatives (module docstring).

    Parameters
    ----------
    model_at : callable
        ``params -> ForceModel`` on the same cloud and bonds (e.g. ``lambda p:
        LPSMaterial(p[0], p[1], rho).force_model(cloud, bonds)``).
    params : (n_params,) float
        The parameter values (SI), each non-zero.
    fixed_dofs, fixed_values
        Flat dof indices ``i * dim + c`` and their displacements (m), as
        :func:`~peridynamics.solvers.linear_static.solve_linear_static`.
    external_force : (n, dim) float
        Body force density b (N/m^3), independent of the parameters.
    rel_step : float
        Relative step h of the central difference of the tangent.
    adjoint : (g, a), optional
        Weights of a scalar output ``J = g . u + a . R``: g of shape (n, dim) or (n dim,),
        a of shape (n_fixed,). Then dJ/dp is also returned, by one adjoint solve.

    Returns
    -------
    Sensitivities
        u, R and their direct derivatives.
    ndarray (n_params,) or None
        dJ/dp by the adjoint method (``None`` without ``adjoint``).
    """
    p0 = np.asarray(params, dtype=np.float64)
    model = model_at(p0)
    n, d = model.n_points, model.dim
    b = np.asarray(external_force, dtype=np.float64)
    if b.shape != (n, d):
        raise ValueError(f"external_force must have shape ({n}, {d}), got {b.shape}")
    fixed = np.asarray(fixed_dofs, dtype=np.intp).reshape(-1)
    if fixed.size and (fixed.min() < 0 or fixed.max() >= n * d):
        raise ValueError(f"fixed_dofs must lie in 0..{n * d - 1} (i * dim + c)")
    free = np.setdiff1d(np.arange(n * d), fixed)
    k, rhs = _system(model, b)
    u = np.zeros(n * d)
    u[fixed] = np.broadcast_to(np.asarray(fixed_values, dtype=np.float64), fixed.shape)
    lu = spla.splu(sp.csc_matrix(k[free][:, free]))
    u[free] = lu.solve(rhs[free] - k[free][:, fixed] @ u[fixed])
    reactions = (k @ u - rhs)[fixed]
    du = np.zeros((len(p0), n * d))
    dreac = np.zeros((len(p0), fixed.size))
    loads = []
    for j, pj in enumerate(p0):
        if pj == 0.0:
            raise ValueError(f"params[{j}] is 0: the relative step needs a non-zero value")
        h = rel_step * abs(pj)
        up, dn = p0.copy(), p0.copy()
        up[j] += h
        dn[j] -= h
        (kp, rp), (km, rm) = _system(model_at(up), b), _system(model_at(dn), b)
        dk_u = (kp @ u - km @ u) / (2 * h)
        dr = (rp - rm) / (2 * h)
        load = dr - dk_u  # K du = load on the free rows (fixed du = 0)
        du[j, free] = lu.solve(load[free])
        dreac[j] = -load[fixed] + k[fixed][:, free] @ du[j, free]
        loads.append(load)
    sens = Sensitivities(u.reshape(n, d), reactions, du.reshape(len(p0), n, d), dreac)
    if adjoint is None:
        return sens, None
    g = np.asarray(adjoint[0], dtype=np.float64).reshape(-1)
    a = np.asarray(adjoint[1], dtype=np.float64).reshape(-1)
    if g.shape != (n * d,) or a.shape != fixed.shape:
        raise ValueError(f"adjoint weights: g of {n * d} values and a of {fixed.size}")
    lam = lu.solve(g[free] + k[fixed][:, free].T @ a, trans="T")
    dj = np.array([lam @ ld[free] - a @ ld[fixed] for ld in loads])
    return sens, dj


def finite_difference_check(
    solve: Callable[[NDArray[np.float64]], Any], params: Sequence[float],
    rel_step: float = 1e-4,
) -> NDArray[np.float64]:  # fmt: skip
    """Central differences ``(solve(p + h e_k) - solve(p - h e_k)) / 2h`` of any output
    of the solve (the oracle of the direct and adjoint derivatives)."""
    p0 = np.asarray(params, dtype=np.float64)
    out: list[Any] = []
    for j, pj in enumerate(p0):
        h = rel_step * abs(pj)
        up, dn = p0.copy(), p0.copy()
        up[j] += h
        dn[j] -= h
        diff = np.asarray(solve(up), dtype=np.float64) - np.asarray(solve(dn), dtype=np.float64)
        out.append(diff / (2 * h))
    return np.array(out)
