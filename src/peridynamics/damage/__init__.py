"""Damage laws: a criterion (parameters, from the deck) and the law it binds to a model's
points and bonds (``criterion.law(x, bonds)``: trial and commit, see
:class:`peridynamics.families.base.DamageLaw`)."""

from peridynamics.damage.bond_softening import BondSofteningLaw, SofteningBonds
from peridynamics.damage.critical_stretch import (
    NO_DAMAGE,
    CriticalStretch,
    CriticalStretchLaw,
    family_minimum,
)
from peridynamics.damage.fatigue import RemainingLife, RemainingLifeLaw
from peridynamics.damage.plastic_strain import PlasticStrainFailure, PlasticStrainLaw
from peridynamics.damage.sed import SEDSoftening
from peridynamics.damage.weibull import WeibullField

__all__ = [
    "BondSofteningLaw",
    "SofteningBonds",
    "RemainingLife",
    "RemainingLifeLaw",
    "PlasticStrainFailure",
    "PlasticStrainLaw",
    "NO_DAMAGE",
    "CriticalStretch",
    "CriticalStretchLaw",
    "SEDSoftening",
    "WeibullField",
    "family_minimum",
]
