"""Plain NumPy twins of the tension-softening bond kernels
(:mod:`peridynamics.kernels.bond_softening`), used by tests.

They take a directed bond list as flat arrays ``bond_i``, ``bond_j`` (n_bonds,) and
never loop in Python over points or bonds. Per-point ``s0`` and ``sf`` (inf: never
softens) give the bond's peak stretch (s0_i + s0_j)/2 and failure stretch
(sf_i + sf_j)/2; ``r`` and ``beta`` place the knee of the envelope.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from peridynamics.kernels.reference import bond_vectors, stretch

F = NDArray[np.float64]


def envelope(s: F, s0: F | float, sf: F | float, r: float, beta: float) -> F:
    """g(s) (stretch units, force = stiffness g), shape like ``s``: s up to s0, linear to
    beta s0 at s1 = s0 + r (sf - s0), linear to 0 at sf, 0 beyond (s >= 0)."""
    s = np.asarray(s, dtype=np.float64)
    s0 = np.broadcast_to(np.asarray(s0, dtype=np.float64), s.shape)
    sf = np.broadcast_to(np.asarray(sf, dtype=np.float64), s.shape)
    with np.errstate(invalid="ignore", divide="ignore"):
        s1 = s0 + r * (sf - s0)
        first = s0 + (beta * s0 - s0) * ((s - s0) / (s1 - s0))
        second = beta * s0 * ((sf - s) / (sf - s1))
        g = np.where(s <= s1, first, second)
        g = np.where(s <= s0, s, g)
    return np.where(s >= sf, 0.0, g)


def factor(s: F, kappa: F, intact: NDArray, s0b: F, sfb: F, r: float, beta: float) -> F:
    """Stiffness factor h of each bond (n_bonds,) at stretch s with trial history
    max(kappa, s): 0 for a broken or failed bond, 1 in compression or up to s0, else
    g(kappa')/kappa'."""
    kap = np.maximum(kappa, s)
    with np.errstate(invalid="ignore", divide="ignore"):
        h = envelope(kap, s0b, sfb, r, beta) / kap
    h = np.where((s <= 0.0) | (kap <= s0b), 1.0, h)
    return np.where((np.asarray(intact) == 0) | (kap >= sfb), 0.0, h)


def _bond_params(bond_i: NDArray, bond_j: NDArray, s0: F, sf: F) -> tuple[F, F]:
    return 0.5 * (s0[bond_i] + s0[bond_j]), 0.5 * (sf[bond_i] + sf[bond_j])


def force(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F, stiffness: F, intact: NDArray,
    kappa: F, s0: F, sf: F, r: float, beta: float,
) -> tuple[F, F]:  # fmt: skip
    """Pure softening force density (N/m^3), shape (n, dim), and the largest tensile
    stretch of a load-carrying bond per point (n,), with the trial history
    max(kappa, s); nothing is committed."""
    n = len(x)
    e = bond_vectors(x, u, bond_i, bond_j)
    rr = np.linalg.norm(e, axis=1)
    s = (rr - length) / length
    s0b, sfb = _bond_params(bond_i, bond_j, s0, sf)
    h = factor(s, kappa, intact, s0b, sfb, r, beta)
    g = stiffness * h * s / rr
    out = np.empty_like(x)
    for c in range(x.shape[1]):  # the (<= 3) components only
        out[:, c] = np.bincount(bond_i, weights=g * e[:, c], minlength=n)
    alive = (np.asarray(intact) != 0) & (np.maximum(kappa, s) < sfb)
    smax = np.zeros(n)
    np.maximum.at(smax, bond_i, np.where(alive, np.maximum(s, 0.0), 0.0))
    return out, smax


def trial(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F, intact: NDArray, kappa: F,
    sf: F,
) -> tuple[F, NDArray]:  # fmt: skip
    """Trial history (n_bonds,): max(kappa, s) for intact bonds (kappa otherwise), and
    the bonds proposed to break (uint8): intact ones whose trial history reaches
    (sf_i + sf_j)/2."""
    s = stretch(x, u, bond_i, bond_j, length)
    on = np.asarray(intact) != 0
    kap = np.where(on, np.maximum(kappa, s), kappa)
    sfb = 0.5 * (sf[bond_i] + sf[bond_j])
    return kap, (on & (kap >= sfb)).astype(np.uint8)


def energy_density(
    x: F, u: F, bond_i: NDArray, bond_j: NDArray, length: F, stiffness: F, intact: NDArray,
    kappa: F, s0: F, sf: F, r: float, beta: float,
) -> F:  # fmt: skip
    """W_i = 1/4 sum_k stiffness_k h_k s_k^2 |xi_k| (J/m^3), shape (n,)."""
    s = stretch(x, u, bond_i, bond_j, length)
    s0b, sfb = _bond_params(bond_i, bond_j, s0, sf)
    h = factor(s, kappa, intact, s0b, sfb, r, beta)
    w = np.bincount(bond_i, stiffness * h * s * s * length, minlength=len(x))
    return np.asarray(0.25 * w, dtype=np.float64)
