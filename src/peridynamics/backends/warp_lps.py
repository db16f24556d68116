"""The LPS (ordinary state-based linear peridynamic solid) family on the Warp device: the
:class:`~peridynamics.backends.warp_device.DeviceFamily` of
:class:`~peridynamics.families.lps.force.LPSForceModel`.

One evaluation runs, as :meth:`peridynamics.evaluation.evaluator.Evaluator.evaluate` on the host:
the
critical-stretch trial and commit (with ``commit``), the dilatation pre-pass, the force
pass. The constants (influence weights of both bond ends, ``tf / m_i``, ``k_theta tf /
m_i``, ``alpha / m_i``) are the host model's arrays, uploaded once; the weighted volume
stays fixed when bonds break, as on the host.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from peridynamics.backends.warp_damage import DeviceCriticalStretch, device_max_stretch
from peridynamics.backends.warp_device import DeviceModel, DeviceState

try:
    from peridynamics.backends._warp_lps_dsl import lps_dilatation, lps_force
except ImportError:  # pragma: no cover - warp-lang absent
    pass

#: the State field the pre-pass writes (:meth:`LPSForceModel.state_fields`)
DILATATION = "dilatation"


def supports(model: Any) -> str | None:
    """None when :class:`DeviceLPS` runs ``model``, else a one-line reason naming the
    deck key."""
    from peridynamics.damage.critical_stretch import CriticalStretchLaw
    from peridynamics.families.lps.force import LPSForceModel

    fm = model.force_model
    if not isinstance(fm, LPSForceModel):
        name = getattr(fm, "name", type(fm).__name__)
        key = "bodies" if name == "bodies" else "material.model"
        return f"{key}: the Warp LPS family runs one material.model lps body (got {name!r})"
    law = model.damage_law
    if not isinstance(law, CriticalStretchLaw):
        return (
            f"damage.model: the Warp backend supports critical stretch for LPS "
            f"(got {getattr(law, 'name', type(law).__name__)!r})"
        )
    if fm.cloud.dim not in (2, 3):  # pragma: no cover - LPSMaterial rejects it first
        return f"discretisation: LPS on the Warp device is 2-D or 3-D (got {fm.cloud.dim}-D)"
    if len(fm.bonds.offsets) - 1 != fm.cloud.n_points:
        return "solver.backend: the Warp backend is serial (every point owns its family)"
    return None


class DeviceLPS:
    """LPS force evaluation on the device (a ``DeviceFamily``).

    Parameters
    ----------
    model : Evaluator
        Its ``force_model`` an :class:`~peridynamics.families.lps.force.LPSForceModel`, its
        damage law a critical-stretch law (``damage.model: none`` is one that breaks
        nothing); ValueError otherwise (:func:`supports`).
    dm : DeviceModel

    Attributes
    ----------
    damage : DeviceCriticalStretch
    length, wv, wvf : wp.array(float64) (n_bonds,)
        L_k, wv_k = omega_ik beta_k V_j, wvf_k = omega_jk beta_k V_j (``wv`` itself
        without the surface correction).
    theta_scale, cd, a : wp.array(float64) (n,)
        tf / m_i, k_theta tf / m_i, alpha / m_i.
    theta : wp.array(float64) (n,)
        The dilatation, where the DeviceState has no ``dilatation`` field.
    """

    def __init__(self, model: Any, dm: DeviceModel) -> None:
        reason = supports(model)
        if reason is not None:
            raise ValueError(reason)
        fm = model.force_model
        b = fm.bonds
        f64 = np.float64
        self.dm = dm
        self.damage = DeviceCriticalStretch(model, dm)
        self.length = dm.upload("bond_length", np.asarray(b.bond_length, dtype=f64))
        self.wv = dm.upload("lps_omega_volume", np.asarray(fm.omega_volume, dtype=f64))
        if fm.omega_volume_far is fm.omega_volume:  # symmetric weights: one array
            self.wvf = self.wv
        else:
            self.wvf = dm.upload("lps_omega_volume_far", np.asarray(fm.omega_volume_far, f64))
        self.theta_scale = dm.upload("lps_theta_scale", np.asarray(fm.theta_scale, f64))
        self.cd = dm.upload("lps_dilatation_coef", np.asarray(fm.dilatation_coef, f64))
        self.a = dm.upload("lps_extension_coef", np.asarray(fm.extension_coef, f64))
        self.theta = dm.zeros(dm.n, dm.wp.float64)

    def dilatation(self, ds: DeviceState) -> Any:
        """The device array the pre-pass writes: ``ds.fields["dilatation"]`` when the
        State has that field (so a download shows it), else this family's own."""
        got = ds.fields.get(DILATATION)
        if got is None:
            return self.theta
        if got.dtype != self.dm.wp.float64 or tuple(got.shape) != (self.dm.n,):
            raise ValueError(
                f"state field {DILATATION!r} must be float64 of shape ({self.dm.n},), "
                f"got {got.dtype} {tuple(got.shape)}"
            )
        return got

    def evaluate(self, ds: DeviceState, commit: bool) -> None:
        """Overwrite ``ds.force`` (N/m^3) at ``ds.u``; with ``commit`` first break the
        bonds at the critical stretch (counts into ``ds.broken``; zeroed otherwise)."""
        dm = self.dm
        if commit:
            self.damage.commit(ds)
        else:
            ds.broken.zero_()
        theta = self.dilatation(ds)
        dm.launch(
            lps_dilatation,
            dm.n,
            [dm.x, ds.u, dm.offsets, dm.bond_j, self.length, self.wv, ds.intact,
             self.theta_scale, theta],
        )  # fmt: skip
        dm.launch(
            lps_force,
            dm.n,
            [dm.x, ds.u, dm.offsets, dm.bond_j, self.length, self.wv, self.wvf, ds.intact,
             theta, self.cd, self.a, ds.force],
        )  # fmt: skip

    def max_stretch(self, ds: DeviceState, out: Any) -> None:
        """Largest stretch of an intact bond per point into ``out`` (wp float64 (n,))."""
        device_max_stretch(self.dm, ds, out)
