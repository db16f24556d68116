"""1-D explicit finite differences for the wave equation (Lu & Wang (2016), eq. 17).

``FDMModel1D`` is a drop-in model for :class:`~peridynamics.solvers.explicit.ExplicitSolver`:
rho u_tt = E (u_{i+1} - 2 u_i + u_{i-1}) / dx^2 + b_i on a uniform node grid, with free
ends (the missing neighbour term is dropped, i.e. a ghost node u_{-1} = u_0). With the
central-difference integrator this is the classical explicit FDM; it is exactly what
bond-based PD with delta = dx and the partial volumes of Lu & Wang (2016) computes
(weight 1/2 on the single neighbour at delta), which the tests check to 1e-12.

It carries the nearest-neighbour bond list (for bookkeeping, the hybrid switch and the
shared output); its "stretch" is Delta u / dx between neighbours, and it never breaks
anything.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds import build_bonds
from peridynamics.bonds.bonds import Bonds
from peridynamics.damage import NO_DAMAGE
from peridynamics.evaluation import Evaluator
from peridynamics.families.pmb.force import PMBForceModel
from peridynamics.families.pmb.material import BondBasedMaterial
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels.fdm import fdm_force_1d
from peridynamics.loading.conditions import BodyForce
from peridynamics.state import State


class FDMForceModel(PMBForceModel):
    """E u_xx by second-order central differences (the force model of
    :class:`FDMModel1D`). Energy and stiffness bound are those of the equivalent PMB
    model with delta = dx on the same nearest-neighbour bonds."""

    name = "fdm"
    fused_breaking = False
    #: the classical finite-difference step (the PMB bound with delta = dx), not the
    #: Lanczos estimate that PMB uses
    spectral_bound = False

    def __init__(self, cloud: PointCloud, bonds: Bonds, material: BondBasedMaterial) -> None:
        super().__init__(cloud, bonds, material)
        self._coef = material.youngs_modulus / cloud.spacing**2
        self._inv_dx = 1.0 / cloud.spacing

    def force(self, state: State) -> None:
        """``state.force`` (n, 1) = E u_xx (N/m^3); ``state.max_stretch`` the largest
        tensile Delta u / dx to a neighbour (Numba kernel
        :func:`~peridynamics.kernels.fdm.fdm_force_1d`)."""
        fdm_force_1d(state.u, self._coef, self._inv_dx, state.force, state.max_stretch)


class FDMModel1D(Evaluator):
    """Second-order central finite differences on a sorted uniform 1-D grid."""

    def __init__(
        self,
        cloud: PointCloud,
        material: BondBasedMaterial,
        body_forces: Sequence[BodyForce] = (),
        damping: float = 0.0,
    ) -> None:
        """``damping``: mass-proportional damping c_d (1/s), as
        :attr:`Evaluator.damping` (``solver.damping``)."""
        if cloud.dim != 1:
            raise ValueError("the finite-difference solver is 1-D")
        x = cloud.x[:, 0]
        dx = np.diff(x)
        if np.any(dx <= 0) or not np.allclose(dx, cloud.spacing, rtol=1e-9, atol=0):
            raise ValueError("the finite-difference solver needs sorted nodes at a uniform spacing")
        bonds = build_bonds(cloud, cloud.spacing, "truncated")
        super().__init__(cloud, bonds, material, NO_DAMAGE, body_forces, damping=damping)
        self.force_model = FDMForceModel(cloud, self.bonds, material)

    def section_stress(self, u: NDArray, intact: NDArray[np.uint8], position: float) -> float:
        """sigma = E (u_{i+1} - u_i) / dx at the section between the nodes around
        ``position`` (Pa, tension positive)."""
        x = self.cloud.x[:, 0]
        i = int(np.clip(np.searchsorted(x, position) - 1, 0, len(x) - 2))
        return float(self.material.youngs_modulus * (u[i + 1, 0] - u[i, 0]) / self.cloud.spacing)
