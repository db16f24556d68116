"""A toy model family: linear springs between bonded points, in plain NumPy.

The worked example of docs/adding.md. Bond (i, j) of reference length L and deformed
vector e = (x_j + u_j) - (x_i + u_i), r = |e|, stretch s = (r - L) / L, pulls point i
with the force density ``c V_j s e / r`` (N/m^3, c the spring constant in N/m^6) and
stores the energy density ``c V_j s^2 L / 4`` at each end. It passes the contract
harness (tests/contracts/test_force_models.py) with no kernel, no State field of its
own and no deck entry: a family is a class with ``force``, ``energy_density``,
``stiffness_bound`` and, optionally, ``tangent``.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import ForceModel
from peridynamics.geometry.cloud import PointCloud
from peridynamics.state import State


class ToySpringModel(ForceModel):
    """Linear springs of constant ``c`` (N/m^6) on every bond of ``bonds``."""

    name = "toy_spring"

    def __init__(self, cloud: PointCloud, bonds: Bonds, c: float) -> None:
        self.cloud, self.bonds = cloud, bonds
        self.k = c * bonds.bond_volume  # N/m^3 per unit stretch, one value per bond

    def _bonds(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Deformed bond vectors e (n_bonds, dim), lengths r and stretches s."""
        b, y = self.bonds, self.cloud.x + state.u
        e = y[b.bond_j] - y[b.bond_i]
        r = np.linalg.norm(e, axis=1)
        return e, r, (r - b.bond_length) / b.bond_length

    def force(self, state: State) -> None:
        """f_i = sum_j mu c V_j s e / r into ``state.force`` (N/m^3)."""
        e, r, s = self._bonds(state)
        g = state.intact * self.k * s / r
        for c in range(self.dim):
            state.force[:, c] = np.bincount(self.bonds.bond_i, g * e[:, c], self.n_points)
        state.max_stretch[:] = 0.0
        np.maximum.at(state.max_stretch, self.bonds.bond_i, state.intact * s)

    def energy_density(self, state: State) -> np.ndarray:
        """W_i = 1/4 sum_j mu c V_j s^2 L (J/m^3), shape (n,)."""
        _, _, s = self._bonds(state)
        w = state.intact * self.k * s * s * self.bonds.bond_length
        return 0.25 * np.bincount(self.bonds.bond_i, w, self.n_points)

    def stiffness_bound(self) -> np.ndarray:
        """K_i = sum_j c V_j / L (N/m^4), Silling & Askari (2005), eq. 18."""
        b = self.bonds
        return np.bincount(b.bond_i, self.k / b.bond_length, self.n_points)

    def tangent(self, state: State) -> sp.csr_matrix:
        """K = -d(V f)/du (N/m): bond (i, j) adds V_i mu c V_j B to block (i, i) and its
        negative to (i, j), with B = (s I + n n^T) / r the derivative of s e / r."""
        b, d, vol = self.bonds, self.dim, self.cloud.volume
        e, r, s = self._bonds(state)
        n = e / r[:, None]
        blk = (s[:, None, None] * np.eye(d) + n[:, :, None] * n[:, None, :]) / r[:, None, None]
        blk *= (vol[b.bond_i] * state.intact * self.k)[:, None, None]
        a = np.arange(d)
        rows = (b.bond_i[:, None, None] * d + a[None, :, None]).repeat(d, axis=2)
        cols_i = (b.bond_i[:, None, None] * d + a[None, None, :]).repeat(d, axis=1)
        cols_j = (b.bond_j[:, None, None] * d + a[None, None, :]).repeat(d, axis=1)
        data = np.concatenate([blk.ravel(), -blk.ravel()])
        ij = (np.concatenate([rows.ravel(), rows.ravel()]),
              np.concatenate([cols_i.ravel(), cols_j.ravel()]))  # fmt: skip
        size = self.n_points * d
        return sp.csr_matrix((data, ij), shape=(size, size))


if __name__ == "__main__":  # a 2-D plate stretched by 0.1 %: energy and time step
    from peridynamics.bonds.bonds import build_bonds
    from peridynamics.geometry.generators import rectangle

    plate = rectangle((0.01, 0.01), 1e-3, thickness=1e-3, plane="stress")
    model = ToySpringModel(plate, build_bonds(plate, 3.015e-3), c=1e20)
    n = plate.n_points
    st = State(u=1e-3 * plate.x, force=np.zeros((n, 2)), max_stretch=np.zeros(n),
               intact=np.ones(model.bonds.n_bonds, dtype=np.uint8))  # fmt: skip
    model.force(st)
    print(f"energy {np.sum(model.energy_density(st) * plate.volume):.6g} J,"
          f" stable step {np.sqrt(2 * 2700 / model.stiffness_bound()).min():.3g} s")  # fmt: skip
