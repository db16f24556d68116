"""Energy-method surface correction for bond-based models (Madenci & Oterkus 2014, ch. 4).

For each coordinate direction ``k`` a uniform uniaxial strain ``eps`` along ``k`` is
applied (linearised bond stretch, so the factors do not depend on ``eps``); the point
strain-energy density ``W_k,i`` of the discrete model is compared
with the continuum value ``W_inf``: ``lambda_k,i = W_inf / W_k,i``. The bond factor in
direction ``k`` is the mean of its end points, ``G_k = (lambda_k,i + lambda_k,j) / 2``,
and the bond factor is the ellipse/ellipsoid interpolation over the bond direction n:

    G = [ sum_k (n_k / G_k)^2 ]^(-1/2)

This also removes the interior discretisation error of the chosen partial-volume rule
for uniaxial loading.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds


def energy_correction_factors(
    x: NDArray[np.float64],
    bonds: Bonds,
    stiffness: NDArray[np.float64],
    continuum_energy_density: float,
    strain: float = 1e-6,
) -> NDArray[np.float64]:
    """Per-bond correction factors, shape (n_bonds,).

    Parameters
    ----------
    x : (n_points, dim) reference positions (m).
    bonds : the bond list (its current correction is ignored).
    stiffness : (n_bonds,) uncorrected bond stiffness ``c(|xi|) * beta * V_j`` (N/m^3).
    continuum_energy_density : float
        Strain-energy density of the infinite body under uniaxial strain ``strain`` (J/m^3).
    """
    n, dim = x.shape
    xi, length = bonds.bond_xi, bonds.bond_length
    lam = np.empty((dim, n))
    for k in range(dim):  # one uniform-strain evaluation per direction
        # linearised stretch xi.eta/|xi|^2 of u = strain * x_k e_k: exact, so the factors
        # carry neither round-off (small strain) nor geometric nonlinearity (large strain)
        s = strain * (xi[:, k] / length) ** 2
        w = 0.25 * np.bincount(bonds.bond_i, stiffness * s * s * length, minlength=n)
        lam[k] = continuum_energy_density / w
    return bond_factors_from_point_ratios(bonds, lam)


def bond_factors_from_point_ratios(
    bonds: Bonds, ratios: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Bond factors G = [sum_k (n_k / G_k)^2]^(-1/2), G_k = (lambda_k,i + lambda_k,j)/2,
    shape (n_bonds,), from the per-direction point ratios ``ratios`` (dim, n_points)
    = W_inf / W_k,i of any model family (the shared step of the energy method)."""
    n_hat = bonds.bond_xi / bonds.bond_length[:, None]
    acc = np.zeros(bonds.n_bonds)
    for k in range(ratios.shape[0]):  # loop over the (<= 3) directions only
        g_k = 0.5 * (ratios[k][bonds.bond_i] + ratios[k][bonds.bond_j])
        acc += (n_hat[:, k] / g_k) ** 2
    return 1.0 / np.sqrt(acc)
