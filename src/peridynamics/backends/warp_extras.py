"""Extras of the bond-based PMB model on the Warp device: viscous bond forces
(:class:`DeviceViscosity`, a :class:`~peridynamics.backends.warp_device.DeviceExtra`) and
strain-energy-density softening of the bond stiffness (:class:`DeviceSED`, the device
twin of :class:`~peridynamics.families.pmb_sed.stiffness.SoftenedStiffness`).

Per committing evaluation the solver runs, in the order of
:meth:`peridynamics.evaluation.evaluator.Evaluator.evaluate`:

1. the PMB force-and-break pass reading ``DeviceSED.stiffness``;
2. :meth:`DeviceSED.update` (energy with the initial stiffness at ``ds.u`` over the
   bonds left intact, levels raised, stiffness of the bonds of raised points rebuilt:
   it acts from the next evaluation on);
3. the extras, :meth:`DeviceViscosity.add` among them.

A pure (non-committing) evaluation skips step 2. After a checkpoint resume
(``ds.upload(host)``) :meth:`DeviceSED.restore` rebuilds the factors and the stiffness
from ``ds.fields["sed_level"]``, as ``Evaluator.on_restore`` does on the host.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from peridynamics.backends.warp_device import DeviceModel, DeviceState, to_device

try:
    from peridynamics.backends._warp_extras_dsl import (
        _sed_factor_all,
        _sed_levels,
        _sed_stiffness,
        _viscous_add,
    )
except ImportError:  # pragma: no cover - warp-lang absent
    pass


def supports(model: Any) -> str | None:
    """None when :class:`DeviceViscosity` and :class:`DeviceSED` can run the extras of
    ``model`` on the device, else a one-line reason naming the deck key."""
    from peridynamics.damage.critical_stretch import CriticalStretchLaw
    from peridynamics.families.pmb.force import PMBForceModel
    from peridynamics.families.pmb_softening.force import PMBSofteningForceModel

    if model.cloud.x.dtype != np.float64:
        return "discretisation: the Warp extras need float64 positions"
    sed = getattr(model, "_sed", None)
    if sed is None:
        return None
    fm = model.force_model
    if not isinstance(fm, PMBForceModel) or isinstance(fm, PMBSofteningForceModel):
        return (
            "damage.sed_softening: on the warp backend it needs material.model pmb, brittle bonds"
        )
    if getattr(fm, "precision", "float64") != "float64" or fm.stiffness.dtype != np.float64:
        return "solver.precision: damage.sed_softening on the warp backend needs float64"
    if not isinstance(model.damage_law, CriticalStretchLaw):
        return "damage.sed_softening: on the warp backend it needs damage.model critical_stretch"
    return None


class DeviceViscosity:
    """Viscous bond forces (PD wave dispersion (n.d.), eqs 45-56) on the device: the twin
    of :func:`~peridynamics.kernels.viscous.add_viscous_force` (same arithmetic order).

    Parameters
    ----------
    model : Evaluator
        With viscosity (``model.viscous_coefficients`` = (lin, quad)); bond weights
        ``model.bonds.bond_volume`` and ``model.inv_length`` are uploaded once.
    dm : DeviceModel
    """

    def __init__(self, model: Any, dm: DeviceModel) -> None:
        if model.viscous_coefficients is None:
            raise ValueError("DeviceViscosity: the model has no viscosity")
        self.dm = dm
        self.lin = float(model.viscous_coefficients[0])
        self.quad = float(model.viscous_coefficients[1])
        b = model.bonds
        self.weight = dm.upload("bond_volume", np.asarray(b.bond_volume, dtype=np.float64))
        self.inv_length = dm.upload("inv_length", np.asarray(model.inv_length, dtype=np.float64))

    def add(self, ds: DeviceState) -> None:
        """Add the viscous force density at ``ds.u``, ``ds.v`` to ``ds.force``."""
        dm = self.dm
        dm.launch(
            _viscous_add,
            dm.n,
            [
                dm.x, ds.u, ds.v, dm.offsets, dm.bond_j, self.inv_length, self.weight,
                ds.intact, self.lin, self.quad, ds.force,
            ],
        )  # fmt: skip


class DeviceSED:
    """SED softening of the PMB bond stiffness on the device (SED-PD (2021), eqs 18-24):
    the twin of :class:`~peridynamics.families.pmb_sed.stiffness.SoftenedStiffness`.

    Attributes
    ----------
    stiffness : wp.array(float64) (n_bonds,)
        The bond stiffness the PMB force pass must read; it is the array kept by the
        DeviceModel under the name ``"stiffness"`` (so a family that uploads the force
        model's stiffness under that name gets this very array).
    stiffness0 : wp.array(float64) (n_bonds,), the unsoftened stiffness.
    energy : wp.array(float64) (n,), point SED of the last :meth:`update` (J/m^3).
    factor : wp.array(float64) (n,), E_i / E of the levels.
    raised : wp.array(uint8) (n,), points whose level rose at the last :meth:`update`.
    Levels live in ``ds.fields["sed_level"]`` (int64 (n,)).
    """

    def __init__(self, model: Any, dm: DeviceModel) -> None:
        sed = model.sed_stiffness
        if sed is None:
            raise ValueError("DeviceSED: the model has no damage.sed_softening")
        why = supports(model)
        if why is not None:
            raise ValueError(why)
        self.dm = dm
        b = model.bonds
        p = sed.params
        self.n_levels = int(p.levels)
        self.residual = float(p.residual)
        self.tensile = 1 if sed.tensile else 0
        # the host's 2-D fused pass sums k0l s^2 (s = r * (1/|xi|) - 1); otherwise
        # sed_update sums stiffness0 s^2 |xi| / 4 (s = r / |xi| - 1): the same values
        # up to round-off, each form kept in its own arithmetic
        fm = model.force_model
        self.fused_form = 1 if dm.dim == 2 and fm.fused_breaking else 0
        length = np.asarray(b.bond_length, dtype=np.float64)
        self.stiffness0 = dm.upload("sed_stiffness0", sed.stiffness0)
        self.length = dm.upload("bond_length", length)
        self.k0l = dm.upload("sed_k0l", np.asarray(sed.k0l, dtype=np.float64))
        self.w_a = dm.upload("sed_w_a", sed.w_a)
        self.w_c = dm.upload("sed_w_c", sed.w_c)
        self.stiffness = dm.upload("stiffness", np.asarray(fm.stiffness, dtype=np.float64))
        self.factor = to_device(np.asarray(sed.factor, dtype=np.float64), dm.device)
        self.energy = dm.zeros(dm.n, dm.wp.float64)
        self.raised = dm.zeros(dm.n, dm.wp.uint8)

    def update(self, ds: DeviceState) -> None:
        """After a committing force pass: the point energies at ``ds.u`` (bonds intact
        after that pass's breaking), the levels ``ds.fields["sed_level"]`` raised, and
        the stiffness of every bond with a raised end rebuilt (the same values as
        ``SoftenedStiffness.update``; nothing is copied to the host)."""
        dm = self.dm
        dm.launch(
            _sed_levels,
            dm.n,
            [
                dm.x, ds.u, dm.offsets, dm.bond_j, self.stiffness0, self.length, self.k0l,
                ds.intact, self.w_a, self.w_c, self.n_levels, self.residual, self.tensile,
                self.fused_form, ds.fields["sed_level"], self.energy, self.raised,
                self.factor,
            ],
        )  # fmt: skip
        self._rebuild(every=0)

    def restore(self, ds: DeviceState) -> None:
        """Factors and bond stiffness from the levels in ``ds.fields["sed_level"]`` (after
        a checkpoint resume, once ``ds.upload(host)`` has copied the levels)."""
        dm = self.dm
        dm.launch(
            _sed_factor_all,
            dm.n,
            [ds.fields["sed_level"], self.n_levels, self.residual, self.factor],
        )
        self._rebuild(every=1)

    def _rebuild(self, every: int) -> None:
        dm = self.dm
        dm.launch(
            _sed_stiffness,
            dm.n,
            [dm.offsets, dm.bond_j, self.stiffness0, self.factor, self.raised, every,
             self.stiffness],
        )  # fmt: skip

    def to_host(self, model: Any) -> None:
        """Copy the device stiffness, factors and energies into the host force model and
        its ``SoftenedStiffness`` (for host-side diagnostics: stress maps, sections)."""
        sed = model.sed_stiffness
        model.force_model.stiffness[...] = self.stiffness.numpy()
        sed.factor[...] = self.factor.numpy()
        sed.energy[...] = self.energy.numpy()
