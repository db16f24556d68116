"""Defaults that changed: a deck that leaves such a key out gets other results than it
did before the change, so the run says so, naming the key (``note: ...`` on stderr and
``notices`` in ``summary.json``). One line per change in ``CHANGED_DEFAULTS``; the
changelog tells the whole story."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from peridynamics.deck.schema import Deck


@dataclass(frozen=True)
class ChangedDefault:
    """A default that changed: ``applies(deck)`` is true when the deck relies on it."""

    key: str
    since: str
    message: str
    applies: Callable[[Deck], bool]


def _unset_surface_correction(deck: Deck) -> bool:
    return "surface_correction" not in deck.discretisation.model_fields_set


def _automatic_step_with_damping(deck: Deck) -> bool:
    solver = deck.solver
    return getattr(solver, "time_step", None) is None and float(getattr(solver, "damping", 0.0)) > 0


def _breaks(damage: object) -> bool:
    return damage is not None and getattr(damage, "model", "none") != "none"


def _spectral_body(material: object, damage: object) -> bool:
    """A body whose family takes its bound from the Lanczos estimate: PMB and LPS, and
    correspondence without damage."""
    model = getattr(material, "model", None)
    return model in ("pmb", "bond_based", "lps") or (
        model == "correspondence" and not _breaks(damage)
    )


def _touches(deck: Deck) -> bool:
    """Contact or rigid bodies: their stiffness is not in the Lanczos estimate."""
    return getattr(deck, "contact", None) is not None or bool(getattr(deck, "rigid_bodies", None))


def _spectral_families(deck: Deck) -> bool:
    """Every body's family takes its bound from the Lanczos estimate where nothing
    touches."""
    if not _spectral_body(deck.material, getattr(deck, "damage", None)):
        return False
    for body in getattr(deck, "bodies", None) or ():
        material = body.material or deck.material
        damage = body.damage if body.damage is not None else getattr(deck, "damage", None)
        if not _spectral_body(material, damage):
            return False
    return True


def _spectral_family(deck: Deck) -> bool:
    """The deck's bound comes from the Lanczos estimate
    (:mod:`peridynamics.evaluation.spectral`)."""
    return _spectral_families(deck) and not _touches(deck)


def _lps_touching(deck: Deck) -> bool:
    """Since 0.3.0 a single-body LPS or correspondence deck with contact or rigid bodies
    keeps the per-point bound again (0.2.0 took the Lanczos estimate)."""
    model = getattr(deck.material, "model", None)
    return (
        not getattr(deck, "bodies", None)
        and model in ("lps", "correspondence")
        and _spectral_families(deck)
        and _touches(deck)
    )


def _spectral_pmb(deck: Deck) -> bool:
    """New in 0.3.0: a PMB deck, or several bodies, whose every body takes the Lanczos
    bound (before: single-body LPS and correspondence decks only)."""
    if not _spectral_family(deck):
        return False
    return bool(getattr(deck, "bodies", None)) or getattr(deck.material, "model", None) in (
        "pmb",
        "bond_based",
    )


def _spectral_before(deck: Deck) -> bool:
    """Since 0.2.0: a single-body LPS deck, or correspondence without damage."""
    return not getattr(deck, "bodies", None) and _spectral_family(deck) and not _spectral_pmb(deck)


def _automatic_explicit_step(deck: Deck) -> bool:
    solver = deck.solver
    explicit = getattr(solver, "type", "explicit") == "explicit"
    return explicit and getattr(solver, "time_step", None) is None


def _spectral_explicit_step(deck: Deck) -> bool:
    return _spectral_before(deck) and _automatic_explicit_step(deck)


def _spectral_adr_density(deck: Deck) -> bool:
    return _spectral_before(deck) and getattr(deck.solver, "type", None) == "adr"


def _pmb_explicit_step(deck: Deck) -> bool:
    return _spectral_pmb(deck) and _automatic_explicit_step(deck)


def _pmb_adr_density(deck: Deck) -> bool:
    return _spectral_pmb(deck) and getattr(deck.solver, "type", None) == "adr"


def _lps_touching_step(deck: Deck) -> bool:
    return _lps_touching(deck) and _automatic_explicit_step(deck)


def _corrected_bar(deck: Deck) -> bool:
    """A 1-D grid deck whose bond-based body has the surface correction on (the default):
    since 0.4.0 the bonds of its complete families keep the factor 1
    (:func:`peridynamics.bonds.surface.bond_factors_from_point_ratios`)."""
    disc = deck.discretisation
    model = getattr(deck.material, "model", None)
    return (
        deck.dim == 1
        and bool(disc.surface_correction)
        and float(disc.jitter) == 0.0
        and model not in ("lps", "correspondence")
    )


def _cubic_bond_based(deck: Deck) -> bool:
    """A 3-D deck with a bond-based body on a grid that leaves
    ``discretisation.isotropic_family`` out: since 0.5.0 its bonds get the isotropy
    factors (:mod:`peridynamics.families.pmb.isotropy`)."""
    disc = deck.discretisation
    if deck.dim != 3 or float(disc.jitter) != 0.0 or "isotropic_family" in disc.model_fields_set:
        return False
    if not disc.surface_correction:  # the factors are part of the correction
        return False
    if getattr(deck.geometry, "type", None) in ("mesh", "gmsh"):
        return False
    materials = [deck.material] + [b.material for b in getattr(deck, "bodies", None) or ()]
    return any(getattr(m, "model", None) in ("pmb", "bond_based") for m in materials)


CHANGED_DEFAULTS = (
    ChangedDefault(
        "discretisation.surface_correction",
        "0.1.0",
        "defaults to true (the nominal Young's modulus at surfaces too); decks written "
        "before it relied on false: set discretisation.surface_correction: false to keep "
        "their results",
        _unset_surface_correction,
    ),
    ChangedDefault(
        "solver.time_step",
        "0.2.0",
        "the automatic step now includes solver.damping in the stable limit (a smaller "
        "step than before for this damped deck); give solver.time_step to fix it",
        _automatic_step_with_damping,
    ),
    ChangedDefault(
        "solver.time_step",
        "0.2.0",
        "the automatic step of an LPS or correspondence deck now comes from a Lanczos "
        "estimate of the highest frequency (1/sqrt(1.25) = 0.89 of the critical step "
        "before safety_factor): 1.1 (LPS) to 3 (correspondence, 3-D) times longer than "
        "before; give solver.time_step to fix it",
        _spectral_explicit_step,
    ),
    ChangedDefault(
        "solver.tolerance",
        "0.2.0",
        "dynamic relaxation of an LPS or correspondence deck now takes its fictitious "
        "density from a Lanczos estimate of the largest eigenvalue (up to 1.25 over it, "
        "before 1.4-12 times): fewer iterations, and the converged fields move within "
        "solver.tolerance; tighten solver.tolerance to compare with earlier results",
        _spectral_adr_density,
    ),
    ChangedDefault(
        "solver.time_step",
        "0.3.0",
        "the automatic step of a PMB deck (or of several bodies) now comes from a "
        "Lanczos estimate of the highest frequency, as LPS's does (0.89 of the critical "
        "step before safety_factor, was 0.50-0.59): 1.5 (2-D) to 1.8 (3-D) times longer "
        "than before, 1.06 in 1-D; give solver.time_step to keep the old results",
        _pmb_explicit_step,
    ),
    ChangedDefault(
        "solver.tolerance",
        "0.3.0",
        "dynamic relaxation of a PMB deck (or of several bodies) now takes its "
        "fictitious density from a "
        "Lanczos estimate of the largest eigenvalue (2-4 times lower than the per-point "
        "bound): fewer iterations, and the converged fields move within "
        "solver.tolerance; tighten solver.tolerance to compare with earlier results",
        _pmb_adr_density,
    ),
    ChangedDefault(
        "solver.time_step",
        "0.3.0",
        "with contact or rigid bodies the automatic step is again the per-point bound "
        "(the contact stiffness is not in the Lanczos estimate of 0.2.0, so that step "
        "could be unstable in contact): shorter than in 0.2.0; give solver.time_step to "
        "fix it",
        _lps_touching_step,
    ),
    ChangedDefault(
        "discretisation.surface_correction",
        "0.4.0",
        "in 1-D the bonds of a point whose family is complete keep the factor 1 (were "
        "the mean of their ends' factors, a force on that point under a uniform strain): "
        "the bonds that reach the end points are softer than before, and with delta = dx "
        "the model is the finite-difference scheme again; set "
        "discretisation.surface_correction: false for the uncorrected model (no key "
        "restores the old factors)",
        _corrected_bar,
    ),
    ChangedDefault(
        "discretisation.isotropic_family",
        "0.5.0",
        "defaults to true: on a regular 3-D grid every bond-based bond gets a factor of "
        "its direction that makes the family isotropic (the interior has nu = 1/4 and "
        "E = E0; the cubic lattice had nu = 0.269 and E = 0.962 E0 at delta = 3.015 dx), "
        "so stiffness, wave speeds and breaking loads move by a few per cent; set "
        "discretisation.isotropic_family: false to keep the old results",
        _cubic_bond_based,
    ),
)


def notices(deck: Deck) -> list[str]:
    """One line per changed default the deck relies on (``key: ...``)."""
    return [
        f"{c.key} {c.message} (changed in {c.since}; CHANGELOG.md)"
        for c in CHANGED_DEFAULTS
        if c.applies(deck)
    ]
