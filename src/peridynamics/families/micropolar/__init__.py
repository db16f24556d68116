"""Micropolar bond-based family (2-D; displacements and rotations): the material
constants (:mod:`~peridynamics.families.micropolar.material`), the spring constants
(:mod:`~peridynamics.families.micropolar.springs`) and the force model with its tangent
(:mod:`~peridynamics.families.micropolar.force`)."""

from peridynamics.families.micropolar.force import ROTATION, MicropolarForceModel
from peridynamics.families.micropolar.material import BEAM_ROTATIONAL_RATIO, MicropolarMaterial
from peridynamics.families.micropolar.springs import SpringConstants

__all__ = [
    "BEAM_ROTATIONAL_RATIO",
    "ROTATION",
    "MicropolarForceModel",
    "MicropolarMaterial",
    "SpringConstants",
]
