"""Plain NumPy twins of the point stress and strain kernels in
:mod:`peridynamics.kernels.stress`, used by tests.

They take the directed bond list as flat arrays ``bond_i``, ``bond_j`` (n_bonds,) and
never loop in Python over points or bonds; ``n_points`` is the number of rows of the
per-point outputs. Same notation and equations as the kernels.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from peridynamics.kernels.stress import DEGENERATE

F = NDArray[np.float64]


def virial_stress(x: F, u: F, bond_i: NDArray, bond_j: NDArray, g: F, n_points: int) -> F:
    """``sigma_i = 1/2 sum_k g_k y_k (x) xi_k`` (Pa), shape (n_points, d, d)."""
    xi = x[bond_j] - x[bond_i]
    y = xi + (u[bond_j] - u[bond_i])
    pair = 0.5 * g[:, None, None] * y[:, :, None] * xi[:, None, :]
    d = x.shape[1]
    out = np.zeros((n_points, d * d))
    flat = pair.reshape(len(g), d * d)
    for c in range(d * d):  # the (<= 9) components only
        out[:, c] = np.bincount(bond_i, flat[:, c], minlength=n_points)
    return out.reshape(n_points, d, d)


def deformation_gradient(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, w: F, intact: NDArray, n_points: int
) -> F:
    """``F_i = N_i K_i^-1`` (n_points, d, d), the identity where K_i is singular
    (``det K_i <= DEGENERATE (tr K_i / d)^d``)."""
    xi = x[bond_j] - x[bond_i]
    y = xi + (u[bond_j] - u[bond_i])
    q = (np.asarray(intact) != 0) * w
    d = x.shape[1]
    kk = np.zeros((n_points, d * d))
    nn = np.zeros((n_points, d * d))
    kb = (q[:, None, None] * xi[:, :, None] * xi[:, None, :]).reshape(-1, d * d)
    nb = (q[:, None, None] * y[:, :, None] * xi[:, None, :]).reshape(-1, d * d)
    for c in range(d * d):
        kk[:, c] = np.bincount(bond_i, kb[:, c], minlength=n_points)
        nn[:, c] = np.bincount(bond_i, nb[:, c], minlength=n_points)
    kmat = kk.reshape(n_points, d, d)
    nmat = nn.reshape(n_points, d, d)
    det = np.linalg.det(kmat)
    ok = det > DEGENERATE * (np.trace(kmat, axis1=1, axis2=2) / d) ** d
    out = np.broadcast_to(np.eye(d), (n_points, d, d)).copy()
    out[ok] = np.einsum("nab,nbc->nac", nmat[ok], np.linalg.inv(kmat[ok]))
    return out
