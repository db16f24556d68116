"""Bitwise reproducibility across processes: the checkpoint/resume guarantee needs every
kernel that touches the state or a reported number to give the same bits whether it
was compiled in this process or loaded from Numba's on-disk cache."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from peridynamics.bonds import build_bonds
from peridynamics.evaluation import Evaluator
from peridynamics.families.pmb import BondBasedMaterial
from peridynamics.geometry import bar, box, rectangle
from peridynamics.kernels import bond_based as bb


def _fresh(kernel):
    opts = {k: v for k, v in kernel.targetoptions.items() if k not in ("cache", "nopython")}
    return numba.njit(**opts)(kernel.py_func)


# the long tier (CI: pytest -m long): the test compiles its kernels afresh by design
@pytest.mark.long
@pytest.mark.parametrize("dim", [1, 2, 3])
def test_fresh_and_cached_kernels_agree_bitwise(dim: int) -> None:
    cloud = {1: bar(0.05, 1e-3), 2: rectangle((0.01, 0.01), 5e-4), 3: box((0.008,) * 3, 1e-3)}[dim]
    bonds = build_bonds(cloud, 3.015 * cloud.spacing)
    model = Evaluator(cloud, bonds, BondBasedMaterial(70e9, 2700.0))
    u = np.random.default_rng(dim).normal(0.0, 1e-6, cloud.x.shape)
    kernel = bb.FORCE_KERNELS[dim]
    out = []
    for k in (kernel, _fresh(kernel)):
        f = np.zeros_like(u)
        smax = np.zeros(cloud.n_points)
        intact = bonds.bond_intact.copy()
        k(
            cloud.x,
            u,
            bonds.offsets,
            bonds.bond_j,
            model.stiffness,
            intact,
            model.point_s0,
            model.family_s0_min,
            f,
            np.zeros(cloud.n_points, np.int64),
        )
        bb.largest_stretch(cloud.x, u, bonds.offsets, bonds.bond_j, intact, 0.0, smax)
        out.append((f, smax))
    assert np.array_equal(out[0][0], out[1][0]) and np.array_equal(out[0][1], out[1][1])
    w = []
    for k in (bb.strain_energy_density, _fresh(bb.strain_energy_density)):
        o = np.zeros(cloud.n_points)
        k(
            cloud.x,
            u,
            bonds.offsets,
            bonds.bond_j,
            model.stiffness,
            bonds.bond_intact,
            o,
        )
        w.append(o)
    assert np.array_equal(w[0], w[1])
