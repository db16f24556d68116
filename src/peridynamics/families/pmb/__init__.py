"""Bond-based prototype microelastic brittle (PMB) family: the material constants
(:mod:`~peridynamics.families.pmb.material`), the force model
(:mod:`~peridynamics.families.pmb.force`) and its analytic tangent
(:mod:`~peridynamics.families.pmb.tangent`)."""

from peridynamics.families.pmb.force import PMBForceModel
from peridynamics.families.pmb.material import PROFILES, BondBasedMaterial, fixed_poisson_ratio
from peridynamics.families.pmb.tangent import pmb_tangent

__all__ = ["PROFILES", "BondBasedMaterial", "PMBForceModel", "fixed_poisson_ratio", "pmb_tangent"]
