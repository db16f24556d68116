"""PMB with thermal expansion: the bond force of the mechanical stretch
``s - (eps_i + eps_j)/2`` (Kilic & Madenci (2010b);
:mod:`peridynamics.kernels.thermal_expansion`)."""

from __future__ import annotations

from types import SimpleNamespace
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.families.pmb.force import PMBForceModel
from peridynamics.families.pmb.tangent import pmb_tangent
from peridynamics.families.thermal import ThermalExpansion, thermal_strain_of
from peridynamics.kernels import thermal_expansion as kernels

if TYPE_CHECKING:
    from peridynamics.state import State


class PMBThermalForceModel(ThermalExpansion, PMBForceModel):
    """:class:`~peridynamics.families.pmb.force.PMBForceModel` whose bonds subtract the
    thermal strain ``state["thermal_strain"]`` of their end points (float64 only)."""

    fused_breaking = False

    def set_precision(self, precision: str) -> None:
        """float64 only."""
        if precision != "float64":
            raise ValueError("[solver.precision] thermal expansion runs in float64")

    def force(self, state: State) -> None:
        """f_i = sum_k stiffness_k mu_k (s_k - a_k) y_k / r_k (N/m^3); never breaks."""
        b = self.bonds
        kernels.PMB_FORCE[self.dim](
            self.cloud.x, state.u, b.offsets, b.bond_j, self.stiffness, state.intact,
            thermal_strain_of(state), state.force,
        )  # fmt: skip

    def force_and_break(self, state: State, point_s0: Any, family_s0_min: Any) -> int:
        """Not fused: refused (the evaluator calls the law and :meth:`force` in turn)."""
        raise NotImplementedError("thermal expansion has no fused breaking pass")

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """W_i = 1/4 sum_k stiffness_k mu_k (s_k - a_k)^2 L_k (J/m^3), shape (n,)."""
        b = self.bonds
        out = np.empty(len(b.offsets) - 1)
        kernels.pmb_energy(
            self.cloud.x, state.u, b.offsets, b.bond_j, self.stiffness, state.intact,
            thermal_strain_of(state), out,
        )  # fmt: skip
        return out

    def pair_force_coefficients(self, state: State) -> NDArray[np.float64]:
        """g_k = stiffness_k mu_k (1/L_k - (1 + a_k)/r_k) (n_bonds,) (N/m^4)."""
        b = self.bonds
        eps = thermal_strain_of(state)
        y = b.bond_xi + (state.u[b.bond_j] - state.u[b.bond_i])
        r = np.sqrt(np.einsum("ij,ij->i", y, y))
        a = 0.5 * (eps[b.bond_i] + eps[b.bond_j])
        stiff = np.asarray(self.stiffness, dtype=np.float64)
        return np.asarray(stiff * state.intact * (self.inv_length - (1.0 + a) / r))

    def tangent(self, state: State) -> sp.csr_matrix:
        """Analytic tangent K = -d(V f)/du (N/m), shape (n dim, n dim): the pair force
        ``g (1/L - (1 + a)/r) y`` is the PMB one of a bond with stiffness ``g (1 + a)``
        and length ``L (1 + a)``, so :func:`~peridynamics.families.pmb.tangent.pmb_tangent`
        of those gives it exactly."""
        b = self.bonds
        eps = thermal_strain_of(state)
        scale = 1.0 + 0.5 * (eps[b.bond_i] + eps[b.bond_j])
        bond = SimpleNamespace(
            bonds=b,
            cloud=self.cloud,
            stiffness=np.asarray(self.stiffness, dtype=np.float64) * scale,
            inv_length=self.inv_length / scale,
        )
        return pmb_tangent(bond, state)
