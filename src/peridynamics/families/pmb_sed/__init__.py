"""Strain-energy-density softening of the PMB bond stiffness (SED-PD (2021), eqs
18-24): :class:`~peridynamics.families.pmb_sed.stiffness.SoftenedStiffness`, composed
around a force model that declares ``sed_softening``. Selected by
``damage.sed_softening`` (parameters: :class:`peridynamics.damage.sed.SEDSoftening`)."""

from peridynamics.families.pmb_sed.stiffness import SoftenedStiffness

__all__ = ["SoftenedStiffness"]
