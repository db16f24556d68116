"""Damage laws: critical stretch (with no-fail zones); more laws in later issues."""

from peridynamics.damage.critical_stretch import NO_DAMAGE, CriticalStretch, family_minimum

__all__ = ["NO_DAMAGE", "CriticalStretch", "family_minimum"]
