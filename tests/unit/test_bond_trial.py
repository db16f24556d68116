"""The filtered critical-stretch trial proposes exactly the bonds of the exact one."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics.bonds import build_bonds
from peridynamics.damage.critical_stretch import family_minimum
from peridynamics.geometry import bar, box, rectangle
from peridynamics.kernels.bond_trial import break_trial, break_trial_filtered

CLOUDS = {
    1: lambda: bar(0.06, 1e-3, 1e-6),
    2: lambda: rectangle((0.02, 0.015), 1e-3, thickness=1e-3),
    3: lambda: box((0.008, 0.007, 0.006), 1e-3),
}


@pytest.mark.parametrize("dim", [1, 2, 3])
@pytest.mark.parametrize("seed", [0, 1])
def test_filtered_trial_equals_the_exact_trial(dim: int, seed: int) -> None:
    """Random thresholds (some infinite: no-fail points), random broken bonds, and
    displacements that put some bonds just below and some above their threshold."""
    rng = np.random.default_rng(seed)
    cloud = CLOUDS[dim]()
    bonds = build_bonds(cloud, 3.015e-3)
    n = cloud.n_points
    s0 = 2e-3 * rng.uniform(0.8, 1.2, n)
    s0[rng.integers(0, n, max(1, n // 20))] = np.inf
    intact = bonds.bond_intact.copy()
    intact[rng.integers(0, bonds.n_bonds, bonds.n_bonds // 10)] = 0
    u = rng.normal(scale=1e-6, size=(n, dim))
    u[: n // 4] += rng.normal(scale=3e-6, size=(n // 4, dim))
    exact = np.zeros(bonds.n_bonds, np.uint8)
    filtered = np.full(bonds.n_bonds, 7, np.uint8)  # every entry must be written
    counts = np.zeros(n, np.int64)
    want = break_trial(cloud.x, u, bonds.offsets, bonds.bond_j, intact, s0, exact)
    got = break_trial_filtered(
        cloud.x, u, bonds.offsets, bonds.bond_j, intact, s0, family_minimum(bonds, s0),
        filtered, counts,
    )  # fmt: skip
    assert 0 < want < bonds.n_bonds  # some bonds break, not all: the test can fail
    assert got == want and int(counts.sum()) == want
    np.testing.assert_array_equal(filtered, exact)
