"""Analytic tangent stiffness of the LPS force model (:mod:`peridynamics.families.lps.force`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

if TYPE_CHECKING:
    from peridynamics.state import State


def bond_blocks(h: NDArray[np.float64], bi: NDArray, bj: NDArray, size: int) -> sp.csr_matrix:
    """The bond part of a tangent: each bond's block ``h`` (nb, d, d) (N/m) at rows of
    point ``bi`` and columns of ``bj`` with a minus sign, and at the columns of ``bi``
    with a plus sign; CSR (size, size), duplicates summed."""
    d = h.shape[1]
    comp = np.arange(d)
    rr = (bi[:, None, None] * d + comp[None, :, None]) * np.ones((1, 1, d), dtype=np.intp)
    cc_j = (bj[:, None, None] * d + comp[None, None, :]) * np.ones((1, d, 1), dtype=np.intp)
    cc_i = (bi[:, None, None] * d + comp[None, None, :]) * np.ones((1, d, 1), dtype=np.intp)
    return sp.coo_matrix(
        (
            np.concatenate([-h.ravel(), h.ravel()]),
            (
                np.concatenate([rr.ravel(), rr.ravel()]),
                np.concatenate([cc_j.ravel(), cc_i.ravel()]),
            ),
        ),
        shape=(size, size),
    ).tocsr()


def lps_tangent(
    model: Any, state: State, thermal_extension: np.ndarray | None = None
) -> sp.csr_matrix:
    """Analytic tangent K = -d(V f)/du at ``state`` (N/m), shape (n dim, n dim), CSR.

    With per intact bond k = (i, j) the deformed direction n_k = y_k / r_k, the
    scalar ``T_k = (wv_k cd_i theta_i + wvf_k cd_j theta_j) L_k + (wv_k a_i +
    wvf_k a_j) e_k`` and ``f_i = sum_k T_k n_k``:

    * bond part: ``H_k = (wv_k a_i + wvf_k a_j) n n^T + T_k (I - n n^T) / r_k``,
      added as ``-V_i H_k`` to block (i, j) and ``+V_i H_k`` to block (i, i);
    * dilatation part: ``k_theta B^T diag(V) B`` with B = d theta / du (n, n dim),
      ``B[i, j] = ts_i wv_k L_k n_k^T``, ``B[i, i] = -sum_k ts_i wv_k L_k n_k^T``
      (the bond part is symmetric because ``V_i wvf_(i,j) = V_j wv_(j,i)``).

    Reads ``state.u`` and ``state.intact``; the dilatation is recomputed from u.
    ``thermal_extension`` (n_bonds,) (m), optional: subtracted from every extension
    e_k (thermal expansion, :mod:`peridynamics.families.lps.thermal`; its derivative
    is e's). Serial models only: every point must own its family (no ghost rows).
    """

    b = model.bonds
    d = model.dim
    n_all = model.cloud.n_points
    if len(b.offsets) - 1 != n_all:
        raise NotImplementedError("the analytic LPS tangent needs every family (no ghosts)")
    x, u = model.cloud.x, state.u
    keep = np.flatnonzero(state.intact)
    bi = b.bond_i[keep].astype(np.intp)
    bj = b.bond_j[keep].astype(np.intp)
    length = b.bond_length[keep]
    wv = model.omega_volume[keep]
    wvf = model.omega_volume_far[keep]
    xi = x[bj] - x[bi]
    eta = u[bj] - u[bi]
    y = xi + eta
    r = np.sqrt(np.einsum("ij,ij->i", y, y))
    e = np.einsum("ij,ij->i", eta, 2.0 * xi + eta) / (r + length)
    if thermal_extension is not None:
        e = e - thermal_extension[keep]
    nv = y / r[:, None]
    ts = model.theta_scale
    theta = ts * np.bincount(bi, wv * length * e, minlength=n_all)
    cd, a = model.dilatation_coef, model.extension_coef
    vol = model.cloud.volume
    k_ext = wv * a[bi] + wvf * a[bj]
    big_t = (wv * cd[bi] * theta[bi] + wvf * cd[bj] * theta[bj]) * length + k_ext * e
    nn = nv[:, :, None] * nv[:, None, :]
    eye = np.eye(d)[None, :, :]
    h = k_ext[:, None, None] * nn + (big_t / r)[:, None, None] * (eye - nn)
    h *= vol[bi][:, None, None]
    comp = np.arange(d)
    size = n_all * d
    k_bond = bond_blocks(h, bi, bj, size)
    # B = d theta / du, rows: points, columns: dofs
    g = (ts[bi] * wv * length)[:, None] * nv  # (nb, d)
    b_rows = np.repeat(bi, d)
    b_cols_j = (bj[:, None] * d + comp[None, :]).ravel()
    b_cols_i = (bi[:, None] * d + comp[None, :]).ravel()
    b_mat = sp.coo_matrix(
        (
            np.concatenate([g.ravel(), -g.ravel()]),
            (np.concatenate([b_rows, b_rows]), np.concatenate([b_cols_j, b_cols_i])),
        ),
        shape=(n_all, size),
    ).tocsr()
    k_dil = (b_mat.T @ sp.diags(model.k_theta * vol) @ b_mat).tocsr()
    k = sp.csr_matrix(k_bond + k_dil)
    k.sum_duplicates()
    return k
