"""Linear peridynamic solid (ordinary state-based, 2-D and 3-D): the material constants
(:mod:`~peridynamics.families.lps.material`), the force model
(:mod:`~peridynamics.families.lps.force`) and its analytic tangent
(:mod:`~peridynamics.families.lps.tangent`); the influence calibration of its surface
correction is :mod:`peridynamics.families.calibration`."""

from peridynamics.families.lps.force import LPSForceModel
from peridynamics.families.lps.material import INFLUENCES, LPSCoefficients, LPSMaterial
from peridynamics.families.lps.tangent import lps_tangent

__all__ = ["INFLUENCES", "LPSCoefficients", "LPSForceModel", "LPSMaterial", "lps_tangent"]
