"""Warp kernels of the PMB step (groundwork of the GPU backend) against the Numba kernels
on Warp's CPU device: the same bonds break, forces to 1e-12 relative, damage."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics.bonds import build_bonds
from peridynamics.geometry import box, rectangle
from peridynamics.kernels import bond_based as bb

wk = pytest.importorskip(
    "peridynamics.backends.warp_kernels", reason="the Warp backend needs warp-lang"
)
pytestmark = pytest.mark.skipif(
    not wk.available(), reason="warp-lang is not installed (pip install '.[gpu]')"
)


# the 2-D case is the default selection's Warp smoke test; the 3-D case and every other
# Warp test are in the gpu tier (pytest -m gpu, run by .ci/run)
@pytest.mark.parametrize("dim", [2, pytest.param(3, marks=pytest.mark.gpu)])
def test_force_break_and_damage_match_numba(dim: int) -> None:
    if dim == 2:
        c = rectangle((0.02, 0.01), 5e-4, thickness=1e-3, plane="stress")
    else:
        c = box((0.006, 0.005, 0.004), 5e-4)
    b = build_bonds(c, 1.5e-3)
    rng = np.random.default_rng(dim)
    u = rng.normal(scale=2e-6, size=c.x.shape)
    stiffness = rng.uniform(1e17, 2e17, b.n_bonds)
    s0 = rng.uniform(3e-3, 6e-3, c.n_points)
    s0[::7] = np.inf  # no-fail points
    ref_intact = b.bond_intact.copy()
    ref_force = np.zeros_like(u)
    kernel = bb.force_2d if dim == 2 else bb.force_3d
    threshold = 0.5 * (s0[b.bond_i] + s0[b.bond_j])
    fmin = np.minimum.reduceat(threshold, b.offsets[:-1])  # each family's smallest
    n_ref = kernel(
        c.x, u, b.offsets, b.bond_j, stiffness, ref_intact, s0, fmin, ref_force,
        np.zeros(c.n_points, np.int64),
    )  # fmt: skip
    force, intact, n = wk.pmb_force_break(c.x, u, b.offsets, b.bond_j, stiffness, b.bond_intact, s0)
    assert n == n_ref > 0
    np.testing.assert_array_equal(intact, ref_intact)
    scale = np.abs(ref_force).max()
    assert np.abs(force - ref_force).max() <= 1e-12 * scale
    ref_damage = np.empty(c.n_points)
    bb.damage(b.offsets, b.bond_volume, ref_intact, ref_damage)
    damage = wk.point_damage(b.offsets, b.bond_volume, intact)
    assert np.array_equal(damage, ref_damage)  # the same sums in the same order
