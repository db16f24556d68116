"""The correspondence (non-ordinary state-based) family on the Warp device: the
:class:`~peridynamics.backends.warp_device.DeviceFamily` of
:class:`~peridynamics.families.correspondence.force.CorrespondenceForceModel`, with its three
zero-energy-mode controls (``material.stabilization``: none, silling2017, lbscmm) and the
built-in stress laws (``material.law``: st_venant_kirchhoff, linear_elastic).

One evaluation runs, as :meth:`peridynamics.evaluation.evaluator.Evaluator.evaluate` on the host:
with
``commit`` the damage law's trial and commit, then the pre-pass (K, F, sigma^s, A =
(P - sigma^s) K^-1 and the stabilisation coefficient of every point) and the force pass.
Damage laws: critical stretch
(:class:`~peridynamics.backends.warp_damage.DeviceCriticalStretch`) and the
correspondence failure law (critical stretch and/or the maximum principal stress,
with the degenerate-family rounds): its trial takes the largest principal Cauchy
stress of a fresh pre-pass at the displacement and the bonds
before breaking, as the host law does.

The pre-pass writes the State's fields ``deformation_gradient``, ``force_tensor``,
``stabilization`` and ``family_active`` (and the force pass ``max_stretch``) when the
DeviceState has them, so a download shows what the host evaluation leaves there.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from peridynamics.backends.warp_damage import DeviceCriticalStretch, device_max_stretch
from peridynamics.backends.warp_device import DeviceModel, DeviceState

try:
    from peridynamics.backends._warp_correspondence_dsl import (
        corr_commit,
        corr_degenerate,
        corr_force,
        corr_propose,
        corr_spread,
    )
    from peridynamics.backends._warp_correspondence_prepass_dsl import corr_prepass
except ImportError:  # pragma: no cover - warp-lang absent
    pass

#: the stress laws with a device kernel (ids of :mod:`peridynamics.kernels.correspondence_points`)
LAWS = {"st_venant_kirchhoff": 0, "linear_elastic": 1}
#: the State fields of :meth:`CorrespondenceForceModel.state_fields`: (name, tensor?)
FIELDS = (
    ("deformation_gradient", True),
    ("force_tensor", True),
    ("stabilization", False),
    ("family_active", False),
)


def supports(model: Any) -> str | None:
    """None when :class:`DeviceCorrespondence` runs ``model``, else a one-line reason
    naming the deck key."""
    from peridynamics.damage.critical_stretch import CriticalStretchLaw
    from peridynamics.families.correspondence.force import CorrespondenceForceModel

    fm = model.force_model
    if not isinstance(fm, CorrespondenceForceModel):
        name = getattr(fm, "name", type(fm).__name__)
        key = "bodies" if name == "bodies" else "material.model"
        return (
            f"{key}: the Warp correspondence family runs one material.model correspondence "
            f"body (got {name!r})"
        )
    if fm.law.name not in LAWS:
        return (
            f"material.law: the Warp backend runs {sorted(LAWS)} for correspondence "
            f"(got {fm.law.name!r})"
        )
    if fm.mode not in (0, 1, 2):  # pragma: no cover - the material rejects it first
        return f"material.stabilization: not on the Warp device (mode {fm.mode})"
    law = model.damage_law
    if not isinstance(law, CriticalStretchLaw):  # CorrespondenceFailureLaw is one
        return (
            "damage.model: the Warp backend supports critical stretch and the correspondence "
            f"failure law for correspondence (got {getattr(law, 'name', type(law).__name__)!r})"
        )
    if fm.cloud.dim not in (2, 3):  # pragma: no cover - the force model rejects it first
        return f"discretisation: correspondence is 2-D or 3-D (got {fm.cloud.dim}-D)"
    if len(fm.bonds.offsets) - 1 != fm.cloud.n_points:
        return "solver.backend: the Warp backend is serial (every point owns its family)"
    return None


class DeviceCorrespondence:
    """Correspondence force evaluation on the device (a ``DeviceFamily``).

    Parameters
    ----------
    model : Evaluator
        Its ``force_model`` a :class:`CorrespondenceForceModel` with a built-in law, its
        damage law critical stretch (``damage.model: none`` breaks nothing) or
        :class:`~peridynamics.damage.principal_stress.CorrespondenceFailureLaw`;
        ValueError otherwise (:func:`supports`).
    dm : DeviceModel

    Attributes
    ----------
    mode : int
        0 none, 1 Silling (2017), 2 LBSCMM.
    failure : bool
        True when the damage law is the correspondence failure law (else ``damage`` is
        a :class:`DeviceCriticalStretch`).
    xi : wp.array2d(float64) (n_bonds, d); length, weight : wp.array(float64) (n_bonds,)
    det_reference, stab_base : wp.array(float64) (n,)
    fgrad, amat : wp.array2d(float64) (n, d*d); stab, active, smax, s1 : (n,)
        Work arrays used where the DeviceState has no field of that name.
    """

    def __init__(self, model: Any, dm: DeviceModel) -> None:
        reason = supports(model)
        if reason is not None:
            raise ValueError(reason)
        from peridynamics.damage.principal_stress import (
            _DEGENERATE_ROUNDS,
            CorrespondenceFailureLaw,
        )
        from peridynamics.families.correspondence.force import DEGENERATE_RATIO

        fm = model.force_model
        law = model.damage_law
        f64 = np.float64
        w = dm.wp
        n, d = dm.n, dm.dim
        self.dm = dm
        self.n, self.dim = n, d
        self.mode = int(fm.mode)
        self.law_id = LAWS[fm.law.name]
        self.lame = float(fm.law.lame)
        self.shear = float(fm.law.shear)
        self.ratio = float(DEGENERATE_RATIO)
        # the host's active * G * C / omega_0 with active = 1: (G * C) / omega_0
        self.silling_gc = float(1.0 * fm.silling_g * (fm.micromodulus / fm.bonds.horizon))
        self.rounds = int(_DEGENERATE_ROUNDS)
        self.xi = dm.upload("corr_bond_xi", np.asarray(fm.bond_xi, dtype=f64))
        self.length = dm.upload("bond_length", np.asarray(fm.length, dtype=f64))
        self.weight = dm.upload("corr_weight", np.asarray(fm.weight, dtype=f64))
        self.det_reference = dm.upload("corr_det_reference", np.asarray(fm.det_reference, f64))
        self.stab_base = dm.upload("corr_stab_base", np.asarray(fm.stab_base[:n], f64))
        self.fgrad = dm.zeros((n, d * d), w.float64)
        self.amat = dm.zeros((n, d * d), w.float64)
        self.stab = dm.zeros(n, w.float64)
        self.active = dm.zeros(n, w.float64)
        self.smax = dm.zeros(n, w.float64)
        self.s1 = dm.zeros(n, w.float64)
        self.failure = isinstance(law, CorrespondenceFailureLaw)
        if self.failure:
            s0 = np.asarray(law.point_s0, dtype=f64)
            self.damage_active = bool(law.active)
            self.stretch_on = bool(np.isfinite(s0).any())
            self.stress_on = bool(math.isfinite(law.tensile_strength))
            self.tensile_strength = float(law.tensile_strength)
            self.s0 = dm.upload("point_s0", s0)
            self.protected = dm.upload("corr_protected", np.asarray(law.protected, dtype=np.uint8))
            self.proposed = dm.zeros(dm.n_bonds, w.uint8)
            self.bad = dm.zeros(n, w.uint8)
            self.any_proposed = dm.zeros(1, w.int32)
        else:
            self.damage = DeviceCriticalStretch(model, dm)

    # -- fields -----------------------------------------------------------------------
    def _field(self, ds: DeviceState, name: str, tensor: bool, own: Any) -> Any:
        """``ds.fields[name]`` when the State has it (checked: float64 of the right
        shape), else this family's own work array ``own``."""
        got = ds.fields.get(name)
        if got is None:
            return own
        shape = (self.n, self.dim * self.dim) if tensor else (self.n,)
        if got.dtype != self.dm.wp.float64 or tuple(got.shape) != shape:
            raise ValueError(
                f"state field {name!r} must be float64 of shape {shape}, "
                f"got {got.dtype} {tuple(got.shape)}"
            )
        return got

    def outputs(self, ds: DeviceState) -> tuple[Any, Any, Any, Any, Any]:
        """(F, A, stab, active, max_stretch) device arrays the passes write."""
        own = (self.fgrad, self.amat, self.stab, self.active)
        got = tuple(
            self._field(ds, name, tensor, a) for (name, tensor), a in zip(FIELDS, own, strict=True)
        )
        smax = self._field(ds, "max_stretch", False, self.smax)
        return got[0], got[1], got[2], got[3], smax

    # -- passes -----------------------------------------------------------------------
    def prepass(self, ds: DeviceState, want_stress: bool = False) -> None:
        """F, A, the stabilisation coefficient and the active flag of every point at
        ``ds.u`` with the bonds ``ds.intact`` (and, ``want_stress``, the largest
        principal Cauchy stress into ``self.s1``)."""
        dm = self.dm
        fgrad, amat, stab, active, _ = self.outputs(ds)
        dm.launch(
            corr_prepass,
            dm.n,
            [self.xi, self.length, ds.u, dm.offsets, dm.bond_j, self.weight, ds.intact,
             self.det_reference, self.ratio, self.mode, self.stab_base, self.silling_gc,
             self.lame, self.shear, self.law_id, int(want_stress), fgrad, amat, stab,
             active, self.s1],
        )  # fmt: skip

    def force(self, ds: DeviceState) -> None:
        """Overwrite ``ds.force`` from the fields of the last :meth:`prepass`."""
        dm = self.dm
        fgrad, amat, stab, _, smax = self.outputs(ds)
        dm.launch(
            corr_force,
            dm.n,
            [self.xi, self.length, ds.u, dm.offsets, dm.bond_j, self.weight, ds.intact,
             amat, fgrad, stab, self.mode, ds.force, smax],
        )  # fmt: skip

    def commit_failure(self, ds: DeviceState) -> None:
        """Trial and commit of the correspondence failure law at ``ds.u`` (per-point
        counts into ``ds.broken``)."""
        dm = self.dm
        if not self.damage_active:
            ds.broken.zero_()
            return
        if self.stress_on:
            self.prepass(ds, want_stress=True)
        self.any_proposed.zero_()
        dm.launch(
            corr_propose,
            dm.n,
            [dm.x, ds.u, dm.offsets, dm.bond_j, ds.intact, self.s0, int(self.stretch_on),
             self.s1, self.tensile_strength if self.stress_on else 0.0,
             int(self.stress_on), self.protected, self.proposed, self.any_proposed],
        )  # fmt: skip
        for _ in range(self.rounds):
            dm.launch(
                corr_degenerate,
                dm.n,
                [self.xi, dm.offsets, self.weight, ds.intact, self.proposed,
                 self.det_reference, self.ratio, self.any_proposed, self.bad],
            )  # fmt: skip
            dm.launch(
                corr_spread, dm.n, [dm.offsets, dm.bond_j, ds.intact, self.bad, self.proposed]
            )
        dm.launch(corr_commit, dm.n, [dm.offsets, self.proposed, ds.intact, ds.broken])

    def evaluate(self, ds: DeviceState, commit: bool) -> None:
        """Overwrite ``ds.force`` (N/m^3) at ``ds.u``; with ``commit`` first break the
        bonds of the damage law (counts into ``ds.broken``; zeroed otherwise)."""
        if not commit:
            ds.broken.zero_()
        elif self.failure:
            self.commit_failure(ds)
        else:
            self.damage.commit(ds)
        self.prepass(ds)
        self.force(ds)

    def max_stretch(self, ds: DeviceState, out: Any) -> None:
        """Largest stretch of an intact bond per point into ``out`` (wp float64 (n,))."""
        device_max_stretch(self.dm, ds, out)
