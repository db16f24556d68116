"""Which device terms run a model on the Warp backend, and the PMB family's.

:func:`device_terms` picks the device family of the model's force model (PMB here; LPS
and correspondence in their modules) and the extras (contact, mass damping, viscosity)
in the order of :meth:`peridynamics.evaluation.evaluator.Evaluator.evaluate`; :func:`unsupported`
names the
deck key of anything the backend does not run (the run is refused before it starts).
Under ``mpiexec`` every rank runs these terms on its part of the body
(:mod:`peridynamics.backends.warp_halo`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from peridynamics.backends import _warp_step_dsl as k
from peridynamics.backends.warp_damage import device_max_stretch
from peridynamics.backends.warp_device import DeviceModel, DeviceState

try:
    from peridynamics.backends._warp_dsl import _pmb_force_break
except ImportError:  # pragma: no cover - warp-lang absent
    pass


class DevicePMB:
    """The bond-based PMB force pass with critical-stretch breaking in the same pass
    (the fused explicit path of :meth:`PMBForceModel.force_and_break`: the same
    decisions and force bits on Warp's CPU device). With SED softening the stiffness is
    the softening's device array and its levels rise after the pass."""

    def __init__(self, model: Any, dm: DeviceModel) -> None:
        self.dm = dm
        fm = model.force_model
        s0 = np.asarray(model.damage_law.point_s0, dtype=np.float64)
        self.breaks = bool(np.isfinite(s0).any())
        self.s0 = dm.upload("point_s0", s0)
        self.never = dm.upload("never", np.full(dm.n, np.inf))
        self.sed: Any = None
        if model.sed_stiffness is not None:
            from peridynamics.backends.warp_extras import DeviceSED

            self.sed = DeviceSED(model, dm)
            self.stiffness = self.sed.stiffness
        else:
            self.stiffness = dm.upload("stiffness", np.asarray(fm.stiffness, dtype=np.float64))

    def attach(self, ds: DeviceState) -> None:
        """Bind to the device State (SED levels after a resume)."""
        if self.sed is not None:
            self.sed.restore(ds)
            self.stiffness = self.sed.stiffness

    def evaluate(self, ds: DeviceState, commit: bool) -> None:
        """Force density into ``ds.force``; with ``commit`` bonds at or above the
        critical stretch break first (``ds.broken`` per point)."""
        dm = self.dm
        s0 = self.s0 if commit else self.never
        dm.launch(
            _pmb_force_break,
            dm.n,
            [dm.x, ds.u, dm.offsets, dm.bond_j, self.stiffness, ds.intact, s0, ds.force, ds.broken],
        )
        if commit and self.sed is not None:
            self.sed.update(ds)

    def max_stretch(self, ds: DeviceState, out: Any) -> None:
        """Largest stretch of an intact bond per point."""
        device_max_stretch(self.dm, ds, out)


class _Adapter:
    """A device family of another module with the solver's attributes added."""

    def __init__(self, family: Any, breaks: bool) -> None:
        self._family = family
        self.breaks = breaks

    def attach(self, ds: DeviceState) -> None:
        hook = getattr(self._family, "attach", None)
        if hook is not None:
            hook(ds)

    def evaluate(self, ds: DeviceState, commit: bool) -> None:
        self._family.evaluate(ds, commit)

    def max_stretch(self, ds: DeviceState, out: Any) -> None:
        self._family.max_stretch(ds, out)


class DeviceDamping:
    """Mass-proportional damping: force -= rho c_d v."""

    def __init__(self, model: Any, dm: DeviceModel) -> None:
        self.dm = dm
        self.coefficient = dm.upload(
            "damping", np.asarray(model.damping * model.density, dtype=np.float64)
        )

    def add(self, ds: DeviceState) -> None:
        self.dm.launch(k.mass_damping, self.dm.n, [self.coefficient, ds.v, ds.force])


def unsupported(model: Any, integrator: str = "velocity_verlet") -> tuple[str, str] | None:
    """(deck key, reason) of the first part of ``model`` the Warp backend does not run,
    or None when it runs all of it."""
    from peridynamics.bodies.composite import CompositeForceModel
    from peridynamics.damage.critical_stretch import CriticalStretchLaw
    from peridynamics.families.correspondence.force import CorrespondenceForceModel
    from peridynamics.families.lps.force import LPSForceModel
    from peridynamics.families.pmb.force import PMBForceModel

    fm = model.force_model
    if isinstance(fm, CompositeForceModel):
        return "bodies", "several bodies are not on the Warp backend"
    if model.rigid is not None:
        return "rigid_bodies", "rigid bodies are not on the Warp backend"
    if len(fm.dofs()) > 1:
        return "material.model", f"the {fm.name!r} model (rotations) is not on the Warp backend"
    if type(fm) is PMBForceModel:
        if fm.precision != "float64":
            return "solver.precision", "the Warp backend is float64"
        if type(model.damage_law) is not CriticalStretchLaw:
            return (
                "damage.model",
                f"the {model.damage_law.name!r} law with PMB is not on the Warp backend "
                "(critical stretch is)",
            )
        if model.sed_stiffness is not None:
            from peridynamics.backends import warp_extras

            why = warp_extras.supports(model)
            if why:
                return "damage.sed_softening", why
    elif isinstance(fm, LPSForceModel):
        from peridynamics.backends import warp_lps

        why = warp_lps.supports(model)
        if why:
            return "material", why
    elif isinstance(fm, CorrespondenceForceModel):
        from peridynamics.backends import warp_correspondence

        why = warp_correspondence.supports(model)
        if why:
            return "damage", why
    else:
        return (
            "material.model",
            f"the {getattr(fm, 'name', type(fm).__name__)!r} force model is not on the Warp "
            "backend (pmb, lps and correspondence are)",
        )
    if model.contact is not None:
        from peridynamics.backends import warp_short_range_contact

        why = warp_short_range_contact.supports(model)
        if why:
            return "contact", why
    if model.viscous_coefficients is not None:
        from peridynamics.backends import warp_extras

        why = warp_extras.supports(model)
        if why:
            return "material.viscosity", why
    return None


def device_terms(model: Any, dm: DeviceModel) -> tuple[Any, list[Any]]:
    """(device family, extras in the order of the host's evaluation) of ``model``;
    ValueError naming the deck key when a part is not on the Warp backend."""
    from peridynamics.families.correspondence.force import CorrespondenceForceModel
    from peridynamics.families.lps.force import LPSForceModel

    got = unsupported(model)
    if got is not None:
        key, why = got
        raise ValueError(f"{key}: {why}; use solver.backend: numba")
    fm = model.force_model
    family: Any
    if isinstance(fm, LPSForceModel):
        from peridynamics.backends.warp_lps import DeviceLPS

        family = _Adapter(DeviceLPS(model, dm), bool(np.isfinite(model.point_s0).any()))
    elif isinstance(fm, CorrespondenceForceModel):
        from peridynamics.backends.warp_correspondence import DeviceCorrespondence

        family = _Adapter(DeviceCorrespondence(model, dm), model.damage_law.active)
    else:
        family = DevicePMB(model, dm)
    extras: list[Any] = []
    if model.contact is not None:
        from peridynamics.backends.warp_short_range_contact import DeviceContact

        extras.append(DeviceContact(model, dm))
    if model.damping > 0:
        extras.append(DeviceDamping(model, dm))
    if model.viscous_coefficients is not None:
        from peridynamics.backends.warp_extras import DeviceViscosity

        extras.append(DeviceViscosity(model, dm))
    return family, extras
