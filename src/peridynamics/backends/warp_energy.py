"""The point strain-energy density W_i (J/m^3) on the Warp device.

:meth:`peridynamics.evaluation.measures.Measures.state_energies` sums ``W_i V_i`` on the host,
which on
the Warp backend needs ``u`` and the bond flags copied back and a host pass over every
bond. :class:`DeviceEnergy` computes W_i on the device with the host's arithmetic
(:mod:`peridynamics.backends._warp_energy_dsl`), so only n floats come back; the
kinetic energy ``1/2 sum rho_i V_i |v_i|^2`` stays on the host (it needs ``v`` only).

Force models (:func:`supports`): PMB (1-D, 2-D, 3-D; with SED softening pass the
softening's device stiffness), LPS (2-D, 3-D) and correspondence (2-D, 3-D; the stress
laws with a device kernel, every stabilisation). Not ported: bond-softening PMB
(``damage.bond_law``), micropolar, multi-body assemblies, float32 PMB.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from peridynamics.backends.warp_device import DeviceModel, DeviceState

try:
    from peridynamics.backends._warp_correspondence_prepass_dsl import corr_prepass
    from peridynamics.backends._warp_energy_dsl import (
        corr_energy_density,
        lps_energy_density,
        pmb_energy_density,
    )
except ImportError:  # pragma: no cover - warp-lang absent
    pass

#: the correspondence stress laws with a device kernel (ids of both DSL modules)
LAWS = {"st_venant_kirchhoff": 0, "linear_elastic": 1}


def _kind(model: Any) -> tuple[str | None, str]:
    """(``"pmb"``, ``"lps"``, ``"correspondence"`` or None, why not)."""
    from peridynamics.families.correspondence.force import CorrespondenceForceModel
    from peridynamics.families.lps.force import LPSForceModel
    from peridynamics.families.pmb.force import PMBForceModel
    from peridynamics.families.pmb_softening.force import PMBSofteningForceModel

    fm = model.force_model
    name = getattr(fm, "name", type(fm).__name__)
    if len(model.bonds.offsets) - 1 != model.cloud.n_points:
        return None, "serial models only (every point owns its family)"
    if isinstance(fm, PMBForceModel) and not isinstance(fm, PMBSofteningForceModel):
        if getattr(fm, "precision", "float64") != "float64":
            return None, "float32 PMB stiffness"
        return "pmb", ""
    if isinstance(fm, LPSForceModel):
        return "lps", ""
    if isinstance(fm, CorrespondenceForceModel):
        if fm.law.name not in LAWS:
            return None, f"correspondence law {fm.law.name!r} has no device kernel"
        if fm.mode not in (0, 1, 2):  # pragma: no cover - the material rejects it first
            return None, f"correspondence stabilisation mode {fm.mode}"
        return "correspondence", ""
    return None, f"force model {name!r} has no device energy kernel"


def supports(model: Any) -> bool:
    """True when :class:`DeviceEnergy` computes the strain energy density of ``model``."""
    return _kind(model)[0] is not None


class DeviceEnergy:
    """Point strain-energy density W_i (J/m^3) of the model's force model on the device,
    the same values as ``model.force_model.energy_density(state)`` (module docstring).

    Parameters
    ----------
    model : Evaluator
        :func:`supports` must be True (ValueError otherwise).
    dm : DeviceModel
    stiffness : wp.array(float64) (n_bonds,), optional
        PMB only: the bond stiffness the device force pass reads (with SED softening
        ``DeviceSED.stiffness``,
        which also is the array kept under ``"stiffness"``). Default: the force model's
        stiffness uploaded under ``"stiffness"`` (the cached array when a family or
        DeviceSED uploaded it first).

    Attributes
    ----------
    kind : str
        ``"pmb"``, ``"lps"`` or ``"correspondence"``.
    out : wp.array(float64) (n,)
        The result of :meth:`strain_energy_density` (overwritten by every call).
    """

    def __init__(self, model: Any, dm: DeviceModel, stiffness: Any = None) -> None:
        kind, why = _kind(model)
        if kind is None:
            raise ValueError(f"DeviceEnergy: {why}")
        fm = model.force_model
        f64 = np.float64
        w = dm.wp
        n = dm.n
        self.dm = dm
        self.kind = kind
        self.out = dm.zeros(n, w.float64)
        if stiffness is not None and kind != "pmb":
            raise ValueError("DeviceEnergy: stiffness is for the PMB force model only")
        if kind == "pmb":
            if stiffness is None:
                stiffness = dm.upload("stiffness", np.asarray(fm.stiffness, dtype=f64))
            if stiffness.dtype != w.float64 or tuple(stiffness.shape) != (dm.n_bonds,):
                raise ValueError(
                    f"DeviceEnergy: stiffness must be float64 of shape ({dm.n_bonds},), "
                    f"got {stiffness.dtype} {tuple(stiffness.shape)}"
                )
            self.stiffness = stiffness
        elif kind == "lps":
            b = fm.bonds
            self.length = dm.upload("bond_length", np.asarray(b.bond_length, dtype=f64))
            self.wv = dm.upload("lps_omega_volume", np.asarray(fm.omega_volume, dtype=f64))
            self.theta_scale = dm.upload("lps_theta_scale", np.asarray(fm.theta_scale, f64))
            self.a = dm.upload("lps_extension_coef", np.asarray(fm.extension_coef, f64))
            self.k_theta = float(fm.k_theta)
        else:
            from peridynamics.families.correspondence.force import DEGENERATE_RATIO

            d = dm.dim
            self.mode = int(fm.mode)
            self.law_id = LAWS[fm.law.name]
            self.lame = float(fm.law.lame)
            self.shear = float(fm.law.shear)
            self.ratio = float(DEGENERATE_RATIO)
            # as DeviceCorrespondence: the host's active * G * C / omega_0, active = 1
            self.silling_gc = float(1.0 * fm.silling_g * (fm.micromodulus / fm.bonds.horizon))
            self.xi = dm.upload("corr_bond_xi", np.asarray(fm.bond_xi, dtype=f64))
            self.length = dm.upload("bond_length", np.asarray(fm.length, dtype=f64))
            self.weight = dm.upload("corr_weight", np.asarray(fm.weight, dtype=f64))
            self.det_reference = dm.upload("corr_det_reference", np.asarray(fm.det_reference, f64))
            self.stab_base = dm.upload("corr_stab_base", np.asarray(fm.stab_base[:n], f64))
            # work arrays of the pre-pass (the State's fields are left alone)
            self.fgrad = dm.zeros((n, d * d), w.float64)
            self.amat = dm.zeros((n, d * d), w.float64)
            self.stab = dm.zeros(n, w.float64)
            self.active = dm.zeros(n, w.float64)
            self.s1 = dm.zeros(n, w.float64)

    def strain_energy_density(self, ds: DeviceState) -> Any:
        """W_i (J/m^3) at ``ds.u`` with the bonds ``ds.intact``: ``out``, a
        wp.array(float64) (n,) on the device (the DeviceState is not changed)."""
        dm = self.dm
        if self.kind == "pmb":
            dm.launch(
                pmb_energy_density,
                dm.n,
                [dm.x, ds.u, dm.offsets, dm.bond_j, self.stiffness, ds.intact, self.out],
            )
        elif self.kind == "lps":
            dm.launch(
                lps_energy_density,
                dm.n,
                [dm.x, ds.u, dm.offsets, dm.bond_j, self.length, self.wv, ds.intact,
                 self.theta_scale, self.k_theta, self.a, self.out],
            )  # fmt: skip
        else:
            dm.launch(
                corr_prepass,
                dm.n,
                [self.xi, self.length, ds.u, dm.offsets, dm.bond_j, self.weight, ds.intact,
                 self.det_reference, self.ratio, self.mode, self.stab_base, self.silling_gc,
                 self.lame, self.shear, self.law_id, 0, self.fgrad, self.amat, self.stab,
                 self.active, self.s1],
            )  # fmt: skip
            dm.launch(
                corr_energy_density,
                dm.n,
                [self.xi, self.length, ds.u, dm.offsets, dm.bond_j, self.weight, ds.intact,
                 self.fgrad, self.stab, self.active, self.mode, self.lame, self.shear,
                 self.law_id, self.out],
            )  # fmt: skip
        return self.out
