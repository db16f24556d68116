"""Deck section ``material``: one schema per model family (PMB, LPS, micropolar,
correspondence), the registry of families (:data:`MATERIAL_SCHEMAS`), and each
family's compatibility checks against the rest of the deck (its ``deck_errors``).

A family's schema (a :class:`FamilySpec`) declares the capabilities that other
sections' checks ask: ``tension_softening`` (bond-based bonds a softening bond law can
replace), ``stress_tensor`` (a stress for the principal-stress criterion) and
``point_rotations`` (rotational degrees of freedom a ``fixed`` condition can clamp).
"""

from __future__ import annotations

from typing import Annotated, Any, ClassVar, Literal

from pydantic import Discriminator, Field, Tag, model_validator

from peridynamics.deck.damage import bond_law_errors, sed_softening_errors
from peridynamics.deck.lps_plasticity import lps_plasticity_errors
from peridynamics.deck.plasticity import AnyPlasticity, plasticity_errors
from peridynamics.deck.types import Errors, NonNegFloat, NotBool, Num, PosFloat, Strict, tag_of
from peridynamics.deck.viscoelastic import ViscoelasticSpec, viscoelastic_errors

#: Young's modulus and density: finite and > 0, of any magnitude (not bounded by
#: ``MAX_MAGNITUDE``): :func:`~peridynamics.deck.derived.derived_errors` names an absurd
#: one by the wave speed sqrt(E / rho) it gives
Property = Annotated[float, Field(gt=0, allow_inf_nan=False), NotBool]


class Viscosity(Strict):
    """Viscous bond forces of PD wave dispersion (n.d.) (eqs 53-56): b1 (linear), b2 (quadratic)."""

    linear: NonNegFloat = 0.0
    quadratic: NonNegFloat = 0.0


class FamilySpec(Strict):
    """Base of a model family's ``material`` section: the capabilities the other
    sections' checks ask (none by default) and the family's own checks."""

    tension_softening: ClassVar[bool] = False
    stress_tensor: ClassVar[bool] = False
    point_rotations: ClassVar[bool] = False

    def deck_errors(self, deck: Any) -> Errors:
        """Checks of this family against the rest of ``deck``: the damage law's."""
        return bond_law_errors(deck)


class Material(FamilySpec):
    """Bond-based PMB material (``model: pmb``, the default)."""

    model: Literal["pmb", "bond_based"] = "pmb"
    youngs_modulus: Property
    density: Property
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5, allow_inf_nan=False), Num] | None = None
    micromodulus_profile: Literal["constant", "conical"] = "constant"
    micromodulus: PosFloat | None = None  # N/m^6: overrides the energy-equivalent c
    viscosity: Viscosity | None = None

    tension_softening: ClassVar[bool] = True

    def deck_errors(self, deck: Any) -> Errors:
        """The Poisson ratio bond-based PD fixes, the damage law, and an explicit
        micromodulus that a fracture energy cannot calibrate."""
        from peridynamics.families.pmb.material import fixed_poisson_ratio

        errors: Errors = []
        dim = deck.dim
        plane = getattr(deck.geometry, "plane", None)
        nu_fixed = fixed_poisson_ratio(dim, plane if dim == 2 else None)
        nu = self.poisson_ratio
        if nu is not None and nu_fixed is not None and abs(nu - nu_fixed) > 1e-6:
            what = f"{dim}-D" + (f" plane {plane}" if dim == 2 else "")
            errors.append(
                (
                    "material.poisson_ratio",
                    f"bond-based PMB fixes nu = {nu_fixed:.6g} in {what}; got {nu} "
                    "(omit poisson_ratio or set it to that value)",
                )
            )
        errors += bond_law_errors(deck)
        if self.micromodulus is not None and deck.damage.fracture_energy is not None:
            errors.append(
                (
                    "damage.fracture_energy",
                    "with an explicit material.micromodulus the fracture energy does not "
                    "fix s0; give damage.critical_stretch instead",
                )
            )
        return errors


class LPSMaterialSpec(FamilySpec):
    """Ordinary state-based linear peridynamic solid (``model: lps``; Silling et al.
    2007, 2-D forms of Le et al. 2014): any Poisson ratio in the admissible range."""

    model: Literal["lps"]
    youngs_modulus: Property
    density: Property
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5, allow_inf_nan=False), Num] = 0.25
    influence: Literal["constant", "inverse"] = "constant"
    viscosity: Viscosity | None = None
    viscoelastic: ViscoelasticSpec | None = None  # deck/viscoelastic.py
    plasticity: AnyPlasticity | None = None  # j2 only (deck/lps_plasticity.py)

    def deck_errors(self, deck: Any) -> Errors:
        """The damage law, a 2-D or 3-D model, no SED softening; ``viscoelastic``'s
        and ``plasticity``'s limits."""
        errors = bond_law_errors(deck)
        if deck.dim == 1:
            errors.append(("material.model", "lps is a 2-D / 3-D model; use pmb for bars"))
        elif self.plasticity is not None:
            errors += lps_plasticity_errors(deck)
        elif self.viscoelastic is not None:
            errors += viscoelastic_errors(deck)
        return errors + sed_softening_errors(deck)


class MicropolarMaterialSpec(FamilySpec):
    """Micropolar bond-based material (``model: micropolar``; 2-D): axial, shear and
    rotational bond springs, every point with (u, v, theta); Zhou, Zhu & Li (n.d.),
    Diana & Casolo 2019. ``poisson_ratio`` up to 1/3 (plane stress) or 1/4 (plane
    strain); ``rotational_stiffness_ratio`` = k_phi / k_t (1/12: beam lattice)."""

    model: Literal["micropolar"]
    youngs_modulus: Property
    density: Property
    poisson_ratio: Annotated[float, Field(gt=-1.0, le=1.0 / 3.0, allow_inf_nan=False), Num] = 0.25
    rotational_stiffness_ratio: NonNegFloat = 1.0 / 12.0
    corrected_critical_stretch: bool = False

    point_rotations: ClassVar[bool] = True

    def deck_errors(self, deck: Any) -> Errors:
        """A 2-D model, the plane-strain limit of the Poisson ratio, no SED softening,
        the damage law."""
        errors: Errors = []
        plane = getattr(deck.geometry, "plane", None)
        if deck.dim != 2:
            errors.append(("material.model", "micropolar is a 2-D model (plane stress or strain)"))
        elif plane == "strain" and self.poisson_ratio > 0.25:
            errors.append(
                (
                    "material.poisson_ratio",
                    f"{self.poisson_ratio} is above the micropolar plane-strain limit 1/4 (the "
                    "shear spring would be negative); use <= 0.25, plane stress or model lps",
                )
            )
        if self.corrected_critical_stretch and getattr(deck.solver, "type", None) != "static":
            errors.append(
                (
                    "material.corrected_critical_stretch",
                    "scales the critical stretch in the static solver's bond breaking "
                    "only; use solver.type static or remove the key",
                )
            )
        return errors + sed_softening_errors(deck) + bond_law_errors(deck)


class CorrespondenceMaterialSpec(FamilySpec):
    """Correspondence (non-ordinary state-based) material (``model: correspondence``;
    2-D and 3-D): deformation gradient, a classical stress law and zero-energy-mode
    control (PD zero-energy modes (n.d.); Silling 2017). ``stabilization``: ``lbscmm``
    (default, parameter-free), ``silling2017`` (penalty ``stabilization_g``,
    dimensionless: Silling's G over the horizon volume, default 0.1) or ``none``."""

    model: Literal["correspondence"]
    youngs_modulus: Property
    density: Property
    poisson_ratio: Annotated[float, Field(gt=-1.0, lt=0.5, allow_inf_nan=False), Num] = 0.25
    stabilization: Literal["lbscmm", "silling2017", "none"] = "lbscmm"
    stabilization_g: PosFloat | None = None
    law: Literal["st_venant_kirchhoff", "linear_elastic"] = "st_venant_kirchhoff"
    plasticity: AnyPlasticity | None = None  # history-dependent law (deck/plasticity.py)

    stress_tensor: ClassVar[bool] = True

    @model_validator(mode="after")
    def _g_only_for_silling(self) -> CorrespondenceMaterialSpec:
        if self.stabilization_g is not None and self.stabilization != "silling2017":
            raise ValueError(
                "[stabilization_g] is the penalty of stabilization 'silling2017'; remove it "
                f"or set stabilization: silling2017 (got {self.stabilization!r})"
            )
        return self

    def deck_errors(self, deck: Any) -> Errors:
        """The damage law, a 2-D or 3-D model, no SED softening."""
        errors = bond_law_errors(deck)
        if deck.dim == 1:
            errors.append(("material.model", "correspondence is a 2-D / 3-D model"))
        elif self.plasticity is not None:
            errors += plasticity_errors(deck, "law" in self.model_fields_set)
        return errors + sed_softening_errors(deck)


#: the registry of model families: deck name -> schema of its material section
MATERIAL_SCHEMAS: dict[str, type[FamilySpec]] = {
    "pmb": Material,
    "bond_based": Material,
    "lps": LPSMaterialSpec,
    "micropolar": MicropolarMaterialSpec,
    "correspondence": CorrespondenceMaterialSpec,
}


AnyMaterial = Annotated[
    Annotated[Material, Tag("pmb")]
    | Annotated[Material, Tag("bond_based")]
    | Annotated[LPSMaterialSpec, Tag("lps")]
    | Annotated[MicropolarMaterialSpec, Tag("micropolar")]
    | Annotated[CorrespondenceMaterialSpec, Tag("correspondence")],
    Discriminator(tag_of("pmb", "model")),
]
