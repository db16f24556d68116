"""SED softening (SED-PD (2021), eqs 18-24) and Weibull heterogeneity (eqs 25-26)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.damage import CriticalStretch, SEDSoftening, WeibullField
from peridynamics.geometry import rectangle
from peridynamics.kernels import reference
from peridynamics.kernels.sed import sed_stiffness, sed_update

# the long tier (CI: pytest -m long): the SED-softening kernels compile for long cold
pytestmark = pytest.mark.long

E = 4.71e9


def patch(surface_correction: bool = True, damage=None, softening=None):
    cloud = rectangle((0.02, 0.02), 5e-4, thickness=0.02)
    bonds = build_bonds(cloud, 3 * 5e-4)
    model = Evaluator(
        cloud,
        bonds,
        BondBasedMaterial(E, 1810.0),
        damage or CriticalStretch(0.00318),
        surface_correction=surface_correction,
        softening=softening,
    )
    return cloud, model


def test_sed_of_uniform_strain_equals_continuum() -> None:
    """Interior W_i under uniaxial strain = E' eps^2 / 2 with E' = 9E/8 (plane stress,
    nu = 1/3), and the softening kernel's W equals the model's energy density."""
    cloud, model = patch(softening=SEDSoftening())
    eps = 1e-4
    u = np.zeros_like(cloud.x)
    u[:, 0] = eps * cloud.x[:, 0]
    w_model = model.strain_energy_density(u, model.bonds.bond_intact)
    centre = np.argmin(np.linalg.norm(cloud.x - 0.01, axis=1))
    assert w_model[centre] == pytest.approx(9 / 16 * E * eps**2, rel=2e-3)
    state = model.new_state()
    state.u[:] = u
    model.evaluate(state)
    np.testing.assert_allclose(model._sed.energy, w_model, rtol=1e-10)


def test_levels_step_exactly_at_the_thresholds() -> None:
    """A point's level is 0 just below W_A, 1 at W_A, n in the n-th band, N + 1 at W_C,
    and never goes back (irreversible)."""
    soft = SEDSoftening(levels=4, k_c=3.0, residual=0.05)
    x = np.array([[0.0, 0.0], [1.0, 0.0]])
    offsets = np.array([0, 1, 2])
    bond_j = np.array([1, 0], dtype=np.int32)
    length = np.ones(2)
    k0 = np.full(2, 4.0)  # W = 1/4 k0 s^2 |xi| = s^2
    intact = np.ones(2, dtype=np.uint8)
    w_a, w_c = np.full(2, 1.0), np.full(2, 3.0)
    level = np.zeros(2, dtype=np.int64)
    factor, energy, stiff = np.ones(2), np.zeros(2), k0.copy()

    def at(w: float) -> int:
        u = np.array([[0.0, 0.0], [math.sqrt(w), 0.0]])  # s = sqrt(w) -> W = w
        sed_update(x, u, offsets, bond_j, length, k0, intact, w_a, w_c, 4, level, energy,
                   False, np.zeros(2, np.uint8))  # fmt: skip
        sed_stiffness(offsets, bond_j, k0, level, 4, 0.05, factor, stiff)
        return int(level[0])

    assert at(1.0 - 1e-9) == 0 and factor[0] == 1.0
    assert at(1.0 + 1e-9) == 1 and factor[0] == 1.0  # E_1 = E (N + 1 - 1) / N = E
    assert at(1.5 - 1e-9) == 1
    assert at(1.5 + 1e-9) == 2 and factor[0] == pytest.approx(3 / 4)  # band [1.5, 2)
    assert stiff[0] == pytest.approx(4.0 * 3 / 4)  # (c_i + c_j) / 2, both points alike
    assert at(2.999) == 4 and factor[0] == pytest.approx(1 / 4)
    assert at(3.0 + 1e-9) == 5 and factor[0] == pytest.approx(0.05)  # residual
    assert at(0.0) == 5  # unloading does not heal
    np.testing.assert_array_equal(soft.factor(np.arange(6)), [1, 1, 0.75, 0.5, 0.25, 0.05])


@pytest.mark.parametrize("tensile", [False, True])
def test_sed_kernel_matches_numpy_twin(tensile: bool) -> None:
    cloud, model = patch(softening=SEDSoftening())
    b = model.bonds
    rng = np.random.default_rng(2)
    u = rng.normal(size=cloud.x.shape) * 5e-6
    intact = (rng.random(b.n_bonds) > 0.05).astype(np.uint8)
    w_a = rng.uniform(5e2, 2e3, cloud.n_points)
    w_c = 4 * w_a
    level0 = rng.integers(0, 3, cloud.n_points)
    level, factor = level0.copy(), SEDSoftening().factor(level0).astype(float)
    energy, stiff = np.zeros(cloud.n_points), model.stiffness.copy()
    k0 = model.stiffness.copy()
    sed_update(cloud.x, u, b.offsets, b.bond_j, b.bond_length, k0, intact, w_a, w_c, 10,
               level, energy, tensile, np.zeros(cloud.n_points, np.uint8))  # fmt: skip
    sed_stiffness(b.offsets, b.bond_j, k0, level, 10, 0.05, factor, stiff)
    e_ref, lev_ref, f_ref, k_ref = reference.sed_update(
        cloud.x,
        u,
        b.bond_i,
        b.bond_j,
        b.bond_length,
        k0,
        intact,
        w_a,
        w_c,
        10,
        0.05,
        level0,
        tensile,
    )
    np.testing.assert_allclose(energy, e_ref, rtol=1e-10)
    np.testing.assert_array_equal(level, lev_ref)
    assert (level != level0).any()
    np.testing.assert_allclose(factor, f_ref, rtol=1e-14)
    np.testing.assert_allclose(stiff, k_ref, rtol=1e-14)


def test_softening_lowers_the_force() -> None:
    """Same displacement, one point at the residual level: its bonds carry less force
    (from the evaluation after the one that raised its level)."""
    cloud, model = patch(softening=SEDSoftening())
    _, plain = patch()
    eps = 1e-4
    u = np.zeros_like(cloud.x)
    u[:, 0] = eps * cloud.x[:, 0]
    centre = int(np.argmin(np.linalg.norm(cloud.x - 0.01, axis=1)))
    model._sed.w_a[centre] = 0.0  # force this one point past W_C
    model._sed.w_c[centre] = 1e-30
    f0 = np.zeros_like(u)
    ms = np.zeros(cloud.n_points)
    state = model.new_state()
    state.u[:] = u
    model.evaluate(state)  # the history (levels) stays in the State
    plain.internal_force(u, plain.bonds.bond_intact.copy(), f0, ms)
    # the levels rise in this evaluation; the new moduli act from the next one
    np.testing.assert_array_equal(state.force, f0)
    model.evaluate(state)
    f1 = state.force
    assert state["sed_level"][centre] == 11
    lo, hi = model.bonds.offsets[centre], model.bonds.offsets[centre + 1]
    np.testing.assert_allclose(model.stiffness[lo:hi], plain.stiffness[lo:hi] * 0.525)
    assert not np.allclose(f1, f0)


@pytest.mark.parametrize("shape", [2.0, 10.0, 50.0])
def test_weibull_samples_pass_kolmogorov_smirnov(shape: float) -> None:
    field = WeibullField(shape, seed=11)
    g = field.sample(20000, u0=3.0)
    res = stats.kstest(g, stats.weibull_min(shape, scale=3.0).cdf)
    assert res.pvalue > 0.01
    # and a wrong shape is rejected, so the test can fail
    assert stats.kstest(g, stats.weibull_min(shape * 1.3, scale=3.0).cdf).pvalue < 1e-6
    mean_field = WeibullField(shape, seed=11, u0_is="mean").sample(20000, u0=3.0)
    assert mean_field.mean() == pytest.approx(3.0, rel=0.02)


def test_weibull_field_is_reproducible_and_enters_the_bond_threshold() -> None:
    a = WeibullField(10.0, seed=5).stretch_factors(1000)
    b = WeibullField(10.0, seed=5).stretch_factors(1000)
    c = WeibullField(10.0, seed=6).stretch_factors(1000)
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    # G Weibull -> s = s0 sqrt(G/u0): factor^2 is Weibull(m)
    assert stats.kstest(a**2, stats.weibull_min(10.0).cdf).pvalue > 0.01
    s_direct = WeibullField(10.0, seed=5, variable="critical_stretch").stretch_factors(1000)
    np.testing.assert_allclose(s_direct, a**2, rtol=1e-12)
    dmg = CriticalStretch(0.003, weibull=WeibullField(10.0, seed=5))
    np.testing.assert_allclose(dmg.point_threshold(1000), 0.003 * a)
    with pytest.raises(ValueError, match="weibull.shape"):
        WeibullField(0.0)
    with pytest.raises(ValueError, match="k_c"):
        SEDSoftening(k_c=1.0)


def test_heterogeneity_spreads_with_small_shape() -> None:
    """Smaller m -> wider spread of point critical stretch (the paper's m study)."""
    spreads = [
        np.std(WeibullField(m, seed=1).stretch_factors(5000)) for m in (2, 6, 10, 20, 50, 100)
    ]
    assert all(a > b for a, b in zip(spreads, spreads[1:], strict=False))


def test_tensile_energy_ignores_compressed_bonds() -> None:
    """Uniform compression: total SED = continuum, tensile-only SED = 0 (no bond is
    stretched), so compression alone softens nothing with energy: tensile."""
    cloud, model = patch(softening=SEDSoftening(energy="tensile"))
    _, total = patch(softening=SEDSoftening())
    u = -2.5e-3 * (cloud.x - 0.01)  # isotropic compression, W above W_A
    levels = []
    for m in (model, total):
        state = m.new_state()
        state.u[:] = u
        m.evaluate(state)
        levels.append(state["sed_level"])
    assert np.all(model._sed.energy == 0) and np.all(levels[0] == 0)
    assert total._sed.energy.max() > 0 and levels[1].max() > 0
    with pytest.raises(ValueError, match="energy"):
        SEDSoftening(energy="shear")


def test_partial_stiffness_rebuild_equals_the_full_one() -> None:
    """Rebuilding only the bonds of raised points gives the bits of a full rebuild."""
    from peridynamics.kernels.sed import sed_stiffness_raised

    cloud, model = patch(softening=SEDSoftening())
    b = model.bonds
    rng = np.random.default_rng(4)
    k0 = model.stiffness.copy()
    level = np.zeros(cloud.n_points, np.int64)
    factor, full = np.ones(cloud.n_points), k0.copy()
    part = k0.copy()
    for _ in range(3):
        raised = (rng.random(cloud.n_points) < 0.05).astype(np.uint8)
        level[raised == 1] += rng.integers(1, 4, int(raised.sum()))
        level = np.minimum(level, 11)
        sed_stiffness(b.offsets, b.bond_j, k0, level, 10, 0.05, factor.copy(), full)
        sed_stiffness_raised(b.offsets, b.bond_j, k0, level, 10, 0.05, factor, part, raised)
        assert np.array_equal(full, part)


def test_explicit_micromodulus_option() -> None:
    """SED-PD (2021) prints the 3-D c = 18 k / (pi delta^4) for a plane-stress model: the
    ``micromodulus`` option uses any given c; the bond stiffness scales with it."""
    from peridynamics.deck import DeckError, parse_deck

    delta, t = 1.5e-3, 0.02
    k = E / (3 * (1 - 2 * 0.25))
    c3d = 18 * k / (np.pi * delta**4)
    c2d = BondBasedMaterial(E, 1810.0).micromodulus_constant(2, delta, t, "stress")
    assert c3d / c2d == pytest.approx(4 * t / (3 * delta), rel=1e-12)
    mat = BondBasedMaterial(E, 1810.0, micromodulus_value=c3d)
    assert mat.micromodulus_constant(2, delta, t, "stress") == c3d
    cloud = rectangle((0.005, 0.005), 5e-4, thickness=t)
    bonds = build_bonds(cloud, delta)
    ratio = (
        Evaluator(cloud, bonds, mat).stiffness
        / Evaluator(cloud, bonds, BondBasedMaterial(E, 1810.0)).stiffness
    )
    np.testing.assert_allclose(ratio, c3d / c2d, rtol=1e-12)
    with pytest.raises(ValueError, match="micromodulus"):
        BondBasedMaterial(E, 1810.0, micromodulus_value=-1.0)
    deck = {
        "name": "m", "geometry": {"type": "rectangle", "size": [0.01, 0.005]},
        "discretisation": {"spacing": 5e-4, "horizon_factor": 3.0},
        "material": {"youngs_modulus": E, "density": 1810.0, "micromodulus": c3d},
        "damage": {"fracture_energy": 10.0}, "solver": {"steps": 1},
    }  # fmt: skip
    with pytest.raises(DeckError, match="critical_stretch"):
        parse_deck(deck)


@pytest.mark.parametrize("tensile", [False, True])
def test_fused_2d_force_and_energy_equal_the_separate_passes(tensile: bool) -> None:
    """force_sed_2d = force_2d (forces, stretches, breaking) + the SED pass (energies)."""
    from peridynamics.kernels import bond_based

    cloud, model = patch(softening=SEDSoftening())
    b = model.bonds
    rng = np.random.default_rng(8)
    u = rng.normal(size=cloud.x.shape) * 2e-6
    s0 = np.full(cloud.n_points, 2e-3)
    s0_min = np.full(cloud.n_points, 2e-3)
    k0 = model.stiffness.copy()
    out = {}
    for fused in (False, True):
        intact = b.bond_intact.copy()
        f, ms, nb = np.zeros_like(u), np.zeros(cloud.n_points), np.zeros(cloud.n_points, np.int64)
        energy = np.zeros(cloud.n_points)
        if fused:
            n = bond_based.force_sed_2d(cloud.x, u, b.offsets, b.bond_j, k0, intact, s0,
                                        s0_min, f, nb, 0.25 * k0 * b.bond_length, tensile,
                                        energy)  # fmt: skip
        else:
            n = bond_based.force_2d(cloud.x, u, b.offsets, b.bond_j, k0, intact, s0, s0_min,
                                    f, nb)  # fmt: skip
            sed_update(cloud.x, u, b.offsets, b.bond_j, b.bond_length, k0, intact,
                       np.full(cloud.n_points, 1e300), np.full(cloud.n_points, 1e300), 10,
                       np.zeros(cloud.n_points, np.int64), energy, tensile,
                       np.zeros(cloud.n_points, np.uint8))  # fmt: skip
        bond_based.largest_stretch(cloud.x, u, b.offsets, b.bond_j, intact, 0.0, ms)
        out[fused] = (n, f, ms, intact, energy)
    (n0, f0, m0, i0, e0), (n1, f1, m1, i1, e1) = out[False], out[True]
    assert n0 == n1 > 0 and np.array_equal(i0, i1)
    np.testing.assert_allclose(f1, f0, rtol=1e-12, atol=1e-12 * np.abs(f0).max())
    np.testing.assert_allclose(m1, m0, rtol=1e-12)
    np.testing.assert_allclose(e1, e0, rtol=1e-10)
