"""Tension-softening PMB family (bilinear / trilinear bonds, Petersson 1981): the
envelope (:mod:`~peridynamics.families.pmb_softening.envelope`) and the force model with
its per-bond history (:mod:`~peridynamics.families.pmb_softening.force`). Selected by
the damage section (``damage.bond_law``); the law that commits the history is
:class:`peridynamics.damage.bond_softening.BondSofteningLaw`."""

from peridynamics.families.pmb_softening.envelope import SofteningEnvelope, softening_envelope
from peridynamics.families.pmb_softening.force import (
    KAPPA,
    PMBSofteningForceModel,
    softening_force_model,
)

__all__ = [
    "KAPPA",
    "PMBSofteningForceModel",
    "SofteningEnvelope",
    "softening_envelope",
    "softening_force_model",
]
