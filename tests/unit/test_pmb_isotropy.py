"""Isotropic bond-based families on a regular 3-D grid (``discretisation.isotropic_family``):
the lattice family's fourth moment, recomputed here from the grid offsets, becomes the
isotropic one, and an interior point's energy is the isotropic continuum's (E0, nu = 1/4,
Silling (2000)) under every uniform strain."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import yaml

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.deck.changed_defaults import notices
from peridynamics.deck.reader import parse_deck
from peridynamics.families.calibration import quartic_values
from peridynamics.families.pmb.isotropy import isotropy_coefficients
from peridynamics.geometry import box, rectangle

E, RHO = 70e9, 2700.0


def _family(m: float, rule: str, profile: str) -> tuple[np.ndarray, np.ndarray]:
    """Offsets (units of dx) and energy weights c(r) beta(r) r of a lattice family,
    written out here from the partial-volume formulas (Lu & Wang (2016), eq. 9; SED-PD
    (2021), eq. 11)."""
    k = int(np.ceil(m)) + 1
    xi, w = [], []
    for a, b, c in itertools.product(range(-k, k + 1), repeat=3):
        r = float(np.sqrt(a * a + b * b + c * c))
        if r == 0:
            continue
        if rule == "truncated":
            beta = 0.0 if r > m * (1 + 1e-9) else min(1.0, m - r + 0.5)
        else:
            beta = min(1.0, max(0.0, m + 0.5 - r)) if r < m + 0.5 else 0.0
        if beta <= 0:
            continue
        micro = 1.0 if profile == "constant" else max(0.0, 1.0 - r / m)
        xi.append((a, b, c))
        w.append(micro * beta * r)
    return np.asarray(xi, dtype=float), np.asarray(w)


def _moments(xi: np.ndarray, w: np.ndarray) -> tuple[float, float, float]:
    n = xi / np.linalg.norm(xi, axis=1)[:, None]
    return (
        float((w * n[:, 0] ** 4).sum()),
        float((w * n[:, 0] ** 2 * n[:, 1] ** 2).sum()),
        float((w * n[:, 0] ** 2 * n[:, 1] * n[:, 2]).sum()),
    )


@pytest.mark.parametrize("m", [3.015, 4.015])
@pytest.mark.parametrize("rule", ["truncated", "extended"])
@pytest.mark.parametrize("profile", ["constant", "conical"])
def test_lattice_family_gets_the_isotropic_fourth_moment(m, rule, profile):
    xi, w = _family(m, rule, profile)
    xxxx, xxyy, _ = _moments(xi, w)
    if (rule, m, profile) == ("truncated", 3.015, "constant"):  # the lattice: not 1/3
        assert xxyy / xxxx == pytest.approx(0.3680, abs=5e-4)
    lam = isotropy_coefficients(xi, w)
    g = 1.0 + quartic_values(xi / np.linalg.norm(xi, axis=1)[:, None]) @ lam
    xxxx_g, xxyy_g, xxyz_g = _moments(xi, w * g)
    assert xxyy_g / xxxx_g == pytest.approx(1.0 / 3.0, rel=1e-12)
    assert abs(xxyz_g) < 1e-12 * xxxx_g
    assert (w * g).sum() == pytest.approx(w.sum(), rel=1e-12)  # the second moment kept
    assert 0.7 < g.min() <= g.max() < 1.3


def _interior_energy(model, bonds, deep, strain):
    """1/4 sum_k stiffness_k (n.eps.n)^2 |xi| (J/m^3) of the points ``deep``."""
    n = bonds.bond_xi / bonds.bond_length[:, None]
    s = np.einsum("ki,ij,kj->k", n, strain, n)
    w = 0.25 * np.bincount(bonds.bond_i, model.stiffness * s**2 * bonds.bond_length)
    return w[deep]


def test_interior_energy_is_the_isotropic_continuum_under_every_strain():
    cloud = box((0.016, 0.016, 0.016), 1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    x = cloud.x
    deep = np.flatnonzero(np.all((x > 6.1e-3) & (x < 0.016 - 6.1e-3), axis=1))
    assert len(deep) >= 8
    lam = mu = E / 2.5  # nu = 1/4: lambda = mu = E / (2 (1 + nu))
    rng = np.random.default_rng(3)
    iso = Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), surface_correction=True)
    cubic = Evaluator(
        cloud, bonds, BondBasedMaterial(E, RHO, isotropic_family=False), surface_correction=True
    )
    worst_cubic = 0.0
    for _ in range(5):
        a = rng.normal(size=(3, 3)) * 1e-4
        eps = 0.5 * (a + a.T)
        w_cont = mu * np.sum(eps * eps) + 0.5 * lam * np.trace(eps) ** 2
        np.testing.assert_allclose(_interior_energy(iso, bonds, deep, eps), w_cont, rtol=1e-9)
        gap = np.abs(_interior_energy(cubic, bonds, deep, eps) / w_cont - 1.0).max()
        worst_cubic = max(worst_cubic, float(gap))
    assert worst_cubic > 0.02  # the cubic lattice is not isotropic: the test can fail


def test_factors_are_off_in_2d_and_on_jittered_clouds():
    cloud = rectangle((0.01, 0.008), 1e-3, thickness=1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    on = Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), surface_correction=True)
    off = Evaluator(
        cloud, bonds, BondBasedMaterial(E, RHO, isotropic_family=False), surface_correction=True
    )
    assert np.array_equal(on.stiffness, off.stiffness)


_DECK = """
name: t
geometry: {{type: {geom}}}
discretisation: {{spacing: 1.0e-3, horizon_factor: 3.015{extra}}}
material: {{youngs_modulus: 70.0e9, density: 2700.0}}
solver: {{type: explicit, steps: 1}}
"""


@pytest.mark.parametrize(
    ("geom", "extra", "noted"),
    [
        ("box, size: [0.01, 0.01, 0.01]", "", True),
        ("box, size: [0.01, 0.01, 0.01]", ", isotropic_family: true", False),
        ("rectangle, size: [0.01, 0.01]", "", False),
    ],
)
def test_a_3d_bond_based_deck_without_the_key_is_told(geom, extra, noted):
    deck = parse_deck(yaml.safe_load(_DECK.format(geom=geom, extra=extra)))
    said = [n for n in notices(deck) if n.startswith("discretisation.isotropic_family")]
    assert bool(said) == noted


def test_compiled_factors_equal_the_numpy_twin_in_any_range():
    from peridynamics.families.calibration import quartic_monomials
    from peridynamics.families.pmb.isotropy import direction_factors
    from peridynamics.kernels.isotropy import direction_factors as kernel

    cloud = box((0.008, 0.007, 0.006), 1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    xi, w = _family(3.015, "truncated", "constant")
    lam = isotropy_coefficients(xi, w)
    got = direction_factors(bonds, lam, 3)
    twin = 1.0 + quartic_values(bonds.bond_xi / bonds.bond_length[:, None]) @ lam
    np.testing.assert_allclose(got, twin, rtol=1e-14)
    monos = np.asarray(quartic_monomials(3), dtype=np.int64)
    part = kernel(np.ascontiguousarray(bonds.bond_xi[7:50]), lam, monos)
    assert part.tobytes() == got[7:50].tobytes()


def test_a_family_that_cannot_be_isotropic_is_told_and_kept():
    """delta = dx in 3-D: six axis bonds have no shear stiffness; the bonds keep the
    grid's family and a warning names the key."""
    cloud = box((0.005, 0.005, 0.005), 1e-3)
    bonds = build_bonds(cloud, 1e-3)
    with pytest.warns(UserWarning, match="discretisation.isotropic_family"):
        on = Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), surface_correction=True)
    off = Evaluator(
        cloud, bonds, BondBasedMaterial(E, RHO, isotropic_family=False), surface_correction=True
    )
    assert np.array_equal(on.stiffness, off.stiffness)
