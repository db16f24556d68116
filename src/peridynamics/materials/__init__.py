"""Constitutive laws. Each is a small class around pure kernel functions."""

from peridynamics.materials.bond_based import PROFILES, BondBasedMaterial, fixed_poisson_ratio

MATERIALS = {"pmb": BondBasedMaterial, "bond_based": BondBasedMaterial}

__all__ = ["MATERIALS", "PROFILES", "BondBasedMaterial", "fixed_poisson_ratio"]
