"""Material, damage, contact and the evaluator of a single-body deck.

:func:`build_material` builds the deck's material through :data:`MATERIAL_BUILDERS`
(keyed by ``material.model``, each calling its family's class in
:data:`peridynamics.families.registry.MATERIALS`); :func:`build_damage` the damage law;
:func:`build_model` the evaluator with loads, viscosity, softening and contact.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from peridynamics import deck as dk
from peridynamics.bonds.bonds import Bonds
from peridynamics.build.errors import SetupError
from peridynamics.build.fatigue import build_fatigue_law
from peridynamics.build.plastic_damage import build_plastic_strain_law
from peridynamics.damage import NO_DAMAGE, CriticalStretch, SEDSoftening, WeibullField
from peridynamics.evaluation import Evaluator
from peridynamics.families.correspondence.plasticity import plastic_law
from peridynamics.families.lps.plastic import LPSPlasticity
from peridynamics.families.lps.viscoelastic import Viscoelasticity
from peridynamics.families.registry import MATERIALS
from peridynamics.families.viscosity import BondViscosity
from peridynamics.geometry import PointCloud


def _bond_based(m: Any, disc: dk.Discretisation | None) -> Any:
    iso = True if disc is None else bool(disc.isotropic_family)
    return MATERIALS[m.model](
        m.youngs_modulus, m.density, m.micromodulus_profile, m.micromodulus, iso
    )


def _lps(m: Any, disc: dk.Discretisation | None) -> Any:
    ve = getattr(m, "viscoelastic", None)
    pl = getattr(m, "plasticity", None)
    return MATERIALS["lps"](
        m.youngs_modulus, m.poisson_ratio, m.density, m.influence,
        None if ve is None else Viscoelasticity(ve.fraction, ve.relaxation_time),
        None if pl is None else LPSPlasticity(pl.yield_stress, pl.hardening_modulus),
    )  # fmt: skip


def _correspondence(m: Any, disc: dk.Discretisation | None) -> Any:
    return MATERIALS["correspondence"](
        m.youngs_modulus,
        m.poisson_ratio,
        m.density,
        m.stabilization,
        0.1 if m.stabilization_g is None else m.stabilization_g,
        m.law,
        plastic_law(m.plasticity),
    )


def _micropolar(m: Any, disc: dk.Discretisation | None) -> Any:
    return MATERIALS["micropolar"](
        m.youngs_modulus,
        m.poisson_ratio,
        m.density,
        m.rotational_stiffness_ratio,
        m.corrected_critical_stretch,
    )


#: ``material.model`` -> builder(section, the deck's discretisation or None) -> material
MATERIAL_BUILDERS: dict[str, Callable[[Any, Any], Any]] = {
    "pmb": _bond_based,
    "bond_based": _bond_based,
    "lps": _lps,
    "correspondence": _correspondence,
    "micropolar": _micropolar,
}


def build_material(m: Any, disc: dk.Discretisation | None = None) -> Any:
    """The deck's material section -> a material of its model family (registry
    :data:`MATERIAL_BUILDERS`, keyed by ``material.model``); ``disc``, the deck's
    discretisation section, gives the keys of the family that live there
    (``isotropic_family``; ``None``: their defaults)."""
    try:
        return MATERIAL_BUILDERS[m.model](m, disc)
    except ValueError as exc:
        raise SetupError("material", str(exc)) from None


def calibrate_fracture_energy(
    material: Any, disc: dk.Discretisation | None, cloud: PointCloud, bonds: Bonds, key: str
) -> Any:
    """``material`` with its critical stretch calibrated on the grid's family when
    ``discretisation.lattice_fracture_energy`` (bond-based materials:
    ``with_lattice_fracture_energy``), else ``material`` itself; ``key`` names the
    material section in the error of a family without the calibration."""
    if disc is None or not disc.lattice_fracture_energy:
        return material
    calibrated = getattr(material, "with_lattice_fracture_energy", None)
    if calibrated is None:
        raise SetupError(
            "discretisation.lattice_fracture_energy",
            f"the calibration is built for bond-based materials (model pmb / bond_based), "
            f"not {key} ({type(material).__name__}); remove the key",
        )
    try:
        return calibrated(cloud, bonds, disc.surface_correction)
    except ValueError as exc:
        raise SetupError("discretisation.lattice_fracture_energy", str(exc)) from None


#: a damage builder: (damage section, material spec, material, cloud, bonds, no-fail
#: points or None) -> the damage object the evaluator binds
DamageBuilder = Callable[[dk.Damage, Any, Any, PointCloud, Bonds, Any], Any]


def _softening_bonds(
    dmg: dk.Damage, m: Any, material: Any, cloud: PointCloud, bonds: Bonds, no_fail: Any
) -> Any:
    """Tension-softening bonds (``damage.bond_law`` bilinear / trilinear; validated: f_t
    and G0 given); SetupError when the envelope has no tail at this horizon."""
    from peridynamics.damage.bond_softening import SofteningBonds
    from peridynamics.families.pmb_softening.envelope import softening_envelope

    assert dmg.bond_law != "brittle"  # DAMAGE_LAWS routes only softening laws here
    assert dmg.tensile_strength is not None and dmg.fracture_energy is not None
    knee = dmg.trilinear_knee
    soft = SofteningBonds(
        dmg.bond_law,
        dmg.tensile_strength,
        dmg.fracture_energy,
        None if knee is None else (float(knee[0]), float(knee[1])),
        no_fail,
    )
    try:  # the envelope needs s_c > s0 at this horizon: say so before the run
        softening_envelope(
            soft, material, cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane
        )
    except ValueError as exc:
        raise SetupError("damage.tensile_strength", str(exc)) from None
    return soft


def _critical_stretch(
    dmg: dk.Damage, m: Any, material: Any, cloud: PointCloud, bonds: Bonds, no_fail: Any
) -> Any:
    """Critical stretch (given, or from G0), with its Weibull field; for a correspondence
    material wrapped in the maximum-principal-stress criterion (``principal_stress``
    alone: an infinite s0)."""
    s0 = dmg.critical_stretch
    if dmg.model == "principal_stress":
        s0 = math.inf
    elif s0 is None:
        assert dmg.fracture_energy is not None
        s0 = material.critical_stretch(
            dmg.fracture_energy, cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane
        )
    w = dmg.weibull
    weibull = None if w is None else WeibullField(w.shape, w.seed, w.variable, w.u0_is)
    damage: Any = CriticalStretch(s0, no_fail, weibull)
    if m.model == "correspondence":
        from peridynamics.damage.principal_stress import CorrespondenceFailure

        f_t = dmg.tensile_strength
        damage = CorrespondenceFailure(damage, math.inf if f_t is None else f_t)
    return damage


#: the registry of damage laws: ``damage.model`` (or, when it is not ``brittle``,
#: ``damage.bond_law``) -> builder; ``none`` never builds a law
DAMAGE_LAWS: dict[str, DamageBuilder] = {
    "critical_stretch": _critical_stretch,
    "principal_stress": _critical_stretch,
    "bilinear": _softening_bonds,
    "trilinear": _softening_bonds,
    "fatigue": build_fatigue_law,
    "plastic_strain": build_plastic_strain_law,
}


def build_damage(dmg: dk.Damage, m: Any, material: Any, cloud: PointCloud, bonds: Bonds) -> Any:
    """The damage object given to :class:`Evaluator` for the deck's ``damage`` section.

    Parameters
    ----------
    dmg : Damage
        The validated ``damage`` section.
    m : material spec of the deck (selects the correspondence failure law).
    material : the material object built from ``m`` (calibrates s0 from G0).
    cloud : PointCloud
        Points of the body (node sets of ``no_fail``, dimension, cross-section).
    bonds : Bonds
        Its bonds (the horizon).

    Returns
    -------
    ``NO_DAMAGE``, :class:`CriticalStretch`, ``CorrespondenceFailure`` or
    :class:`~peridynamics.damage.bond_softening.SofteningBonds` (from
    :data:`DAMAGE_LAWS`). Raises SetupError when a softening law has no tail at this
    horizon.
    """
    if dmg.model == "none":
        return NO_DAMAGE
    no_fail = (
        np.unique(np.concatenate([cloud.node_set(n) for n in dmg.no_fail])) if dmg.no_fail else None
    )
    key = dmg.model if dmg.bond_law == "brittle" else dmg.bond_law
    return DAMAGE_LAWS[key](dmg, m, material, cloud, bonds, no_fail)


def build_model(deck: dk.Deck, cloud: PointCloud, bonds: Bonds, body: list) -> Evaluator:
    """Material + damage + loads -> Evaluator."""
    material = build_material(deck.material, deck.discretisation)
    material = calibrate_fracture_energy(material, deck.discretisation, cloud, bonds, "material")
    m = deck.material
    dmg = deck.damage
    damage = build_damage(dmg, m, material, cloud, bonds)
    sed = dmg.sed_softening
    softening = (
        None
        if sed is None
        else SEDSoftening(sed.levels, sed.k_c, sed.residual, sed.threshold_stretch, sed.energy)
    )
    contact = build_contact(deck, cloud, bonds, material)
    visc = getattr(m, "viscosity", None)
    return Evaluator(
        cloud,
        bonds,
        material,
        damage,
        body,
        surface_correction=deck.discretisation.surface_correction,
        viscosity=None if visc is None else BondViscosity(visc.linear, visc.quadratic),
        softening=softening,
        contact=contact,
        damping=getattr(deck.solver, "damping", 0.0),
    )


def build_contact(deck: dk.Deck, cloud: PointCloud, bonds: Bonds, material: Any) -> Any:
    """Short-range contact between points not joined by an intact bond (``None`` without a
    ``contact`` section); its stiffness from the PMB micromodulus of ``material``'s E."""
    if deck.contact is None:
        return None
    from peridynamics.evaluation.short_range_contact import ShortRangeContact

    c0 = material.micromodulus_constant(cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane)
    d_c = deck.contact.distance_factor * cloud.spacing
    return ShortRangeContact(
        cloud.x,
        cloud.volume,
        bonds,
        contact_distance=d_c,
        stiffness=ShortRangeContact.parks_stiffness(
            c0, d_c, bonds.horizon, deck.contact.stiffness_factor
        ),
        friction_static=deck.contact.friction_static,
        friction_kinetic=deck.contact.friction_kinetic,
        global_ids=cloud.global_ids,
    )
