"""Bond breaking: symmetric, permanent, and consistent with the critical stretch."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, CriticalStretch, Evaluator, build_bonds
from peridynamics.damage import NO_DAMAGE, family_minimum
from peridynamics.geometry import bar, box, rectangle
from peridynamics.kernels import reference

DX = 1e-3


def body(dim):
    if dim == 1:
        return bar(0.04, DX)
    if dim == 2:
        return rectangle((0.015, 0.012), DX)
    return box((0.007, 0.006, 0.006), DX)


@pytest.mark.parametrize("dim", [1, 2, 3])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_bond_breaking_is_symmetric_after_large_random_deformation(dim, seed):
    rng = np.random.default_rng(seed)
    cloud = body(dim)
    b = build_bonds(cloud, 3.015 * DX)
    model = Evaluator(cloud, b, BondBasedMaterial(70e9, 2700.0), damage=CriticalStretch(0.05))
    # heterogeneous thresholds: per-point field, symmetric by the (s0_i + s0_j)/2 rule
    model.point_s0 = rng.uniform(0.02, 0.2, cloud.n_points)
    model.family_s0_min = family_minimum(b, model.point_s0)
    u = rng.normal(0.0, 0.15 * DX, cloud.x.shape)  # strains of order 10 %
    intact = b.bond_intact.copy()
    n_broken = model.internal_force(u, intact, np.empty_like(u), np.empty(cloud.n_points))
    rev = b.reverse_index()
    assert 0 < n_broken < b.n_bonds
    assert n_broken == int(np.sum(intact == 0))
    assert np.array_equal(intact, intact[rev])
    s = reference.stretch(cloud.x, u, b.bond_i, b.bond_j, b.bond_length)
    thr = 0.5 * (model.point_s0[b.bond_i] + model.point_s0[b.bond_j])
    assert np.array_equal(intact == 0, s >= thr)


def test_broken_bonds_stay_broken_and_carry_no_force():
    cloud = body(2)
    b = build_bonds(cloud, 3.015 * DX)
    model = Evaluator(cloud, b, BondBasedMaterial(70e9, 2700.0), damage=CriticalStretch(0.01))
    rng = np.random.default_rng(3)
    u = rng.normal(0.0, 0.02 * DX, cloud.x.shape)
    intact = b.bond_intact.copy()
    f = np.empty_like(u)
    smax = np.empty(cloud.n_points)
    model.internal_force(u, intact, f, smax)
    broken = intact == 0
    assert broken.any()
    # relax to zero displacement: nothing heals, and no force is exerted there
    assert model.internal_force(np.zeros_like(u), intact, f, smax) == 0
    assert np.array_equal(intact == 0, broken)
    u2 = 0.5 * u
    model.internal_force(u2, intact, f, smax)
    ref = reference.force(cloud.x, u2, b.bond_i, b.bond_j, b.bond_length, model.stiffness, intact)
    np.testing.assert_allclose(f, ref, rtol=1e-10, atol=1e-12 * np.abs(ref).max())
    phi = model.point_damage(intact)
    assert np.all((phi > 1e-12) == np.bincount(b.bond_i, broken, cloud.n_points).astype(bool))


def test_no_damage_never_breaks():
    cloud = body(2)
    b = build_bonds(cloud, 3.015 * DX)
    model = Evaluator(cloud, b, BondBasedMaterial(70e9, 2700.0), damage=NO_DAMAGE)
    u = np.random.default_rng(0).normal(0.0, 0.5 * DX, cloud.x.shape)
    intact = b.bond_intact.copy()
    assert model.internal_force(u, intact, np.empty_like(u), np.empty(cloud.n_points)) == 0
    assert np.all(intact == 1)


def test_critical_stretch_validation():
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(ValueError):
            CriticalStretch(bad)
    s0 = CriticalStretch(0.01, no_fail=np.array([1, 3])).point_threshold(5)
    assert np.array_equal(s0, [0.01, np.inf, 0.01, np.inf, 0.01])


@pytest.mark.parametrize("dim", [1, 2, 3])
def test_fused_explicit_path_equals_trial_commit_force(dim) -> None:
    """The explicit fast path (PMB force_and_break) breaks the same bonds as the damage
    law's trial and its commit, and gives the force of the pure force pass in turn: the
    same bits in 2-D and 3-D; in 1-D within 4 ulp of the largest force (both passes are
    fast-math kernels, whose sums LLVM may vectorise differently: 8 of 40 components
    differed by 1.0e-16 of the largest force on an AVX2 AMD EPYC, none on the machines
    before it)."""
    rng = np.random.default_rng(7)
    cloud = body(dim)
    b = build_bonds(cloud, 3.015 * DX)
    model = Evaluator(cloud, b, BondBasedMaterial(70e9, 2700.0), damage=CriticalStretch(0.05))
    fused, split = model.new_state(), model.new_state()
    u = rng.normal(0.0, 0.15 * DX, cloud.x.shape)
    fused.u[:] = u
    split.u[:] = u
    broken = model.evaluate(fused, commit=True)
    proposed = model.damage_law.trial(split)
    assert np.array_equal(split.intact, b.bond_intact)  # a trial changes nothing
    assert model.damage_law.commit(split) == proposed == broken > 0
    model.force_model.force(split)
    assert np.array_equal(fused.intact, split.intact)
    if dim == 1:
        ulp = np.spacing(np.abs(split.force).max())
        assert np.abs(fused.force - split.force).max() <= 4 * ulp
    else:
        assert np.array_equal(fused.force, split.force)
    assert np.array_equal(fused.max_stretch, split.max_stretch)
    assert fused.bonds_broken == split.bonds_broken == broken
    # the pure evaluation breaks nothing
    again = model.new_state()
    again.u[:] = u
    model.evaluate(again, commit=False)
    assert np.array_equal(again.intact, b.bond_intact) and again.bonds_broken == 0
