"""Viscoelastic linear peridynamic solid (Mitchell (2011), SAND2011-8064; LAMMPS
``pair_style peri/ves``), 3-D.

The deviatoric part of the LPS force state is split into an equilibrium (elastic) part
of weight ``1 - lambda`` and a Maxwell part of weight ``lambda`` with relaxation time
tau (a standard linear solid in shear; the bulk response stays elastic):

    t_k = (3 K theta_i / m_i) w_k L_k + (15 mu / m_i) w_k (ed_k - lambda eb_k),

``ed_k = e_k - theta_i L_k / 3`` the deviatoric extension of the directed bond k and
``eb_k`` its back extension, integrated exactly for ``ed`` linear in time within a step
(:mod:`peridynamics.kernels.viscoelastic`). With ``eb = 0`` this is the elastic LPS
(:class:`~peridynamics.families.lps.force.LPSForceModel`, its force pass runs
unchanged); the Maxwell pass adds ``-lambda a_i wv_k eb_k`` per directed bond.

History (bond fields, checkpointed): ``viscoelastic_back_extension`` and
``viscoelastic_deviatoric_extension`` (eb and ed at the last commit) and the point field
``viscoelastic_commit_time`` (the time of that commit, s, the same on every point). An
evaluation at time ``t = state.t + step_time`` (the end of the step the solver is
taking: explicit ``t + dt``, dynamic relaxation the next load step's pseudo-time) writes
the trial fields ``*_trial``; :meth:`ViscoelasticLPSModel.commit_history` (called by the
evaluator where damage is committed) makes them the history. A second commit at the same
time (a re-solve after bonds broke) adds no relaxation (dt = 0).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import FieldSpec
from peridynamics.families.lps.force import LPSForceModel
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import viscoelastic as kernels

if TYPE_CHECKING:
    import scipy.sparse as sp

    from peridynamics.state import State

BACK = "viscoelastic_back_extension"
DEVIATORIC = "viscoelastic_deviatoric_extension"
BACK_TRIAL = "viscoelastic_back_extension_trial"
DEVIATORIC_TRIAL = "viscoelastic_deviatoric_extension_trial"
COMMIT_TIME = "viscoelastic_commit_time"


@dataclass(frozen=True)
class Viscoelasticity:
    """The Maxwell part of the deviatoric response.

    Parameters
    ----------
    fraction : float
        lambda in [0, 1]: the share of the shear modulus that relaxes (the relaxed shear
        modulus is ``(1 - lambda) mu``).
    relaxation_time : float
        tau > 0 (s).
    """

    fraction: float
    relaxation_time: float

    def __post_init__(self) -> None:
        if not 0.0 <= self.fraction <= 1.0:
            raise ValueError(
                f"material.viscoelastic.fraction must be in [0, 1], got {self.fraction}"
            )
        if not (np.isfinite(self.relaxation_time) and self.relaxation_time > 0):
            raise ValueError(
                "material.viscoelastic.relaxation_time must be a finite value > 0 s, got "
                f"{self.relaxation_time}"
            )


class ViscoelasticLPSModel(LPSForceModel):
    """LPS with a standard-linear-solid deviatoric response (module docstring).

    Parameters
    ----------
    cloud : PointCloud
        3-D.
    bonds : Bonds
        Serial bond list (every bond's reverse is in it).
    material : LPSMaterial
    viscoelastic : Viscoelasticity
    surface_correction : bool
        As :class:`~peridynamics.families.lps.force.LPSForceModel`.

    Attributes
    ----------
    step_time : float or None
        The time (s) one solver step advances (explicit ``dt``, dynamic relaxation
        ``load_time / load_steps``); set by the solver's builder
        (:meth:`bind_step_time`). None: an evaluation gives the instantaneous
        response (dt = 0) and a commit raises.
    """

    def __init__(
        self,
        cloud: PointCloud,
        bonds: Bonds,
        material: Any,
        viscoelastic: Viscoelasticity,
        surface_correction: bool = False,
    ) -> None:
        if cloud.dim != 3:
            raise ValueError(
                "material.viscoelastic needs a 3-D body (the 2-D deviatoric split is not "
                "implemented)"
            )
        super().__init__(cloud, bonds, material, surface_correction=surface_correction)
        self.viscoelastic = viscoelastic
        self.reverse = np.ascontiguousarray(bonds.reverse_index())
        self.step_time: float | None = None

    def bind_step_time(self, step_time: float) -> None:
        """The time (s) of one solver step (> 0)."""
        if not (np.isfinite(step_time) and step_time > 0):
            raise ValueError(f"the step time must be a finite value > 0 s, got {step_time}")
        self.step_time = float(step_time)

    def state_fields(self) -> tuple[FieldSpec, ...]:
        """The LPS dilatation, the bond history (eb, ed: history fields), its trial and
        the commit time."""
        return super().state_fields() + (
            FieldSpec(BACK, where="bond", history=True),
            FieldSpec(DEVIATORIC, where="bond", history=True),
            FieldSpec(BACK_TRIAL, where="bond"),
            FieldSpec(DEVIATORIC_TRIAL, where="bond"),
            FieldSpec(COMMIT_TIME, history=True),
        )

    def _now(self, state: State) -> float:
        """The end (s) of the step being taken: ``state.t + step_time``."""
        if self.step_time is None:
            raise RuntimeError(
                "ViscoelasticLPSModel.step_time is not set: call bind_step_time(dt) before "
                "committing a history (the solver builders do)"
            )
        return state.t + self.step_time

    def _increment(self, state: State) -> float:
        """dt (s) from the last commit to the end of the step being taken; 0 (the
        instantaneous response) before a step time is bound."""
        if self.step_time is None:
            return 0.0
        return max(self._now(state) - float(state[COMMIT_TIME][0]), 0.0)

    def force(self, state: State) -> None:
        """Elastic LPS force plus the Maxwell part at the end of the step being taken,
        from the committed history; the trial history into the State."""
        super().force(state)
        ve = self.viscoelastic
        decay, beta = kernels.decay_and_beta(self._increment(state), ve.relaxation_time)
        b = self.bonds
        kernels.viscous_force_3d(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            self.omega_volume_far, state.intact, state["dilatation"], self.extension_coef,
            self.reverse, ve.fraction, decay, beta, state[BACK], state[DEVIATORIC],
            state[BACK_TRIAL], state[DEVIATORIC_TRIAL], state.force,
        )  # fmt: skip

    def commit_history(self, state: State, fresh: bool = False) -> None:
        """The trial back and deviatoric extensions of the last evaluation (``fresh``: of
        a force pass at ``state.u`` run now) become the history, committed at the end of
        the step being taken."""
        if fresh:
            self.prepass(state)
            saved = state.force.copy()
            self.force(state)
            state.force[...] = saved
        t = self._now(state)
        state[BACK][...] = state[BACK_TRIAL]
        state[DEVIATORIC][...] = state[DEVIATORIC_TRIAL]
        state[COMMIT_TIME][...] = t

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """Free energy W_i = K theta_i^2 / 2 + (a_i / 2) sum_k wv_k ((1 - lambda) ed_k^2
        + lambda (ed_k - eb_k)^2) (J/m^3), shape (n,), with the committed back extension
        (Mitchell (2011)); the dissipated work is not counted."""
        w = super().energy_density(state)
        b = self.bonds
        lam = self.viscoelastic.fraction
        theta = np.zeros(state.u.shape[0])
        self._dilatation(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            state.intact, self.theta_scale, theta,
        )  # fmt: skip
        y = b.bond_xi + state.u[b.bond_j] - state.u[b.bond_i]
        e = np.sqrt(np.einsum("ij,ij->i", y, y)) - b.bond_length
        ed = e - theta[b.bond_i] * b.bond_length / 3.0
        eb = state[BACK]
        q = state.intact * self.omega_volume * (eb * eb - 2.0 * ed * eb)
        extra = (
            0.5
            * lam
            * self.extension_coef[: len(w)]
            * np.bincount(b.bond_i, q, minlength=len(w))[: len(w)]
        )
        return np.asarray(w + extra)

    def pair_force_coefficients(self, state: State) -> None:  # type: ignore[override]
        """None: the Maxwell part is not in the elastic pair coefficients."""
        return None

    def tangent(self, state: State) -> sp.csr_matrix | None:  # type: ignore[override]
        """None (the static solver is refused with ``material.viscoelastic``)."""
        return None
