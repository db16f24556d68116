"""The registry of model families: one entry per family, with what it declares.

Adding a family is adding its package (constants, force model, tangent) and one line in
:data:`FAMILIES`. An entry names the family as the deck does (``material.model``; the
variants chosen by the damage section, ``damage.bond_law`` and ``damage.sed_softening``,
under their own names), its material class, its force-model class and the capabilities
it declares; the evaluator, the solvers and the backends may ask these instead of
testing classes.

:data:`MATERIALS` (``material.model`` -> material class) is the view of the registry that
the build layer reads, and :func:`build_force_model` the one place a force model is made
from a material and a damage criterion.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import ForceModel
from peridynamics.families.correspondence import CorrespondenceForceModel, CorrespondenceMaterial
from peridynamics.families.correspondence.thermal import CorrespondenceThermalForceModel
from peridynamics.families.lps import LPSForceModel, LPSMaterial
from peridynamics.families.lps.thermal import LPSThermalForceModel
from peridynamics.families.micropolar import MicropolarForceModel, MicropolarMaterial
from peridynamics.families.pmb import BondBasedMaterial, PMBForceModel
from peridynamics.families.pmb.thermal import PMBThermalForceModel
from peridynamics.families.pmb_softening import PMBSofteningForceModel, softening_force_model
from peridynamics.geometry.cloud import PointCloud


@dataclass(frozen=True)
class Family:
    """One model family and the capabilities it declares.

    Attributes
    ----------
    name : str
        The deck's ``material.model`` (or the registry name of a variant chosen by the
        damage section).
    material : type
        The class of its constants (``force_model(cloud, bonds, surface_correction)``).
    force_model : type
        Its :class:`~peridynamics.families.base.ForceModel`.
    selected_by : str
        The deck key that chooses it.
    analytic_tangent : bool
        ``tangent`` is analytic (else the finite-difference tangent).
    fused_step : bool
        Declares a fused explicit step (``ForceModel.fused_step``): the damage law's
        trial and commit inside the force pass.
    mpi : bool
        Runs decomposed over MPI ranks.
    ghost_families : bool
        Under MPI, the first ghost layer needs its bond families (a pre-pass quantity or
        history read at the far end of a bond).
    warp : bool
        Runs on the Warp backend (with its own conditions, asked there).
    rotations : bool
        Has a rotational dof group (micropolar).
    builder : callable, optional
        ``(criterion, material, cloud, bonds, surface_correction) -> ForceModel`` for a
        family chosen by the damage section (it needs the law's parameters).
    thermal : callable, optional
        ``(force_model) -> ForceModel``: its thermal-expansion variant, which reads the
        State's ``thermal_strain`` (:mod:`peridynamics.families.thermal`); None: the
        family has no thermal expansion (``thermal.expansion`` is refused).
    """

    name: str
    material: type
    force_model: type[ForceModel]
    selected_by: str = "material.model"
    analytic_tangent: bool = False
    fused_step: bool = False
    mpi: bool = True
    ghost_families: bool = True
    warp: bool = False
    rotations: bool = False
    builder: Callable[..., ForceModel] | None = None
    thermal: Callable[[Any], ForceModel] | None = None


_PMB = Family(
    "pmb", BondBasedMaterial, PMBForceModel, analytic_tangent=True, fused_step=True,
    ghost_families=False, warp=True, thermal=PMBThermalForceModel.of,
)  # fmt: skip

#: every family, by name
FAMILIES: dict[str, Family] = {
    "pmb": _PMB,
    "bond_based": _PMB,
    "pmb_softening": Family(
        "pmb_softening",
        BondBasedMaterial,
        PMBSofteningForceModel,
        "damage.bond_law",
        fused_step=True,
        builder=softening_force_model,
    ),  # fmt: skip
    "pmb_sed": Family(
        "pmb_sed",
        BondBasedMaterial,
        PMBForceModel,
        "damage.sed_softening",
        analytic_tangent=True,
        fused_step=True,
        warp=True,
    ),  # fmt: skip
    "lps": Family(
        "lps",
        LPSMaterial,
        LPSForceModel,
        analytic_tangent=True,
        warp=True,
        thermal=LPSThermalForceModel.of,
    ),
    "micropolar": Family(
        "micropolar",
        MicropolarMaterial,
        MicropolarForceModel,
        analytic_tangent=True,
        mpi=False,
        rotations=True,
    ),  # fmt: skip
    "correspondence": Family(
        "correspondence",
        CorrespondenceMaterial,
        CorrespondenceForceModel,
        warp=True,
        thermal=CorrespondenceThermalForceModel.of,
    ),
}

#: ``material.model`` -> material class (the families chosen by ``material.model``)
MATERIALS: dict[str, Any] = {
    name: f.material for name, f in FAMILIES.items() if f.selected_by == "material.model"
}


def build_force_model(
    material: Any,
    damage: Any,
    cloud: PointCloud,
    bonds: Bonds,
    surface_correction: bool = False,
) -> ForceModel:
    """The force model of ``material`` on ``cloud`` and ``bonds``; a damage criterion
    that names a family (``force_family``, as the tension-softening bond laws) has that
    family's builder make it instead."""
    family = getattr(damage, "force_family", None)
    if family is not None:
        builder = FAMILIES[family].builder
        assert builder is not None, f"the family {family!r} has no builder"
        return builder(damage, material, cloud, bonds, surface_correction)
    fm: ForceModel = material.force_model(cloud, bonds, surface_correction)
    return fm
