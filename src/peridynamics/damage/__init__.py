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
from peridynamics.damage.sed import SEDSoftening
from peridynamics.damage.weibull import WeibullField

#: the registry of damage laws: ``damage.model`` -> criterion class (``none`` is the
#: critical-stretch law with an infinite threshold, which never proposes a bond)
DAMAGE_LAWS = {"critical_stretch": CriticalStretch, "none": CriticalStretch}

__all__ = [
    "DAMAGE_LAWS",
    "BondSofteningLaw",
    "SofteningBonds",
    "NO_DAMAGE",
    "CriticalStretch",
    "CriticalStretchLaw",
    "SEDSoftening",
    "WeibullField",
    "family_minimum",
]
