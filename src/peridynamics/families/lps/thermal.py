"""LPS with thermal expansion: the mechanical extension ``e - (eps_i + eps_j) L / 2``
in the dilatation, the force state and the energy (Oterkus, Madenci & Agwai
(2014b); :mod:`peridynamics.kernels.thermal_expansion`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.families.lps.force import LPSForceModel
from peridynamics.families.lps.tangent import lps_tangent
from peridynamics.families.thermal import ThermalExpansion, thermal_strain_of
from peridynamics.kernels import thermal_expansion as kernels

if TYPE_CHECKING:
    from peridynamics.state import State


class LPSThermalForceModel(ThermalExpansion, LPSForceModel):
    """:class:`~peridynamics.families.lps.force.LPSForceModel` whose extension
    subtracts the thermal strain ``state["thermal_strain"]``; ``state["dilatation"]``
    is the mechanical dilatation."""

    def _theta(self, state: State, out: NDArray[np.float64]) -> None:
        b = self.bonds
        kernels.LPS_DILATATION[self.dim](
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            state.intact, self.theta_scale, thermal_strain_of(state), out,
        )  # fmt: skip

    def prepass(self, state: State) -> None:
        """Mechanical dilatation of every owned point into ``state["dilatation"]``."""
        if "dilatation" not in state:
            state["dilatation"] = np.zeros(state.u.shape[0])
        self._theta(state, state["dilatation"])

    def force(self, state: State) -> None:
        """LPS force density of the mechanical extension (N/m^3); reads the dilatation of
        the last :meth:`prepass`."""
        if "dilatation" not in state:
            raise KeyError("state has no 'dilatation' field: call prepass(state) first")
        b = self.bonds
        kernels.LPS_FORCE[self.dim](
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            self.omega_volume_far, state.intact, state["dilatation"], self.dilatation_coef,
            self.extension_coef, thermal_strain_of(state), state.force,
        )  # fmt: skip

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """W_i of the mechanical extension (J/m^3), shape (n,)."""
        b = self.bonds
        out = np.empty(len(b.offsets) - 1)
        kernels.lps_energy(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            state.intact, self.theta_scale, self.k_theta, self.extension_coef,
            thermal_strain_of(state), out,
        )  # fmt: skip
        return out

    def pair_force_coefficients(self, state: State) -> NDArray[np.float64]:
        """The net pair force g_k of the force pass (N/m^4) with the mechanical
        extension and dilatation (recomputed; the State is not changed)."""
        b = self.bonds
        eps = thermal_strain_of(state)
        theta = np.zeros(state.u.shape[0])
        self._theta(state, theta)
        bi, bj, length = b.bond_i, b.bond_j, b.bond_length
        xi = b.bond_xi
        eta = state.u[bj] - state.u[bi]
        y = xi + eta
        r = np.sqrt(np.einsum("ij,ij->i", y, y))
        e = np.einsum("ij,ij->i", eta, 2.0 * xi + eta) / (r + length)
        e = e - 0.5 * (eps[bi] + eps[bj]) * length
        cd, a = self.dilatation_coef, self.extension_coef
        wv, wvf = self.omega_volume, self.omega_volume_far
        t = (wv * cd[bi] * theta[bi] + wvf * cd[bj] * theta[bj]) * length + (
            wv * a[bi] + wvf * a[bj]
        ) * e
        return np.asarray(state.intact * t / r)

    def tangent(self, state: State) -> sp.csr_matrix:
        """Analytic tangent K = -d(V f)/du (N/m): the LPS one with the thermal extension
        ``a_k L_k`` subtracted from every extension
        (:func:`~peridynamics.families.lps.tangent.lps_tangent`)."""
        b = self.bonds
        eps = thermal_strain_of(state)
        extension = 0.5 * (eps[b.bond_i] + eps[b.bond_j]) * b.bond_length
        return lps_tangent(self, state, thermal_extension=extension)
