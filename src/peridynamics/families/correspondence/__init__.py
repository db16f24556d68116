"""Correspondence (non-ordinary state-based) family, 2-D and 3-D: the material constants
and stress laws (:mod:`~peridynamics.families.correspondence.material`) and the force
model with zero-energy-mode control (:mod:`~peridynamics.families.correspondence.force`,
finite-difference tangent)."""

from peridynamics.families.correspondence.force import DEGENERATE_RATIO, CorrespondenceForceModel
from peridynamics.families.correspondence.material import (
    LAWS,
    STABILIZATIONS,
    ConstitutiveLaw,
    CorrespondenceMaterial,
    LinearElastic,
    StVenantKirchhoff,
)

__all__ = [
    "DEGENERATE_RATIO",
    "LAWS",
    "STABILIZATIONS",
    "ConstitutiveLaw",
    "CorrespondenceForceModel",
    "CorrespondenceMaterial",
    "LinearElastic",
    "StVenantKirchhoff",
]
