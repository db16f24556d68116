"""Damage laws: critical stretch (with no-fail zones); more laws in later issues."""

from peridynamics.damage.critical_stretch import NO_DAMAGE, CriticalStretch, family_minimum
from peridynamics.damage.sed import SEDSoftening
from peridynamics.damage.weibull import WeibullField

__all__ = ["NO_DAMAGE", "CriticalStretch", "SEDSoftening", "WeibullField", "family_minimum"]
