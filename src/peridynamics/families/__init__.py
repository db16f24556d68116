"""Model families: one package per family (its constants, force model and tangent),
the force-model and damage-law interface (:mod:`peridynamics.families.base`), the
finite-difference tangent, sparse assembly, the isotropic-moduli helper, viscous bond
forces and the registry of families (:mod:`peridynamics.families.registry`)."""

from peridynamics.families.base import DamageLaw, Dof, FieldSpec, ForceModel, FusedStep

__all__ = ["DamageLaw", "Dof", "FieldSpec", "ForceModel", "FusedStep"]
