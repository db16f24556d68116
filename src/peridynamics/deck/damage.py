"""Deck section ``damage``: bond breaking (critical stretch, principal stress, none),
Weibull heterogeneity, SED softening and tension-softening bond laws, with the checks
of a law against the model family, the solver and the node sets."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from peridynamics.deck.fatigue import FatigueSpec, fatigue_damage_errors
from peridynamics.deck.types import Errors, Finite, Num, PosFloat, Strict


class WeibullSpec(Strict):
    """Weibull heterogeneity of the critical stretch (SED-PD (2021), eqs 25-26)."""

    shape: PosFloat
    seed: Annotated[int, Field(ge=0), Num] = 0
    variable: Literal["fracture_energy", "critical_stretch"] = "fracture_energy"
    u0_is: Literal["scale", "mean"] = "scale"


class SEDSofteningSpec(Strict):
    """Strain-energy-density softening (SED-PD (2021), eqs 18-24)."""

    levels: Annotated[int, Field(ge=1, le=1000), Num] = 10
    k_c: Annotated[float, Field(gt=1, allow_inf_nan=False), Num] = 4.0
    residual: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False), Num] = 0.05
    threshold_stretch: PosFloat | None = None
    energy: Literal["total", "tensile"] = "total"


class Damage(Strict):
    """Bond breaking: ``critical_stretch`` (s0 or fracture_energy; with
    ``tensile_strength`` too, a bond breaks at whichever comes first),
    ``principal_stress`` (``tensile_strength`` only: the mean of the two points' largest
    principal stresses, correspondence models), ``fatigue`` (the remaining-life law of
    ``fatigue``, with ``solver.type: fatigue``), ``plastic_strain`` (a point's bonds break
    when its equivalent plastic strain reaches ``critical_plastic_strain``; with
    ``material.plasticity``; critical_stretch, fracture_energy and tensile_strength may
    be added) or ``none``. ``bond_law`` ``bilinear`` /
    ``trilinear`` (PMB only) replaces the brittle bond by a tension-softening one: peak
    at s0 = tensile_strength / E, the failure stretch from fracture_energy;
    ``trilinear_knee`` [r, beta] places the knee (default Petersson's [2/9, 1/3])."""

    model: Literal["critical_stretch", "principal_stress", "fatigue", "plastic_strain", "none"] = (
        "critical_stretch"
    )
    critical_plastic_strain: PosFloat | None = None
    critical_stretch: PosFloat | None = None
    fracture_energy: PosFloat | None = None
    tensile_strength: PosFloat | None = None
    no_fail: list[str] = []
    weibull: WeibullSpec | None = None
    sed_softening: SEDSofteningSpec | None = None
    bond_law: Literal["brittle", "bilinear", "trilinear"] = "brittle"
    trilinear_knee: tuple[Finite, Finite] | None = None
    fatigue: FatigueSpec | None = None

    @model_validator(mode="after")
    def _one(self) -> Damage:
        if self.trilinear_knee is not None:
            if self.bond_law != "trilinear":
                raise ValueError("[trilinear_knee] is only used with bond_law 'trilinear'")
            for name, v in zip(("r", "beta"), self.trilinear_knee, strict=True):
                if not 0.0 < v < 1.0:
                    raise ValueError(f"[trilinear_knee] {name} must be in (0, 1), got {v}")
        plastic = _plastic_strain_error(self)
        if plastic is not None:
            raise ValueError(plastic)
        if self.bond_law != "brittle":
            law = f"bond_law {self.bond_law!r}"
            if self.model != "critical_stretch":
                raise ValueError(f"[bond_law] {law} needs model 'critical_stretch'")
            if self.critical_stretch is not None:
                raise ValueError(
                    f"[critical_stretch] {law} takes tensile_strength (the peak, s0 = f_t/E) "
                    "and fracture_energy (the tail), not critical_stretch"
                )
            for key in ("tensile_strength", "fracture_energy"):
                if getattr(self, key) is None:
                    raise ValueError(
                        f"[{key}] {law} needs tensile_strength (f_t, Pa) and "
                        "fracture_energy (G0, J/m^2)"
                    )
            for key in ("sed_softening", "weibull"):
                if getattr(self, key) is not None:
                    raise ValueError(f"[{key}] does not combine with {law}; use bond_law 'brittle'")
            return self
        fatigue = fatigue_damage_errors(self)
        if fatigue is not None:
            raise ValueError(fatigue)
        if self.model == "fatigue":
            return self
        if self.model == "plastic_strain":
            return self
        if self.model == "none":
            if self.critical_stretch is not None or self.fracture_energy is not None:
                raise ValueError(
                    "[model] model 'none' takes neither critical_stretch nor fracture_energy"
                )
            if self.tensile_strength is not None:
                raise ValueError("[tensile_strength] has no effect with model 'none'; remove it")
            if self.weibull is not None or self.sed_softening is not None:
                raise ValueError("[model] weibull and sed_softening need model 'critical_stretch'")
        elif self.model == "principal_stress":
            if self.tensile_strength is None:
                raise ValueError(
                    "[tensile_strength] model 'principal_stress' needs tensile_strength (f_t, Pa)"
                )
            if self.critical_stretch is not None or self.fracture_energy is not None:
                raise ValueError(
                    "[model] model 'principal_stress' uses tensile_strength only; for both "
                    "criteria use model 'critical_stretch' with tensile_strength"
                )
            if self.weibull is not None or self.sed_softening is not None:
                raise ValueError("[model] weibull and sed_softening need model 'critical_stretch'")
        elif (self.critical_stretch is None) == (self.fracture_energy is None):
            raise ValueError(
                "[critical_stretch] give exactly one of critical_stretch (s0) "
                "or fracture_energy (G0, J/m^2)"
            )
        return self


def _plastic_strain_error(d: Damage) -> str | None:
    """``critical_plastic_strain`` goes with model ``plastic_strain`` and back; at most one
    of critical_stretch and fracture_energy; no weibull or sed_softening."""
    if d.model != "plastic_strain":
        if d.critical_plastic_strain is not None:
            return "[critical_plastic_strain] is only used with model 'plastic_strain'"
        return None
    if d.critical_plastic_strain is None:
        return (
            "[critical_plastic_strain] model 'plastic_strain' needs critical_plastic_strain "
            "(the equivalent plastic strain at which a point's bonds break, > 0)"
        )
    if d.critical_stretch is not None and d.fracture_energy is not None:
        return "[critical_stretch] give at most one of critical_stretch and fracture_energy"
    if d.weibull is not None or d.sed_softening is not None:
        return "[model] weibull and sed_softening need model 'critical_stretch'"
    return None


# --------------------------------------------------------------------------- checks
def bond_law_errors(deck: Any) -> Errors:
    """Checks of the damage law against the model family (its declared capabilities)
    and the solver: tension-softening bonds need bond-based PMB bonds and a solver that
    commits their history; ``tensile_strength`` (the principal-stress criterion) needs
    a family with a stress tensor."""
    errors: Errors = []
    law, mat = deck.damage.bond_law, deck.material
    if law != "brittle":  # tension-softening bonds: bond-based PMB only
        if not mat.tension_softening:
            errors.append(
                (
                    "damage.bond_law",
                    f"{law!r} softens bond-based PMB bonds: needs "
                    f"material.model pmb or bond_based (got {mat.model!r}); use bond_law "
                    "'brittle' with this material",
                )
            )
        sv = deck.solver
        if (
            sv.type == "static"
            or getattr(sv, "hybrid", None) is not None
            or getattr(sv, "method", "pd") != "pd"
        ):
            errors.append(
                (
                    "damage.bond_law",
                    f"{law!r} bonds keep a history that the explicit "
                    "(method pd, no hybrid) and adr solvers commit; use one of them",
                )
            )
    elif deck.damage.model == "plastic_strain" and getattr(mat, "plasticity", None) is None:
        errors.append(
            (
                "damage.model",
                "'plastic_strain' reads the equivalent plastic strain of an elastic-plastic "
                "law: use material.model correspondence with material.plasticity (j2 or "
                "drucker_prager), or damage.model critical_stretch",
            )
        )
    elif deck.damage.tensile_strength is not None and not mat.stress_tensor:
        errors.append(
            (
                "damage.tensile_strength",
                "the principal-stress criterion reads the stress tensor of a correspondence "
                "model: use material.model correspondence, or a critical stretch",
            )
        )
    if deck.damage.model == "plastic_strain" and deck.solver.type == "static":
        errors.append(
            (
                "damage.model",
                "'plastic_strain' breaks bonds in explicit and adr runs; the static solver "
                "breaks them by critical stretch only: use solver.type adr",
            )
        )
    return errors


def sed_softening_errors(deck: Any) -> Errors:
    """SED softening scales bond stiffness: refused by a family without bond springs."""
    if deck.damage.sed_softening is None:
        return []
    return [("damage.sed_softening", "softens bond stiffness: needs material.model pmb")]


def no_fail_errors(deck: Any, sets: set[str]) -> Errors:
    """Checks of ``damage.no_fail``: known node sets, and a law that breaks bonds."""
    errors: Errors = []
    if deck.damage.model == "none" and deck.damage.no_fail:
        errors.append(("damage.no_fail", "has no effect with model 'none'; remove it"))
    for n, name in enumerate(deck.damage.no_fail):
        if name not in sets:
            errors.append(
                (f"damage.no_fail.{n}", f"unknown node set {name!r}; known: {sorted(sets)}")
            )
    return errors
