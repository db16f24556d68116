"""Correspondence (non-ordinary state-based) family, 2-D and 3-D: the material constants
and stress laws (:mod:`~peridynamics.families.correspondence.material`) and the force
model with zero-energy-mode control (:mod:`~peridynamics.families.correspondence.force`,
finite-difference tangent), and the elastic-plastic laws and their force model
(:mod:`~peridynamics.families.correspondence.plasticity`,
:mod:`~peridynamics.families.correspondence.plastic_force`)."""

from peridynamics.families.correspondence.force import DEGENERATE_RATIO, CorrespondenceForceModel
from peridynamics.families.correspondence.material import (
    LAWS,
    STABILIZATIONS,
    ConstitutiveLaw,
    CorrespondenceMaterial,
    LinearElastic,
    StVenantKirchhoff,
)
from peridynamics.families.correspondence.plastic_force import PlasticCorrespondenceModel
from peridynamics.families.correspondence.plasticity import (
    PLASTIC_LAWS,
    DruckerPrager,
    J2Plasticity,
    PlasticLaw,
)

__all__ = [
    "DEGENERATE_RATIO",
    "LAWS",
    "PLASTIC_LAWS",
    "STABILIZATIONS",
    "ConstitutiveLaw",
    "CorrespondenceForceModel",
    "CorrespondenceMaterial",
    "DruckerPrager",
    "J2Plasticity",
    "LinearElastic",
    "PlasticCorrespondenceModel",
    "PlasticLaw",
    "StVenantKirchhoff",
]
