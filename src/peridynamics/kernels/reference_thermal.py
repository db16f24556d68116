"""Plain NumPy twins of :mod:`peridynamics.kernels.thermal_expansion`.

They take the directed bond list as flat arrays ``bond_i``, ``bond_j`` (n_bonds,) and
never loop in Python over points or bonds; ``eps`` (n_all,) is the thermal strain of
every point and ``a_k = (eps_i + eps_j) / 2`` that of a bond.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from peridynamics.kernels.reference_lps import bond_extension

F = NDArray[np.float64]


def _gather(bond_i: NDArray, w: F, y: F, n_points: int) -> F:
    out = np.empty((n_points, y.shape[1]))
    for c in range(y.shape[1]):  # loop over the (<= 3) components only
        out[:, c] = np.bincount(bond_i, weights=w * y[:, c], minlength=n_points)
    return out


def mechanical_stretch(x: F, u: F, bond_i: NDArray, bond_j: NDArray, eps: F) -> F:
    """s_k - a_k (n_bonds,)."""
    y = (x[bond_j] - x[bond_i]) + (u[bond_j] - u[bond_i])
    length = np.linalg.norm(x[bond_j] - x[bond_i], axis=1)
    return np.asarray(np.linalg.norm(y, axis=1) / length - 1.0 - 0.5 * (eps[bond_i] + eps[bond_j]))


def pmb_force(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, stiffness: F, intact: NDArray, eps: F, n: int
) -> F:
    """f_i = sum_k stiffness_k mu_k (s_k - a_k) y_k / r_k, shape (n, dim)."""
    y = (x[bond_j] - x[bond_i]) + (u[bond_j] - u[bond_i])
    r = np.linalg.norm(y, axis=1)
    g = stiffness * intact * mechanical_stretch(x, u, bond_i, bond_j, eps) / r
    return _gather(bond_i, g, y, n)


def pmb_energy(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, stiffness: F, intact: NDArray, eps: F, n: int
) -> F:
    """W_i = 1/4 sum_k stiffness_k mu_k (s_k - a_k)^2 L_k, shape (n,)."""
    s = mechanical_stretch(x, u, bond_i, bond_j, eps)
    length = np.linalg.norm(x[bond_j] - x[bond_i], axis=1)
    return np.asarray(0.25 * np.bincount(bond_i, stiffness * intact * s * s * length, minlength=n))


def lps_extension(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F, eps: F
) -> tuple[F, F, F]:
    """(y, r, e - a L) of every bond."""
    y, r, e = bond_extension(x, u, bond_i, bond_j, length)
    return y, r, e - 0.5 * (eps[bond_i] + eps[bond_j]) * length


def lps_dilatation(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F, wv: F, intact: NDArray,
    theta_scale: F, eps: F, n: int,
) -> F:  # fmt: skip
    """theta_i = ts_i sum_k mu_k wv_k L_k (e_k - a_k L_k), shape (n,)."""
    _, _, e = lps_extension(x, u, bond_i, bond_j, length, eps)
    return np.asarray(theta_scale[:n] * np.bincount(bond_i, intact * wv * length * e, minlength=n))


def lps_force(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F, wv: F, wvf: F, intact: NDArray,
    theta: F, cd: F, a: F, eps: F, n: int,
) -> F:  # fmt: skip
    """The LPS force density with the mechanical extension, shape (n, dim)."""
    y, r, e = lps_extension(x, u, bond_i, bond_j, length, eps)
    bi, bj = bond_i, bond_j
    g = (
        intact
        * (
            (wv * cd[bi] * theta[bi] + wvf * cd[bj] * theta[bj]) * length
            + (wv * a[bi] + wvf * a[bj]) * e
        )
        / r
    )
    return _gather(bond_i, g, y, n)


def lps_energy(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F, wv: F, intact: NDArray,
    theta_scale: F, k_theta: float, a: F, eps: F, n: int,
) -> F:  # fmt: skip
    """W_i = k_theta theta_i^2 / 2 + (a_i / 2) sum_k mu_k wv_k (e_k - a_k L_k)^2."""
    _, _, e = lps_extension(x, u, bond_i, bond_j, length, eps)
    th = theta_scale[:n] * np.bincount(bond_i, intact * wv * length * e, minlength=n)
    w = np.bincount(bond_i, intact * wv * e * e, minlength=n)
    return np.asarray(0.5 * (k_theta * th * th + a[:n] * w))
