"""Analytic tangent stiffness of the bond-based PMB force model.

The PMB force density of point i (:mod:`peridynamics.kernels.bond_based`) is a sum over
the directed bonds k = (i, j) of its family,

    f_i = sum_k g_k (1/|xi_k| - 1/|y_k|) y_k,     y_k = xi_k + u_j - u_i,

with ``g_k = stiffness_k mu_k`` (N/m^3 per unit stretch: c beta V_j lambda times the
bond status). The bond's own force is ``g s y/|y|`` with the stretch
``s = |y|/|xi| - 1``, so its derivative with respect to the bond vector is

    A_k = d f_k / d y_k = g_k [ (1/|xi_k| - 1/|y_k|) I + y_k y_k^T / |y_k|^3 ],

the second term the material (axial) stiffness g/|xi| e e^T plus, together with the
first, the geometric (initial-stress) term. Since ``y_k`` depends on ``+u_j`` and
``-u_i``, the tangent K = -d(V f)/du (N/m) has the blocks

    K_ij = -V_i A_k   (j a neighbour of i),        K_ii = V_i sum_k A_k.

Each point's row gathers only its own family: the directed list stores (i, j) and
(j, i) separately and the family sum of the kernel already is the whole force on i, so
no factor 1/2 or 2 enters. K is symmetric when ``V_i g_ij = V_j g_ji`` (symmetric
partial volumes, surface-correction factors and bond status, as built here), and
``K u = V (f(0) - f(u))`` to first order; at u = 0 it is the linear PMB stiffness
(Silling 2000, linearised micromodulus tensor c xi xi^T / |xi|^3).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

if TYPE_CHECKING:
    from peridynamics.state import State


class BondStiffnessModel(Protocol):
    """What the tangent reads: the bonds (CSR, with ``bond_i``, ``bond_xi``), the cloud
    (``volume``, ``n_points``, ``dim``), the bond stiffness g (n_bonds,) and 1/|xi|
    (n_bonds,); a :class:`~peridynamics.families.pmb.force.PMBForceModel` or the bonds of
    an interface between bodies."""

    @property
    def bonds(self) -> Any: ...

    @property
    def cloud(self) -> Any: ...

    @property
    def stiffness(self) -> NDArray[np.float64]: ...

    @property
    def inv_length(self) -> NDArray[np.float64]: ...


def bond_jacobians(
    force_model: BondStiffnessModel, u: NDArray[np.float64], intact: NDArray[np.uint8]
) -> NDArray[np.float64]:
    """Per-bond derivative A_k = d f_k / d y_k (N/m^4), shape (n_bonds, dim, dim).

    Parameters
    ----------
    force_model : BondStiffnessModel
        Supplies the bonds, the bond stiffness g (n_bonds,) and 1/|xi| (n_bonds,).
    u : (n, dim) displacement (m).
    intact : (n_bonds,) uint8 bond status.

    Returns
    -------
    (n_bonds, dim, dim) float64, zero for broken bonds.
    """
    b = force_model.bonds
    i, j = b.bond_i, b.bond_j
    y = b.bond_xi + (u[j] - u[i])  # (nb, d), m
    r = np.sqrt(np.einsum("kd,kd->k", y, y))
    g = force_model.stiffness * intact
    a = g * (force_model.inv_length - 1.0 / r)  # coefficient of I (N/m^4)
    c = g / (r * r * r)  # coefficient of y y^T (N/m^6)
    d = y.shape[1]
    out = c[:, None, None] * y[:, :, None] * y[:, None, :]
    out[:, np.arange(d), np.arange(d)] += a[:, None]
    return out


def pmb_tangent(force_model: BondStiffnessModel, state: State) -> sp.csr_matrix:
    """Tangent stiffness K = -d(V f)/du of the PMB force (N/m) at ``state.u``.

    Assembled with NumPy from the per-bond Jacobians (no Python loop over bonds or
    points); see the module docstring for the blocks.

    Parameters
    ----------
    force_model : BondStiffnessModel
    state : State
        Reads ``u`` (n, dim) (m) and ``intact`` (n_bonds,).

    Returns
    -------
    scipy.sparse.csr_matrix
        Shape (n dim, n dim), row/column ``i * dim + a`` for component a of point i;
        symmetric up to round-off, positive semi-definite at u = 0.
    """
    b = force_model.bonds
    cloud = force_model.cloud
    n, d = cloud.n_points, cloud.dim
    n_own = len(b.offsets) - 1
    A = bond_jacobians(force_model, state.u, state.intact)
    vol_i = cloud.volume[b.bond_i]
    blocks = vol_i[:, None, None] * A  # V_i A_k (N/m)
    comp = np.arange(d)
    # neighbour blocks K_ij = -V_i A_k, only for bonds that carry stiffness
    keep = np.flatnonzero((force_model.stiffness != 0) & (state.intact != 0))
    bi = b.bond_i[keep].astype(np.int64)
    bj = b.bond_j[keep].astype(np.int64)
    rows_off = np.broadcast_to((bi[:, None] * d + comp)[:, :, None], (len(keep), d, d))
    cols_off = np.broadcast_to((bj[:, None] * d + comp)[:, None, :], (len(keep), d, d))
    # diagonal blocks K_ii = V_i sum_k A_k: a segmented sum over the CSR families
    starts = b.offsets[:-1]
    nonempty = np.flatnonzero(np.diff(b.offsets) > 0)
    diag = np.zeros((n_own, d, d))
    if len(nonempty):
        diag[nonempty] = np.add.reduceat(blocks, starts[nonempty], axis=0)
    own = np.arange(n_own, dtype=np.int64)
    rows_diag = np.broadcast_to((own[:, None] * d + comp)[:, :, None], (n_own, d, d))
    cols_diag = np.broadcast_to((own[:, None] * d + comp)[:, None, :], (n_own, d, d))
    rows = np.concatenate([rows_diag.ravel(), rows_off.ravel()])
    cols = np.concatenate([cols_diag.ravel(), cols_off.ravel()])
    data = np.concatenate([diag.ravel(), -blocks[keep].ravel()])
    size = n * d
    return sp.csr_matrix(sp.coo_matrix((data, (rows, cols)), shape=(size, size)))
