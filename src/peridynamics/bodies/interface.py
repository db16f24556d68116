"""Bonded interfaces between two bodies: PMB bonds with their own stiffness and strength.

The interface of a mesoscale concrete or rock model (aggregate-mortar, rock-grout) is
weaker than either phase. Here the bonds that join a point of body A to a point of body
B within the horizon form their own directed CSR list (a row for every point of the
model, empty away from the interface), evaluated by the PMB kernels of
:mod:`peridynamics.kernels.bond_based`:

* micromodulus ``c_I = stiffness_factor * 2 c_A c_B / (c_A + c_B)`` (two half-bonds in
  series; ``c`` the constant-profile PMB micromodulus of each body's Young's modulus,
  Silling & Askari (2005));
* critical stretch ``s_I`` given, or from the interface fracture energy ``G_I`` by the
  PMB relation of :meth:`~peridynamics.families.pmb.material.BondBasedMaterial.critical_stretch`
  with ``c_I``; ``inf`` (never breaks) when neither is given.

The bonds carry a partial volume like the bodies' bonds and no surface correction.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.kernels import bond_based, bond_trial


class InterfaceBonds:
    """The bonds of one interface and their law.

    Parameters
    ----------
    name : str
        ``"A/B"`` (for messages).
    bonds : Bonds
        Directed CSR list over all points of the model (both (i, j) and (j, i)); rows
        of points away from the interface are empty.
    micromodulus : float
        c_I (N/m^6).
    critical_stretch : float
        s_I (``inf``: unbreakable).
    """

    def __init__(self, name: str, bonds: Bonds, micromodulus: float, critical_stretch: float):
        if not (math.isfinite(micromodulus) and micromodulus > 0):
            raise ValueError(f"interface {name}: micromodulus must be > 0, got {micromodulus}")
        if not critical_stretch > 0:
            raise ValueError(f"interface {name}: critical stretch must be > 0")
        self.name = name
        self.bonds = bonds
        self.micromodulus = float(micromodulus)
        self.critical_stretch = float(critical_stretch)
        self.stiffness = np.ascontiguousarray(self.micromodulus * bonds.bond_volume)
        self.inv_length = bonds.inv_length
        n = bonds.n_points
        self._s0 = np.full(n, self.critical_stretch)
        self._never = np.full(n, np.inf)
        self._scratch = np.zeros(n, dtype=np.int64)
        self._proposed = np.zeros(bonds.n_bonds, dtype=np.uint8)
        self._count = 0
        self._force: NDArray[np.float64] | None = None
        self._smax = np.zeros(n)

    @property
    def n_bonds(self) -> int:
        """Directed interface bonds."""
        return self.bonds.n_bonds

    @property
    def proposed(self) -> NDArray[np.uint8]:
        """The last trial's proposal (n_bonds,) uint8."""
        return self._proposed

    @property
    def breakable(self) -> bool:
        """True when the bonds can break."""
        return math.isfinite(self.critical_stretch) and self.n_bonds > 0

    def add_force(
        self,
        x: NDArray[np.float64],
        u: NDArray[np.float64],
        intact: NDArray[np.uint8],
        force: NDArray[np.float64],
        max_stretch: NDArray[np.float64],
    ) -> None:
        """ADD the interface bond force density (N/m^3) to ``force`` (n, dim) and raise
        ``max_stretch`` (n,) where an interface bond is stretched more."""
        if self.n_bonds == 0:
            return
        if self._force is None or self._force.shape != force.shape:
            self._force = np.zeros_like(force)
        b = self.bonds
        bond_based.FORCE_KERNELS[x.shape[1]](
            x, u, b.offsets, b.bond_j, self.stiffness, intact, self._never, self._never,
            self._force, self._scratch,
        )  # fmt: skip
        force += self._force
        self.raise_max_stretch(x, u, intact, max_stretch)

    def raise_max_stretch(
        self,
        x: NDArray[np.float64],
        u: NDArray[np.float64],
        intact: NDArray[np.uint8],
        max_stretch: NDArray[np.float64],
    ) -> None:
        """Raise ``max_stretch`` (n,) where an intact interface bond is stretched more."""
        if self.n_bonds == 0:
            return
        b = self.bonds
        bond_based.largest_stretch(x, u, b.offsets, b.bond_j, intact, 0.0, self._smax)
        np.maximum(max_stretch, self._smax, out=max_stretch)

    def energy_density(
        self, x: NDArray[np.float64], u: NDArray[np.float64], intact: NDArray[np.uint8]
    ) -> NDArray[np.float64]:
        """Strain energy density of the interface bonds per point (J/m^3), shape (n,)."""
        out = np.zeros(self.bonds.n_points)
        if self.n_bonds:
            b = self.bonds
            bond_based.strain_energy_density(x, u, b.offsets, b.bond_j, self.stiffness, intact, out)
        return out

    def stiffness_bound(self) -> NDArray[np.float64]:
        """Per-point stiffness bound of the interface bonds (N/m^4), shape (n,)."""
        out = np.zeros(self.bonds.n_points)
        if self.n_bonds:
            b = self.bonds
            out = np.bincount(b.bond_i, self.stiffness / b.bond_length, b.n_points).astype(float)
        return out

    def trial(
        self, x: NDArray[np.float64], u: NDArray[np.float64], intact: NDArray[np.uint8]
    ) -> int:
        """Propose the interface bonds stretched to s_I; returns how many."""
        self._count = 0
        if not self.breakable:
            return 0
        b = self.bonds
        self._count = int(
            bond_trial.break_trial(x, u, b.offsets, b.bond_j, intact, self._s0, self._proposed)
        )
        return self._count

    def commit(self, intact: NDArray[np.uint8]) -> int:
        """Break the proposed bonds; returns how many."""
        if self._count == 0:
            return 0
        intact[self._proposed.view(bool)] = 0
        n, self._count = self._count, 0
        return n


def interface_pairs(bonds_all: Bonds, body: NDArray[np.int64], a: int, b: int) -> NDArray[np.bool_]:
    """Mask of the directed bonds of ``bonds_all`` that join body ``a`` and body ``b``
    (either direction); ``body`` is the body index of each point."""
    bi, bj = body[bonds_all.bond_i], body[bonds_all.bond_j]
    return ((bi == a) & (bj == b)) | ((bi == b) & (bj == a))
