"""The correspondence force model with a history-dependent (elastic-plastic) law.

The pre-pass of :class:`~peridynamics.families.correspondence.force.CorrespondenceForceModel`
(F, K^-1, the zero-energy-mode control) is kept; the stress comes from the return map of
the law (:mod:`~peridynamics.families.correspondence.plasticity`) at the corotated
strain ``U - I`` of ``F = R U`` (``P = J R s U^-1``), or, when the law's ``strain`` is
``"logarithmic"``, at the Hencky strain ``ln U`` (the rotated Kirchhoff stress T,
``P = R T U^-1``), starting from the committed history:

* ``plastic_history`` (n, h): the committed history (a history field: checkpoints keep
  it; zero at the start);
* ``plastic_history_trial`` (n, h): what the last evaluation proposes; the solver
  commits it (:meth:`PlasticCorrespondenceModel.commit_history`) on an accepted step:
  every explicit step, an accepted load step of dynamic relaxation, never inside an
  iteration.

The force at a displacement is then a function of that displacement and the committed
history, so dynamic relaxation and the finite-difference tangent see a fixed law inside
a load step. The stabilisation stays elastic (the linearised bonds of the reference).
A built-in law runs in the Numba kernel
:func:`peridynamics.kernels.plasticity.corotated_update` (log strain:
:func:`peridynamics.kernels.finite_plasticity.hencky_update`); a user law (``update`` of
:class:`~peridynamics.families.correspondence.plasticity.PlasticLaw`) runs on the batch
of owned points after a NumPy polar decomposition.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import FieldSpec
from peridynamics.families.correspondence.force import (
    CorrespondenceConstants,
    CorrespondenceForceModel,
)
from peridynamics.families.correspondence.plasticity import check_strain
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import correspondence as corr_kernels
from peridynamics.kernels import finite_plasticity as finite_kernels
from peridynamics.kernels import plasticity as kernels
from peridynamics.kernels import reference_plasticity as twins

if TYPE_CHECKING:
    from peridynamics.state import State

F64 = NDArray[np.float64]
HISTORY = "plastic_history"
TRIAL = "plastic_history_trial"


class PlasticCorrespondenceModel(CorrespondenceForceModel):
    """Correspondence force model whose stress law has history (plasticity).

    Parameters
    ----------
    cloud : PointCloud
        3-D, or 2-D plane strain (plane stress is refused).
    bonds : Bonds
    material : CorrespondenceMaterial with ``plasticity`` set.
    plasticity : a built-in law (``law_id``, ``params``) or a :class:`PlasticLaw`.
    """

    name: ClassVar[str] = "correspondence"

    def __init__(
        self, cloud: PointCloud, bonds: Bonds, material: CorrespondenceConstants, plasticity: Any
    ) -> None:
        if cloud.dim == 2 and cloud.plane != "strain":
            raise ValueError(
                "material.plasticity needs a 3-D body or geometry.plane: strain (the return "
                "map of plane stress is not implemented)"
            )
        super().__init__(cloud, bonds, material)
        size = getattr(plasticity, "history_size", None)
        if not (
            isinstance(size, int) and size > 0 and callable(getattr(plasticity, "update", None))
        ):
            raise TypeError(
                "material.plasticity must be a law with an int history_size > 0 and "
                "update(strain, history, lame, shear) (PlasticLaw)"
            )
        self.plasticity = plasticity
        self.history_size = size
        self._law_id: int | None = getattr(plasticity, "law_id", None)
        #: the strain of the return map: "small" (U - I) or "logarithmic" (ln U)
        self.strain: str = getattr(plasticity, "strain", "small")
        check_strain(self.strain)  # a user law's too
        self._params = (
            plasticity.params(self.law.lame, self.law.shear) if self._law_id is not None else None
        )
        self._stress: F64 | None = None
        #: the committed history last read (the stresses of :meth:`cauchy_stress`)
        self._committed: F64 | None = None

    def state_fields(self) -> tuple[FieldSpec, ...]:
        """The elastic model's fields, the committed history (a history field) and the
        trial history, both (n, history_size)."""
        h = self.history_size
        return super().state_fields() + (
            FieldSpec(HISTORY, components=h, history=True),
            FieldSpec(TRIAL, components=h),
        )

    def update(self, fgrad: F64, active: F64, history: F64) -> tuple[F64, F64, F64]:
        """(P (n, d, d), s (n, 3, 3), trial history (n, h)) at deformation gradients
        ``fgrad`` (n, d, d) from the committed ``history``; fresh arrays. With the log
        strain, s is the rotated Kirchhoff stress T (Pa)."""
        n, d, _ = fgrad.shape
        if self._law_id is not None:
            piola = np.empty((n, d, d))
            stress = np.empty((n, 3, 3))
            trial = np.empty_like(history)
            kernel = (
                finite_kernels.hencky_update
                if self.strain == "logarithmic"
                else kernels.corotated_update
            )
            kernel(
                np.ascontiguousarray(fgrad), np.ascontiguousarray(active), self._law_id,
                self._params, np.ascontiguousarray(history), trial, piola, stress,
            )  # fmt: skip
            return piola, stress, trial
        f = np.tile(np.eye(3), (n, 1, 1))
        f[:, :d, :d] = fgrad
        if self.strain == "logarithmic":
            r, strain, u_inv = twins.log_stretch(f)
            scale: F64 = np.ones(n)  # P = R T U^-1
        else:
            r, u = twins.polar(f)
            strain = 0.5 * (u + np.swapaxes(u, 1, 2)) - np.eye(3)
            u_inv = np.asarray(np.linalg.inv(u), dtype=np.float64)
            scale = np.asarray(np.linalg.det(f), dtype=np.float64)
        stress, trial = self.plasticity.update(strain, history, self.law.lame, self.law.shear)
        stress = np.asarray(stress, dtype=np.float64)
        trial = np.asarray(trial, dtype=np.float64)
        if stress.shape != (n, 3, 3) or trial.shape != history.shape:
            raise ValueError(
                f"material.plasticity.update returned shapes {stress.shape}, {trial.shape}; "
                f"expected {(n, 3, 3)}, {history.shape}"
            )
        piola = scale[:, None, None] * r @ stress @ u_inv
        on = active > 0
        piola = np.where(on[:, None, None], piola, 0.0)[:, :d, :d]
        stress = np.where(on[:, None, None], stress, 0.0)
        return piola, stress, np.where(on[:, None], trial, history)

    def _force_tensor(
        self,
        state: State,
        fgrad: F64,
        kinv: F64,
        sigma_s: F64,
        active: F64,
        work: F64,
        amat: F64,
    ) -> None:
        """A = (P - sigma^s) K^-1 with P from the return map; the trial history into
        the State."""
        n = len(fgrad)
        history = state[HISTORY][:n]
        self._committed = history
        piola, stress, trial = self.update(fgrad, active, history)
        state[TRIAL][:n] = trial
        self._stress = stress
        amat[...] = np.einsum("nab,nbc->nac", piola - sigma_s, kinv)

    def commit_history(self, state: State, fresh: bool = False) -> None:
        """The trial history of the last evaluation (``fresh``: of a pre-pass at
        ``state.u`` run now) becomes the committed history."""
        if fresh or TRIAL not in state:
            self.prepass(state)
        n = len(self.bonds.offsets) - 1
        state[HISTORY][:n] = state[TRIAL][:n]

    def _point_update(self, u: F64, intact: NDArray[np.uint8], history: F64 | None) -> tuple:
        n = len(self.bonds.offsets) - 1
        fgrad, _, _, _, active, stab = self.kinematics(u, intact)
        if history is None:
            history = np.zeros((n, self.history_size))
        return (*self.update(fgrad[:n], active[:n], history[:n]), fgrad, active, stab)

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """Elastic (stored) energy ``s : C^-1 : s / 2`` at ``state.u`` from the committed
        history, plus the stabilisation energy (J/m^3), shape (n,). The plastic work is
        dissipated and not counted."""
        b = self.bonds
        n = len(b.offsets) - 1
        hist = state[HISTORY] if HISTORY in state else None
        _, stress, _, fgrad, active, stab = self._point_update(state.u, state.intact, hist)
        lam, mu = self.law.lame, self.law.shear
        bulk = lam + 2.0 * mu / 3.0
        tr = np.trace(stress, axis1=1, axis2=2)
        dev = stress - tr[:, None, None] / 3.0 * np.eye(3)
        w = np.einsum("nab,nab->n", dev, dev) / (4.0 * mu) + tr * tr / (18.0 * bulk)
        extra = np.empty(n)
        corr_kernels.stabilization_energy(
            self.bond_xi, self.length, state.u, b.offsets, b.bond_j, self.weight, state.intact,
            fgrad, stab, self.mode, extra,
        )  # fmt: skip
        return np.asarray(active[:n] * w + extra)

    def cauchy_stress(self, u: F64, intact: NDArray[np.uint8]) -> F64:
        """Cauchy stress ``R s R^T`` (Pa), (n, d, d), at ``u`` from the history the last
        pre-pass read (zero history before any); zero on a degenerate point."""
        piola, _, _, fgrad, active, _ = self._point_update(u, intact, self._committed)
        n = len(piola)
        f = fgrad[:n]
        jac = np.linalg.det(f)
        jac = np.where(jac > 0, jac, 1.0)
        sigma = np.einsum("nab,ncb->nac", piola, f) / jac[:, None, None]
        return np.asarray(sigma * active[:n, None, None])

    def point_stress(self, state: State) -> NDArray[np.float64]:
        """:meth:`cauchy_stress` at ``state.u`` from the State's committed history."""
        if HISTORY in state:
            self._committed = state[HISTORY]
        return self.cauchy_stress(state.u, state.intact)
