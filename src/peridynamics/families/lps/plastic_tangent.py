"""Consistent (algorithmic) tangent of the elastic-plastic LPS
(:mod:`peridynamics.families.lps.plastic`): the exact derivative of the force of the
radial return from the committed history, for the static solver's Newton iterations.

Per point i and intact bond k of its family (wv_k, L_k, e_k, the committed ep_k), with
``d_k = e_k - theta_i L_k / 3 - ep_k`` (the trial elastic deviatoric extension) and the
factor c_i of the return, the force state of the point is::

    tau_k = wv_k (kappa_i theta_i L_k + a_i c_i d_k),  kappa_i = cd_i + a_i / 3

(since ``e - p = theta L / 3 + c d`` for the returned plastic extension p). Its
derivative with respect to the extensions of the family, with ``theta_i = ts_i sum wv L
e``, ``S_i = sum_k wv_k d_k L_k`` and, on a yielding point (c_i < 1), ``c_i = 1 - beta
(1 - Y_i / sbar_i)`` (``beta = 3 mu / (3 mu + H)``, ``Y_i = sigma_y + H q_n``,
``sbar_i = sqrt(6 mu Wd_i)``), is::

    d tau / d e = diag(a_i c_i wv) + ts_i (kappa_i - a_i c_i / 3) (wv L)(wv L)^T
                  - gamma_i (wv d)(wv d - ts_i S_i / 3 wv L)^T,
    gamma_i = 3 mu beta Y_i a_i^2 / sbar_i^3  (0 on an elastic point).

With ``de_k / du = n_k^T (du_j - du_i)`` the tangent K = -d(V f)/du is the elastic LPS
form of :func:`peridynamics.families.lps.tangent.lps_tangent` with the bond stiffness
``wv a_i c_i + wvf a_j c_j``, the bond force T_k of the plastic force pass, and the
point-wise rank-one products of ``Bw_i = d(sum wv L e)/du`` and ``D_i = d(sum wv d e)/du``
(rows per point, columns per dof; ``d`` held fixed in D)::

    K_pt = Bw^T diag(V ts (kappa - a c / 3)) Bw - D^T diag(V gamma) (D - diag(ts S / 3) Bw).

On an elastic point it is the elastic LPS tangent (``ts (kappa - a / 3) = k_theta``).
The plastic term is symmetric when ``S_i = -sum wv ep L`` vanishes (a deviatoric plastic
extension, as the radial return keeps it while no bond breaks). Checked against the
finite-difference tangent and central differences of the force in
tests/unit/test_lps_plasticity_static.py.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.families.lps.tangent import bond_blocks
from peridynamics.kernels import reference_lps_plasticity as twins

if TYPE_CHECKING:
    from peridynamics.state import State


def _rows(
    values: NDArray[np.float64],
    nv: NDArray[np.float64],
    bi: NDArray[np.intp],
    bj: NDArray[np.intp],
    n: int,
) -> sp.csr_matrix:
    """(n, n d) CSR: row i holds ``sum_k values_k n_k^T`` at the dofs of j and its
    negative at the dofs of i (the derivative of ``sum_k values_k e_k`` of point i)."""
    d = nv.shape[1]
    comp = np.arange(d)
    g = values[:, None] * nv
    rows = np.repeat(bi, d)
    cols_j = (bj[:, None] * d + comp[None, :]).ravel()
    cols_i = (bi[:, None] * d + comp[None, :]).ravel()
    return sp.coo_matrix(
        (
            np.concatenate([g.ravel(), -g.ravel()]),
            (np.concatenate([rows, rows]), np.concatenate([cols_j, cols_i])),
        ),
        shape=(n, n * d),
    ).tocsr()


def plastic_lps_tangent(
    model: Any, state: State, ep_all: NDArray[np.float64], q: NDArray[np.float64]
) -> sp.csr_matrix:
    """Consistent tangent K = -d(V f)/du (N/m), shape (3 n, 3 n), CSR, at ``state.u``
    with the committed history (module docstring).

    Parameters
    ----------
    model : PlasticLPSModel
        Serial: every point owns its family (no ghost rows).
    state : State
        Reads ``u`` (n, 3) (m) and ``intact``; changes nothing.
    ep_all : (n_bonds,) float
        The committed plastic extension (m).
    q : (n,) float
        The committed equivalent plastic strain.
    """
    b, p = model.bonds, model.plasticity
    n = model.cloud.n_points
    if len(b.offsets) - 1 != n:
        raise NotImplementedError("the plastic LPS tangent needs every family (no ghosts)")
    x, u, intact = model.cloud.x, state.u, state.intact
    wv_all, ts, cd, a = (
        model.omega_volume, model.theta_scale, model.dilatation_coef, model.extension_coef,
    )  # fmt: skip
    theta, scale, _ = twins.return_map(
        x, u, b.bond_i, b.bond_j, b.bond_length, wv_all, intact, ts, a, ep_all, q,
        model.shear, p.yield_stress, p.hardening_modulus,
    )  # fmt: skip
    g_all, _, _ = twins.pair_coefficients(
        x, u, b.bond_i, b.bond_j, b.bond_length, wv_all, model.omega_volume_far, intact,
        theta, cd, a, model.reverse, ep_all, scale,
    )  # fmt: skip
    keep = np.flatnonzero(intact)
    bi = b.bond_i[keep].astype(np.intp)
    bj = b.bond_j[keep].astype(np.intp)
    length, wv, wvf = b.bond_length[keep], wv_all[keep], model.omega_volume_far[keep]
    y = x[bj] - x[bi] + u[bj] - u[bi]
    r = np.sqrt(np.einsum("ij,ij->i", y, y))
    eta = u[bj] - u[bi]
    e = np.einsum("ij,ij->i", eta, 2.0 * (x[bj] - x[bi]) + eta) / (r + length)
    nv = y / r[:, None]
    dev = e - theta[bi] * length / 3.0 - ep_all[keep]  # d_k of the owner
    # the return of every point: Y, sbar, gamma
    s_sum = np.bincount(bi, wv * dev * length, minlength=n)
    wd = 0.5 * a * np.bincount(bi, wv * dev * dev, minlength=n)
    sbar = np.sqrt(6.0 * model.shear * np.maximum(wd, 0.0))
    mu3, hard = 3.0 * model.shear, p.hardening_modulus
    yielded = scale < 1.0
    big_y = p.yield_stress + hard * q
    safe = np.where(yielded, sbar, 1.0)
    gamma = np.where(yielded, mu3 * (mu3 / (mu3 + hard)) * big_y * a**2 / safe**3, 0.0)
    # bond part: axial stiffness and the geometric term T_k / r_k = g_k of the force pass
    vol = model.cloud.volume
    k_ext = wv * a[bi] * scale[bi] + wvf * a[bj] * scale[bj]
    nn = nv[:, :, None] * nv[:, None, :]
    h = k_ext[:, None, None] * nn + g_all[keep][:, None, None] * (np.eye(3)[None] - nn)
    h *= vol[bi][:, None, None]
    k_bond = bond_blocks(h, bi, bj, 3 * n)
    # point part: the dilatation and the derivative of the return factor
    bw = _rows(wv * length, nv, bi, bj, n)
    k_pt = bw.T @ sp.diags(vol * ts * (cd + a * (1.0 - scale) / 3.0)) @ bw
    if yielded.any():
        dd = _rows(wv * dev, nv, bi, bj, n)
        k_pt = k_pt - dd.T @ sp.diags(vol * gamma) @ (dd - sp.diags(ts * s_sum / 3.0) @ bw)
    k = sp.csr_matrix(k_bond + k_pt)
    k.sum_duplicates()
    return k
