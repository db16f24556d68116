"""Energy-method surface correction factors (Madenci & Oterkus 2014), recomputed here."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.geometry import PointCloud, box, rectangle

E, RHO = 70e9, 2700.0


def my_factors(cloud, bonds, raw_stiffness, w_inf, strain=1e-3):
    """lambda_k,i = W_inf / W_k,i under uniaxial (small) strain along k, with the
    linearised stretch s = xi . eta / |xi|^2; G_k = mean over ends;
    G = (sum_k (n_k / G_k)^2)^(-1/2)."""
    x = cloud.x
    n, dim = x.shape
    acc = np.zeros(bonds.n_bonds)
    for k in range(dim):
        u = np.zeros_like(x)
        u[:, k] = strain * x[:, k]
        eta = u[bonds.bond_j] - u[bonds.bond_i]
        xi = x[bonds.bond_j] - x[bonds.bond_i]
        s = np.einsum("ij,ij->i", xi, eta) / bonds.bond_length**2
        w = 0.25 * np.bincount(bonds.bond_i, raw_stiffness * s**2 * bonds.bond_length, n)
        lam = w_inf / w
        g_k = 0.5 * (lam[bonds.bond_i] + lam[bonds.bond_j])
        acc += (bonds.bond_xi[:, k] / bonds.bond_length / g_k) ** 2
    return acc**-0.5


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("profile", ["constant", "conical"])
def test_correction_factors_match_independent_recomputation(dim, profile):
    if dim == 2:
        base = rectangle((0.012, 0.009), 1e-3, thickness=1e-3)
    else:
        base = box((0.007, 0.006, 0.006), 1e-3)
    rng = np.random.default_rng(dim)
    cloud = PointCloud(
        x=base.x + rng.uniform(-1e-4, 1e-4, base.x.shape),
        volume=base.volume,
        spacing=base.spacing,
        cross_section=base.cross_section,
        plane=base.plane,
    )
    bonds = build_bonds(cloud, 3.015e-3)
    mat = BondBasedMaterial(E, RHO, profile=profile)
    model = Evaluator(cloud, bonds, mat, surface_correction=True)
    raw = mat.bond_stiffness(cloud, bonds, corrected=False)
    w_inf = mat.uniaxial_energy_density(1e-3, dim, bonds.horizon, cloud.cross_section, cloud.plane)
    mine = my_factors(cloud, bonds, raw, w_inf)
    np.testing.assert_allclose(model.bonds.bond_correction, mine, rtol=1e-6)
    np.testing.assert_allclose(model.stiffness, raw * mine, rtol=1e-6)
    rev = bonds.reverse_index()
    np.testing.assert_allclose(
        model.bonds.bond_correction, model.bonds.bond_correction[rev], rtol=1e-14
    )


def test_interior_factor_is_continuum_over_lattice_energy():
    """Deep inside a regular grid every lambda is W_inf / W_lattice, so is every G."""
    cloud = rectangle((0.03, 0.03), 1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    model = Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), surface_correction=True)
    # lattice sum of beta * cos^4 * r (units of dx) vs its continuum (3 pi / 4) m^3 / 3
    m, lattice = 3.015, 0.0
    for a in range(-4, 5):
        for b in range(-4, 5):
            r = np.hypot(a, b)
            if 0 < r <= m:
                lattice += min(1.0, m - r + 0.5) * (a / r) ** 4 * r
    ratio = (np.pi / 4 * m**3) / lattice
    x = cloud.x
    deep = np.all((x > 2 * 3.015e-3) & (x < 0.03 - 2 * 3.015e-3), axis=1)
    mask = deep[bonds.bond_i]
    # the calibration uses the linearised stretch: no geometric-nonlinearity bias
    np.testing.assert_allclose(model.bonds.bond_correction[mask], ratio, rtol=1e-10)
    assert np.ptp(model.bonds.bond_correction[mask]) < 1e-9
