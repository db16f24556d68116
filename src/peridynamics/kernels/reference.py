"""Plain NumPy twins of the Numba kernels. Used by tests and as the benchmark baseline.

They take a half or full directed bond list given as flat arrays ``bond_i``,
``bond_j`` (n_bonds,) and never loop in Python over points or bonds.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F = NDArray[np.float64]


def bond_vectors(x: F, u: F, bond_i: NDArray, bond_j: NDArray) -> F:
    """Deformed bond vectors xi + eta, shape (n_bonds, dim)."""
    return (x[bond_j] - x[bond_i]) + (u[bond_j] - u[bond_i])


def stretch(x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F) -> F:
    """Bond stretch s = (|xi + eta| - |xi|) / |xi|, shape (n_bonds,)."""
    r = np.linalg.norm(bond_vectors(x, u, bond_i, bond_j), axis=1)
    return (r - length) / length


def force(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F, stiffness: F, intact: NDArray
) -> F:
    """Bond-based force density (N/m^3), shape (n_points, dim), without breaking."""
    e = bond_vectors(x, u, bond_i, bond_j)
    r = np.linalg.norm(e, axis=1)
    g = stiffness * intact * ((r - length) / length) / r
    out = np.empty_like(x)
    for c in range(x.shape[1]):  # loop over the (<= 3) components only
        out[:, c] = np.bincount(bond_i, weights=g * e[:, c], minlength=len(x))
    return out


def force_half_list(
    x: F, u: F, pair_i: NDArray, pair_j: NDArray, length: F, stiff_ij: F, stiff_ji: F
) -> F:
    """Best plain-NumPy version: half list (i < j), one scatter per direction."""
    e = (x[pair_j] - x[pair_i]) + (u[pair_j] - u[pair_i])
    r = np.sqrt(np.einsum("ij,ij->i", e, e))
    g = ((r - length) / length) / r
    out = np.empty_like(x)
    n = len(x)
    for c in range(x.shape[1]):
        ge = g * e[:, c]
        out[:, c] = np.bincount(pair_i, ge * stiff_ij, n) - np.bincount(pair_j, ge * stiff_ji, n)
    return out


def strain_energy_density(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F, stiffness: F, intact: NDArray
) -> F:
    """W_i = 1/4 sum stiffness mu s^2 |xi| (J/m^3), shape (n_points,)."""
    s = stretch(x, u, bond_i, bond_j, length)
    w = np.bincount(bond_i, stiffness * intact * s * s * length, minlength=len(x))
    return np.asarray(0.25 * w, dtype=np.float64)


def damage(bond_i: NDArray, bond_volume: F, intact: NDArray, n_points: int) -> F:
    """phi_i = 1 - sum mu V / sum V, shape (n_points,)."""
    tot = np.bincount(bond_i, bond_volume, n_points)
    lost = np.bincount(bond_i, bond_volume * (1 - np.asarray(intact, dtype=float)), n_points)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(tot > 0, lost / tot, 0.0)


def fdm_force_1d(u: F, coef: float, inv_dx: float) -> tuple[F, F]:
    """NumPy twin of :func:`peridynamics.kernels.fdm.fdm_force_1d`: the force (n, 1)
    coef (u_{i+1} - 2 u_i + u_{i-1}) with free ends and the largest tensile
    (u_{i+1} - u_i) inv_dx per node (n,)."""
    du = np.diff(u[:, 0])
    f = np.zeros(len(u))
    f[:-1] += du
    f[1:] -= du
    strain = du * inv_dx
    ms = np.zeros(len(u))
    ms[:-1] = strain
    ms[1:] = np.maximum(ms[1:], strain)
    return (coef * f)[:, None], np.maximum(ms, 0.0)


def viscous_force(
    x: F,
    u: F,
    v: F,
    bond_i: NDArray,
    bond_j: NDArray,
    length: F,
    weight: F,
    intact: NDArray,
    lin: float,
    quad: float,
) -> F:
    """NumPy twin of :func:`peridynamics.kernels.viscous.add_viscous_force` (returns the
    viscous force density alone, shape (n, dim))."""
    e = bond_vectors(x, u, bond_i, bond_j)
    r = np.linalg.norm(e, axis=1)
    n = e / r[:, None]
    zeta = np.sum((v[bond_j] - v[bond_i]) * n, axis=1) / length
    f = weight * intact * (lin * zeta + quad * zeta * np.abs(zeta))
    out = np.zeros_like(x)
    np.add.at(out, bond_i, f[:, None] * n)
    return out


def sed_update(
    x: F,
    u: F,
    bond_i: NDArray,
    bond_j: NDArray,
    length: F,
    stiffness0: F,
    intact: NDArray,
    w_a: F,
    w_c: F,
    n_levels: int,
    residual: float,
    level: NDArray,
    tensile_only: bool = False,
) -> tuple[F, NDArray, F, F]:
    """NumPy twin of :func:`peridynamics.kernels.sed.sed_update`: returns (energy (n,),
    new level (n,), factor (n,), stiffness (n_bonds,))."""
    s = stretch(x, u, bond_i, bond_j, length)
    energy = np.zeros(len(x))
    counted = intact * (s > 0) if tensile_only else intact
    np.add.at(energy, bond_i, 0.25 * stiffness0 * counted * s**2 * length)
    band = np.floor(n_levels * (energy - w_a) / (w_c - w_a)).astype(np.int64)
    new = np.where(
        energy < w_a, 0, np.where(energy < w_c, np.minimum(1 + band, n_levels), n_levels + 1)
    )
    lev = np.maximum(level, new)
    factor = np.where(lev == 0, 1.0, (n_levels + 1 - lev) / n_levels)
    factor = np.where(lev == n_levels + 1, residual, factor)
    return energy, lev, factor, stiffness0 * 0.5 * (factor[bond_i] + factor[bond_j])
