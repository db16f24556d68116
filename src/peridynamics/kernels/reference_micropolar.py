"""NumPy twins of :mod:`peridynamics.kernels.micropolar` (the test oracle).

Vectorised over a directed bond list given as ``bond_i``, ``bond_j`` (n_bonds,); no
Python loop over points or bonds.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F = NDArray[np.float64]


def bond_measures(
    x: F, u: F, theta: F, bond_i: NDArray, bond_j: NDArray
) -> tuple[F, F, F, F, F, F]:
    """(n, n_perp, length, l, gamma, phi) of every bond: unit vectors (n_bonds, 2),
    length (m), axial stretch, shear deformation and relative rotation (n_bonds,)."""
    xi = x[bond_j] - x[bond_i]
    length = np.linalg.norm(xi, axis=1)
    n = xi / length[:, None]
    n_perp = np.stack([-n[:, 1], n[:, 0]], axis=1)
    d = u[bond_j] - u[bond_i]
    th = theta.reshape(-1)
    stretch = np.einsum("kd,kd->k", d, n) / length
    gamma = np.einsum("kd,kd->k", d, n_perp) / length - 0.5 * (th[bond_i] + th[bond_j])
    phi = th[bond_j] - th[bond_i]
    return n, n_perp, length, stretch, gamma, phi


def force(
    x: F,
    u: F,
    theta: F,
    bond_i: NDArray,
    bond_j: NDArray,
    weight: F,
    intact: NDArray,
    kn: float,
    kt: float,
    kphi: float,
) -> tuple[F, F]:
    """Force density (n, 2) (N/m^3) and moment density (n, 1) (N m/m^3)."""
    n, n_perp, length, s, g, phi = bond_measures(x, u, theta, bond_i, bond_j)
    w = weight * intact
    fb = (w * kn * s)[:, None] * n + (w * kt * g)[:, None] * n_perp
    npts = len(x)
    f = np.stack([np.bincount(bond_i, fb[:, c], minlength=npts) for c in range(2)], axis=1)
    mb = w * length * (0.5 * kt * g + kphi * phi)
    m = np.asarray(np.bincount(bond_i, mb, minlength=npts), dtype=np.float64)[:, None]
    return np.asarray(f, dtype=np.float64), m


def energy_density(
    x: F,
    u: F,
    theta: F,
    bond_i: NDArray,
    bond_j: NDArray,
    weight: F,
    intact: NDArray,
    kn: float,
    kt: float,
    kphi: float,
) -> F:
    """W_i (J/m^3), shape (n,)."""
    _, _, length, s, g, phi = bond_measures(x, u, theta, bond_i, bond_j)
    wb = weight * intact * length * (kn * s * s + kt * g * g + kphi * phi * phi)
    return np.asarray(0.25 * np.bincount(bond_i, wb, minlength=len(x)), dtype=np.float64)
