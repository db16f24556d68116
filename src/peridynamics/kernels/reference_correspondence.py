"""NumPy twins of :mod:`peridynamics.kernels.correspondence` (the test oracle).

Written from the equations of that module, bond-vectorised with ``np.add.at`` and
``np.linalg.inv``, sharing no code with the Numba kernels.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]


def _bonds(
    bond_xi: F64,
    u: F64,
    offsets: NDArray[np.int64],
    bond_j: NDArray[np.int32],
    wv: F64,
    intact: NDArray[np.uint8],
) -> tuple[NDArray[np.intp], NDArray[np.intp], F64, F64]:
    """(owner i, neighbour j, weight w = wv * intact, deformed bond y) of every bond."""
    i = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    j = bond_j.astype(np.intp)
    return i, j, wv * intact, bond_xi + u[j] - u[i]


def prepass(
    bond_xi: F64,
    u: F64,
    offsets: NDArray[np.int64],
    bond_j: NDArray[np.int32],
    wv: F64,
    intact: NDArray[np.uint8],
    det_ref: F64,
    degenerate_ratio: float,
    mode: int,
    stab: F64,
) -> tuple[F64, F64, F64, F64, F64]:
    """(kinv, fgrad, sigma_s, omega0, active) of :func:`.correspondence.prepass`."""
    n = len(offsets) - 1
    d = u.shape[1]
    i, _, w, y = _bonds(bond_xi, u, offsets, bond_j, wv, intact)
    kmat = np.zeros((n, d, d))
    nmat = np.zeros((n, d, d))
    np.add.at(kmat, i, w[:, None, None] * bond_xi[:, :, None] * bond_xi[:, None, :])
    np.add.at(nmat, i, w[:, None, None] * y[:, :, None] * bond_xi[:, None, :])
    omega0 = np.bincount(i, w, minlength=n).astype(np.float64)
    det = np.linalg.det(kmat)
    active = ((det > degenerate_ratio * det_ref) & (det > 0)).astype(np.float64)
    safe = np.where(active[:, None, None] > 0, kmat, np.eye(d))
    kinv = np.linalg.inv(safe) * active[:, None, None]
    fgrad = np.einsum("nab,nbc->nac", nmat, kinv)
    fgrad[active == 0] = np.eye(d)
    sigma_s = np.zeros((n, d, d))
    if mode == 2:
        z = y - np.einsum("kab,kb->ka", fgrad[i], bond_xi)
        length = np.linalg.norm(bond_xi, axis=1)
        g = stab[i] * active[i] * w * np.einsum("ka,ka->k", bond_xi, z) / length**3
        np.add.at(sigma_s, i, g[:, None, None] * bond_xi[:, :, None] * bond_xi[:, None, :])
    return kinv, fgrad, sigma_s, omega0, active


def force(
    bond_xi: F64,
    u: F64,
    offsets: NDArray[np.int64],
    bond_j: NDArray[np.int32],
    wv: F64,
    intact: NDArray[np.uint8],
    amat: F64,
    fgrad: F64,
    stab: F64,
    mode: int,
) -> F64:
    """Force density (n, d) of :func:`.correspondence.force`, from the half force
    states T_i<xi> and T_j<-xi> (not the pair form of the kernel)."""
    n = len(offsets) - 1
    i, j, w, y = _bonds(bond_xi, u, offsets, bond_j, wv, intact)
    xi = bond_xi
    length = np.linalg.norm(xi, axis=1)

    def half(p: NDArray[np.intp], bond: F64, deformed: F64) -> F64:
        t = np.einsum("kab,kb->ka", amat[p], bond)
        z = deformed - np.einsum("kab,kb->ka", fgrad[p], bond)
        if mode == 1:
            t = t + stab[p][:, None] * z
        elif mode == 2:
            t = t + (stab[p] * np.einsum("ka,ka->k", bond, z) / length**3)[:, None] * bond
        return np.asarray(t)

    t_pair = half(i, xi, y) - half(j, -xi, -y)
    out = np.zeros((n, u.shape[1]))
    np.add.at(out, i, w[:, None] * t_pair)
    return out


def stabilization_energy(
    bond_xi: F64,
    u: F64,
    offsets: NDArray[np.int64],
    bond_j: NDArray[np.int32],
    wv: F64,
    intact: NDArray[np.uint8],
    fgrad: F64,
    stab: F64,
    mode: int,
) -> F64:
    """Stabilisation energy density (n,) of :func:`.correspondence.stabilization_energy`."""
    n = len(offsets) - 1
    if mode == 0:
        return np.zeros(n)
    i, _, w, y = _bonds(bond_xi, u, offsets, bond_j, wv, intact)
    z = y - np.einsum("kab,kb->ka", fgrad[i], bond_xi)
    if mode == 1:
        e = w * np.einsum("ka,ka->k", z, z)
    else:
        length = np.linalg.norm(bond_xi, axis=1)
        e = w * np.einsum("ka,ka->k", bond_xi, z) ** 2 / length**3
    return np.asarray(0.5 * stab * np.bincount(i, e, minlength=n))
