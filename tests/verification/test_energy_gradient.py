"""Force is minus the gradient of the strain energy: V_i f_i == -dE/du_i.

E(u) = sum_i W_i(u) V_i from Evaluator.strain_energy; f from Evaluator.internal_force; the
derivative by central differences. Checked on irregular clouds (jittered positions,
random volumes), with and without surface correction, constant and conical profiles.
"""

from __future__ import annotations

import numpy as np

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.geometry import PointCloud, bar, box, rectangle

DX = 1e-3


def irregular_cloud(dim: int, seed: int) -> PointCloud:
    rng = np.random.default_rng(seed)
    if dim == 1:
        base = bar(0.02, DX, area=3e-6)
    elif dim == 2:
        base = rectangle((0.010, 0.008), DX, thickness=2e-3, plane="stress")
    else:
        base = box((0.005, 0.005, 0.004), DX)
    x = base.x + rng.uniform(-0.15, 0.15, base.x.shape) * DX
    vol = base.volume * rng.uniform(0.7, 1.3, base.n_points)
    return PointCloud(
        x=x, volume=vol, spacing=DX, cross_section=base.cross_section, plane=base.plane
    )


def test_internal_forces_sum_to_zero_and_have_no_torque():
    """Pairwise central forces: sum V_i f_i = 0 and sum y_i x V_i f_i = 0 (2-D)."""
    cloud = irregular_cloud(2, seed=9)
    bonds = build_bonds(cloud, 3.015 * DX)
    model = Evaluator(
        cloud, bonds, BondBasedMaterial(70e9, 2700.0, profile="conical"), surface_correction=True
    )
    u = np.random.default_rng(1).normal(0.0, 0.05 * DX, cloud.x.shape)
    f = np.empty_like(u)
    model.internal_force(u, bonds.bond_intact.copy(), f, np.empty(cloud.n_points))
    vf = cloud.volume[:, None] * f
    scale = np.abs(vf).sum()
    assert np.abs(vf.sum(axis=0)).max() < 1e-12 * scale
    y = cloud.x + u
    torque = np.sum(y[:, 0] * vf[:, 1] - y[:, 1] * vf[:, 0])
    assert abs(torque) < 1e-12 * scale * np.abs(y).max()
