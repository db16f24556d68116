"""NumPy twins of :mod:`peridynamics.kernels.lps_plasticity` (the test oracles): the same
return map and force of the elastic-plastic LPS, vectorised over the bond list (the
deviatoric energy summed directly, not expanded)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from peridynamics.kernels.reference_lps import bond_extension

F64 = NDArray[np.float64]


def return_map(
    x: F64, u: F64, bond_i: NDArray, bond_j: NDArray, length: F64, wv: F64, intact: NDArray,
    theta_scale: F64, a: F64, ep: F64, q: F64, shear: float, yield_stress: float,
    hardening: float,
) -> tuple[F64, F64, F64]:  # fmt: skip
    """(theta, c, q_trial), each (n,): arguments as
    :func:`peridynamics.kernels.lps_plasticity.plastic_prepass_3d` with the owner
    ``bond_i`` of every bond."""
    n = len(q)
    _, _, e = bond_extension(x, u, bond_i, bond_j, length)
    w = intact * wv
    theta = theta_scale[:n] * np.bincount(bond_i, w * length * e, minlength=n)
    de = e - theta[bond_i] * length / 3.0 - ep
    wd = 0.5 * a[:n] * np.bincount(bond_i, w * de * de, minlength=n)
    sbar = np.sqrt(6.0 * shear * wd)
    f = sbar - (yield_stress + hardening * q)
    dq = np.where(f > 0, f / (3.0 * shear + hardening), 0.0)
    scale = np.where(f > 0, 1.0 - 3.0 * shear * dq / np.where(f > 0, sbar, 1.0), 1.0)
    return np.asarray(theta), np.asarray(scale), np.asarray(q + dq)


def pair_coefficients(
    x: F64, u: F64, bond_i: NDArray, bond_j: NDArray, length: F64, wv: F64, wvf: F64,
    intact: NDArray, theta: F64, cd: F64, a: F64, reverse: NDArray, ep: F64, scale: F64,
) -> tuple[F64, F64, F64]:  # fmt: skip
    """(g (n_bonds,) N/m^4 with f_i = sum_k g_k y_k, deformed bonds y (n_bonds, 3), trial
    plastic extension (n_bonds,)); arguments as
    :func:`peridynamics.kernels.lps_plasticity.plastic_force_3d`."""
    y, r, e = bond_extension(x, u, bond_i, bond_j, length)
    c = 1.0 - scale
    p = ep + intact * c[bond_i] * (e - theta[bond_i] * length / 3.0 - ep)
    p_far = ep[reverse] + intact * c[bond_j] * (e - theta[bond_j] * length / 3.0 - ep[reverse])
    t = (
        (wv * cd[bond_i] * theta[bond_i] + wvf * cd[bond_j] * theta[bond_j]) * length
        + (wv * a[bond_i] + wvf * a[bond_j]) * e
        - (wv * a[bond_i] * p + wvf * a[bond_j] * p_far)
    )
    return np.asarray(intact * t / r), y, np.asarray(p)


def force(
    x: F64, u: F64, bond_i: NDArray, bond_j: NDArray, length: F64, wv: F64, wvf: F64,
    intact: NDArray, theta: F64, cd: F64, a: F64, reverse: NDArray, ep: F64, scale: F64,
) -> tuple[F64, F64]:  # fmt: skip
    """(force density (n, 3) N/m^3, trial plastic extension (n_bonds,))."""
    g, y, p = pair_coefficients(
        x, u, bond_i, bond_j, length, wv, wvf, intact, theta, cd, a, reverse, ep, scale
    )
    out = np.zeros((len(scale), 3))
    np.add.at(out, bond_i, g[:, None] * y)
    return out, p


def energy_density(
    x: F64, u: F64, bond_i: NDArray, bond_j: NDArray, length: F64, wv: F64, intact: NDArray,
    theta_scale: F64, k_theta: float, a: F64, ep: F64, n_points: int,
) -> F64:  # fmt: skip
    """Free energy W_i = k_theta theta_i^2 / 2 + (a_i / 2) sum_k mu_k wv_k (e_k - ep_k)^2
    (J/m^3), shape (n_points,), at fixed (committed) plastic extension ``ep``."""
    _, _, e = bond_extension(x, u, bond_i, bond_j, length)
    w = intact * wv
    th = theta_scale[:n_points] * np.bincount(bond_i, w * length * e, minlength=n_points)
    d = e - ep
    s = np.bincount(bond_i, w * d * d, minlength=n_points)
    return np.asarray(0.5 * (k_theta * th * th + a[:n_points] * s), dtype=np.float64)
