"""Plain NumPy twins of the LPS kernels in :mod:`peridynamics.kernels.lps`.

They take the directed bond list as flat arrays ``bond_i``, ``bond_j`` (n_bonds,) and
never loop in Python over points or bonds. Same notation and equations as the kernels;
``n_points`` is the number of rows of the per-point outputs.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F = NDArray[np.float64]


def bond_extension(x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F) -> tuple[F, F, F]:
    """Deformed bond vectors y (n_bonds, dim), their lengths r and extensions e = r - L
    (both (n_bonds,), m), e evaluated as eta.(2 xi + eta)/(r + L)."""
    xi = x[bond_j] - x[bond_i]
    eta = u[bond_j] - u[bond_i]
    y = xi + eta
    r = np.sqrt(np.einsum("ij,ij->i", y, y))
    e = np.einsum("ij,ij->i", eta, 2.0 * xi + eta) / (r + length)
    return y, r, e


def weighted_volume(bond_i: NDArray, length: F, wv: F, intact: NDArray, n_points: int) -> F:
    """m_i = sum_k mu_k wv_k L_k^2 (m^5), shape (n_points,)."""
    m = np.bincount(bond_i, intact * wv * length * length, minlength=n_points)
    return np.asarray(m, dtype=np.float64)


def dilatation(
    x: F,
    u: F,
    bond_i: NDArray,
    bond_j: NDArray,
    length: F,
    wv: F,
    intact: NDArray,
    theta_scale: F,
    n_points: int,
) -> F:
    """theta_i = ts_i sum_k mu_k wv_k L_k e_k, shape (n_points,)."""
    _, _, e = bond_extension(x, u, bond_i, bond_j, length)
    acc = np.bincount(bond_i, intact * wv * length * e, minlength=n_points)
    return np.asarray(theta_scale[:n_points] * acc, dtype=np.float64)


def force(
    x: F,
    u: F,
    bond_i: NDArray,
    bond_j: NDArray,
    length: F,
    wv: F,
    intact: NDArray,
    theta: F,
    cd: F,
    a: F,
    n_points: int,
    wv_far: F | None = None,
) -> tuple[F, F]:
    """LPS force density (n_points, dim) (N/m^3) and largest tensile stretch (n_points,)
    of an intact bond (0 when none is stretched). ``wv_far`` (n_bonds,): the bond
    weighted by the far point's influence function (``wvf`` of the kernels); ``wv``
    when omitted (symmetric weights)."""
    y, r, e = bond_extension(x, u, bond_i, bond_j, length)
    wvf = wv if wv_far is None else wv_far
    t = (wv * cd[bond_i] * theta[bond_i] + wvf * cd[bond_j] * theta[bond_j]) * length + (
        wv * a[bond_i] + wvf * a[bond_j]
    ) * e
    g = intact * t / r
    out = np.empty((n_points, x.shape[1]))
    for c in range(x.shape[1]):  # loop over the (<= 3) components only
        out[:, c] = np.bincount(bond_i, g * y[:, c], minlength=n_points)
    smax = np.zeros(n_points)
    np.maximum.at(smax, bond_i, intact * e / length)
    return out, smax


def energy_density(
    x: F,
    u: F,
    bond_i: NDArray,
    bond_j: NDArray,
    length: F,
    wv: F,
    intact: NDArray,
    theta_scale: F,
    k_theta: float,
    a: F,
    n_points: int,
) -> F:
    """W_i = k_theta theta_i^2 / 2 + (a_i / 2) sum_k mu_k wv_k e_k^2 (J/m^3), shape
    (n_points,)."""
    _, _, e = bond_extension(x, u, bond_i, bond_j, length)
    q = intact * wv
    th = theta_scale[:n_points] * np.bincount(bond_i, q * length * e, minlength=n_points)
    w = np.bincount(bond_i, q * e * e, minlength=n_points)
    return np.asarray(0.5 * (k_theta * th * th + a[:n_points] * w), dtype=np.float64)
