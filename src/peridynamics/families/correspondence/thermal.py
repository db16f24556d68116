"""Correspondence with thermal expansion: the constitutive law sees the mechanical
deformation gradient ``F_m = F / (1 + eps_i)`` (the multiplicative split ``F = F_m
F_th``, ``F_th = (1 + eps_i) I``: Lu & Pister (1975); the first Piola stress conjugate
to F is ``P_m(F_m) / (1 + eps_i)``). The stabilisation acts on the non-affine part of
the deformation, ``y - F xi``, which a thermal strain does not change."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from peridynamics.families.correspondence.force import CorrespondenceForceModel
from peridynamics.families.thermal import ThermalExpansion, thermal_strain_of
from peridynamics.kernels import correspondence as kernels

if TYPE_CHECKING:
    from peridynamics.state import State


class CorrespondenceThermalForceModel(ThermalExpansion, CorrespondenceForceModel):
    """:class:`~peridynamics.families.correspondence.force.CorrespondenceForceModel`
    whose constitutive law reads ``F / (1 + eps_i)``, eps the State's
    ``thermal_strain``."""

    def prepass(self, state: State) -> None:
        """The family's pre-pass, then the force tensor ``A = (P_m(F_m) / (1 + eps) -
        sigma^s) K^-1`` of every owned point."""
        super().prepass(state)
        assert self._scratch is not None
        kinv, sigma_s, _, _ = self._scratch
        n = len(self.bonds.offsets) - 1
        fgrad = self._tensor(state, "deformation_gradient")[:n]
        scale = 1.0 + thermal_strain_of(state)[:n, None, None]
        active = state["family_active"][:n, None, None]
        piola = self.law.first_piola(fgrad / scale) / scale * active
        amat = self._tensor(state, "force_tensor")
        amat[:n] = np.einsum("nab,nbc->nac", piola - sigma_s[:n], kinv[:n])

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """W_i = active_i W(F_i / (1 + eps_i)) + stabilisation energy (J/m^3), (n,)."""
        b = self.bonds
        n = len(b.offsets) - 1
        fgrad, _, _, _, active, stab = self.kinematics(state.u, state.intact)
        scale = 1.0 + thermal_strain_of(state)[:n, None, None]
        w = active[:n] * self.law.energy_density(fgrad[:n] / scale)
        extra = np.empty(n)
        kernels.stabilization_energy(
            self.bond_xi, self.length, state.u, b.offsets, b.bond_j, self.weight, state.intact,
            fgrad, stab, self.mode, extra,
        )  # fmt: skip
        return np.asarray(w + extra)

    def point_stress(self, state: State) -> NDArray[np.float64]:
        """The Cauchy stress of the law at the mechanical F_m of every point (n, d, d)
        (Pa): ``P_m F_m^T / det F_m``."""
        n = len(self.bonds.offsets) - 1
        fgrad, _, _, _, active, _ = self.kinematics(state.u, state.intact)
        f = fgrad[:n] / (1.0 + thermal_strain_of(state)[:n, None, None])
        piola = self.law.first_piola(f)
        jac = np.linalg.det(f)
        jac = np.where(jac > 0, jac, 1.0)
        sigma = np.einsum("nab,ncb->nac", piola, f) / jac[:, None, None]
        return np.asarray(sigma * active[:n, None, None])
