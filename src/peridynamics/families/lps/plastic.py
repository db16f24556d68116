"""Elastic-plastic linear peridynamic solid (Mitchell (2011), SAND2011-3166; LAMMPS
``pair_style peri/eps``), 3-D, with linear isotropic hardening.

The deviatoric extension ``ed_k = e_k - theta_i L_k / 3`` of every directed bond is
split into an elastic and a plastic part ``ep_k``; the deviatoric force state is
``t^d = (15 mu / m_i) omega (ed - ep)``, the bulk part stays elastic. The yield function
of a point is Mitchell's ``||t^d||^2 / 2 - psi0`` written with its elastic deviatoric
energy ``Wd_i = (a_i / 2) sum wv (ed - ep)^2`` and the equivalent stress
``sqrt(6 mu Wd_i)`` against ``sigma_y + H q_i`` (von Mises under a homogeneous strain;
``psi0 = 25 sigma_y^2 / (8 pi delta^5)`` for omega = 1 and the continuum m), and the
return is radial (:mod:`peridynamics.kernels.lps_plasticity`; docs/theory_plasticity.md).

History (checkpointed): the bond field ``lps_plastic_extension`` (ep, m) and the point
field ``lps_plastic_strain`` (q, the equivalent plastic strain). An evaluation writes
their trials ``*_trial`` from the committed history; :meth:`PlasticLPSModel.commit_history`
(called where damage is committed: every explicit step, an accepted ADR load step, a
converged static level, never inside Newton) makes them the history. With zero history
and a state below yield the force is that of the elastic LPS. The static solver uses
the consistent tangent of the return from the committed history
(:mod:`peridynamics.families.lps.plastic_tangent`) and backtracks its Newton steps
(``newton_line_search``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import FieldSpec
from peridynamics.families.lps.force import LPSForceModel
from peridynamics.families.lps.plastic_tangent import plastic_lps_tangent
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import lps_plasticity as kernels
from peridynamics.kernels import reference_lps_plasticity as twins

if TYPE_CHECKING:
    import scipy.sparse as sp

    from peridynamics.state import State

EXTENSION = "lps_plastic_extension"
STRAIN = "lps_plastic_strain"
EXTENSION_TRIAL = "lps_plastic_extension_trial"
STRAIN_TRIAL = "lps_plastic_strain_trial"
SCALE = "lps_plastic_scale"


@dataclass(frozen=True)
class LPSPlasticity:
    """Yield stress and linear isotropic hardening of the elastic-plastic LPS.

    Parameters
    ----------
    yield_stress : float
        sigma_y (Pa), the initial uniaxial yield stress, finite and > 0.
    hardening_modulus : float
        H (Pa), >= 0: the yield stress is ``sigma_y + H q`` (q the equivalent plastic
        strain), so the uniaxial hardening slope is ``E H / (E + H)`` (as ``j2`` of the
        correspondence family).
    """

    yield_stress: float
    hardening_modulus: float = 0.0

    def __post_init__(self) -> None:
        for key, value, zero in (
            ("yield_stress", self.yield_stress, False),
            ("hardening_modulus", self.hardening_modulus, True),
        ):
            ok = isinstance(value, int | float) and math.isfinite(value)
            if not ok or value < 0 or (value == 0 and not zero):
                need = ">= 0" if zero else "> 0"
                raise ValueError(
                    f"material.plasticity.{key} must be a finite value {need} Pa, got {value}"
                )


class PlasticLPSModel(LPSForceModel):
    """LPS with an elastic-plastic deviatoric response (module docstring).

    Parameters
    ----------
    cloud : PointCloud
        3-D.
    bonds : Bonds
        Serial bond list (every bond's reverse is in it).
    material : LPSMaterial
    plasticity : LPSPlasticity
    surface_correction : bool
        As :class:`~peridynamics.families.lps.force.LPSForceModel`.

    Attributes
    ----------
    newton_line_search : bool
        True: the static solver backtracks its Newton steps
        (:mod:`peridynamics.solvers.static_line_search`; full steps cycle between yielded
        sets).
    """

    newton_line_search: ClassVar[bool] = True

    def __init__(
        self,
        cloud: PointCloud,
        bonds: Bonds,
        material: Any,
        plasticity: LPSPlasticity,
        surface_correction: bool = False,
    ) -> None:
        if cloud.dim != 3:
            raise ValueError(
                "material.plasticity of model lps needs a 3-D body (the 2-D deviatoric "
                "split is not implemented)"
            )
        super().__init__(cloud, bonds, material, surface_correction=surface_correction)
        self.plasticity = plasticity
        self.shear = float(material.shear_modulus)
        self.reverse = np.ascontiguousarray(bonds.reverse_index())

    def state_fields(self) -> tuple[FieldSpec, ...]:
        """The dilatation, the history (ep per bond, q per point: history fields), their
        trials and the return factor c of every point."""
        return super().state_fields() + (
            FieldSpec(EXTENSION, where="bond", history=True),
            FieldSpec(STRAIN, history=True),
            FieldSpec(EXTENSION_TRIAL, where="bond"),
            FieldSpec(STRAIN_TRIAL),
            FieldSpec(SCALE),
        )

    def _fields(self, state: State) -> None:
        n, nb = state.u.shape[0], self.bonds.n_bonds
        for name, size in ((EXTENSION, nb), (EXTENSION_TRIAL, nb), (STRAIN, n)):
            if name not in state:
                state[name] = np.zeros(size)
        for name in ("dilatation", STRAIN_TRIAL, SCALE):
            if name not in state:
                state[name] = np.zeros(n)

    def prepass(self, state: State) -> None:
        """Dilatation and the return map of every point from the committed history."""
        self._fields(state)
        b, p = self.bonds, self.plasticity
        kernels.plastic_prepass_3d(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            state.intact, self.theta_scale, self.extension_coef, state[EXTENSION],
            state[STRAIN], self.shear, p.yield_stress, p.hardening_modulus,
            state["dilatation"], state[SCALE], state[STRAIN_TRIAL],
        )  # fmt: skip

    def force(self, state: State) -> None:
        """Force density (N/m^3) into ``state.force`` and the trial plastic extension;
        reads the fields of the last :meth:`prepass`. Pure: never breaks a bond."""
        if SCALE not in state:
            raise KeyError("call PlasticLPSModel.prepass(state) before force(state)")
        b = self.bonds
        kernels.plastic_force_3d(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            self.omega_volume_far, state.intact, state["dilatation"], self.dilatation_coef,
            self.extension_coef, self.reverse, state[EXTENSION], state[SCALE],
            state[EXTENSION_TRIAL], state.force,
        )  # fmt: skip

    def commit_history(self, state: State, fresh: bool = False) -> None:
        """The trial plastic extension and strain of the last evaluation (``fresh``: of
        a pre-pass and force pass at ``state.u`` run now) become the history."""
        if fresh or SCALE not in state:
            self.prepass(state)
            saved = state.force.copy()
            self.force(state)
            state.force[...] = saved
        state[EXTENSION][...] = state[EXTENSION_TRIAL]
        state[STRAIN][...] = state[STRAIN_TRIAL]

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """Free energy W_i = k_theta theta_i^2 / 2 + (a_i / 2) sum_k wv_k (e_k - ep_k)^2
        (J/m^3), shape (n,), with the committed ep (= K theta^2 / 2 + (a_i / 2) sum wv
        (ed - ep)^2 while every bond is intact); the plastic work is not counted."""
        b = self.bonds
        ep = state[EXTENSION] if EXTENSION in state else np.zeros(b.n_bonds)
        return twins.energy_density(
            self.cloud.x, state.u, b.bond_i, b.bond_j, b.bond_length, self.omega_volume,
            state.intact, self.theta_scale, self.k_theta, self.extension_coef, ep,
            len(b.offsets) - 1,
        )  # fmt: skip

    def pair_force_coefficients(self, state: State) -> NDArray[np.float64]:
        """g_k (n_bonds,) (N/m^4) of the force pass at ``state.u`` from the committed
        history (the State is not changed): the virial stress of
        :meth:`~peridynamics.families.base.ForceModel.point_stress`."""
        b, p = self.bonds, self.plasticity
        n = len(b.offsets) - 1
        ep = state[EXTENSION] if EXTENSION in state else np.zeros(b.n_bonds)
        q = state[STRAIN][:n] if STRAIN in state else np.zeros(n)
        theta, scale, _ = twins.return_map(
            self.cloud.x, state.u, b.bond_i, b.bond_j, b.bond_length, self.omega_volume,
            state.intact, self.theta_scale, self.extension_coef, ep, q, self.shear,
            p.yield_stress, p.hardening_modulus,
        )  # fmt: skip
        g, _, _ = twins.pair_coefficients(
            self.cloud.x, state.u, b.bond_i, b.bond_j, b.bond_length, self.omega_volume,
            self.omega_volume_far, state.intact, theta, self.dilatation_coef,
            self.extension_coef, self.reverse, ep, scale,
        )  # fmt: skip
        return g

    def tangent(self, state: State) -> sp.csr_matrix:
        """The consistent (algorithmic) tangent K = -d(V f)/du (N/m), (3 n, 3 n) CSR, of
        the return from the committed history at ``state.u``
        (:func:`peridynamics.families.lps.plastic_tangent.plastic_lps_tangent`)."""
        n = len(self.bonds.offsets) - 1
        ep = state[EXTENSION] if EXTENSION in state else np.zeros(self.bonds.n_bonds)
        q = state[STRAIN][:n] if STRAIN in state else np.zeros(n)
        return plastic_lps_tangent(self, state, ep, q)
