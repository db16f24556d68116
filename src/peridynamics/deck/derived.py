"""Checks of quantities derived from several keys: the wave speed, the PMB
micromodulus and the critical stretch from a fracture energy must be finite and > 0."""

from __future__ import annotations

import math
from typing import Any

from peridynamics.deck.geometry import cross_section
from peridynamics.deck.materials import Material
from peridynamics.deck.types import Errors

SPEED_OF_LIGHT = 299_792_458.0  # m/s: no wave in a solid is faster
#: a typical solid (rock, glass): the reference for saying which of E and rho is off
_TYPICAL_E, _TYPICAL_RHO = 1.0e10, 2.5e3


def _finite_positive(value: float) -> bool:
    return math.isfinite(value) and value > 0


def derived_errors(deck: Any) -> Errors:
    """Quantities derived from several keys that must be finite and non-zero: the wave
    speed sqrt(E / rho) (and below the speed of light), the micromodulus and the
    critical stretch computed from the fracture energy. Absurd values (E = 1e308,
    rho = 1e-300, a typo in the exponent) then fail here with the key named instead of
    giving a zero or a 1e-100 s time step."""
    errors: Errors = []
    m = deck.material
    E, rho = m.youngs_modulus, m.density
    try:
        speed = math.sqrt(E / rho)
    except (OverflowError, ZeroDivisionError):
        speed = math.inf
    off_e = abs(math.log10(E / _TYPICAL_E))
    off_rho = abs(math.log10(rho / _TYPICAL_RHO))
    blame = "material.youngs_modulus" if off_e >= off_rho else "material.density"
    units = "check the units: youngs_modulus in Pa, density in kg/m^3"
    if not _finite_positive(speed) or speed > SPEED_OF_LIGHT:
        why = "faster than light" if speed > SPEED_OF_LIGHT else "not a finite number > 0"
        errors.append(
            (
                blame,
                f"the wave speed sqrt(E / rho) = {speed:.3g} m/s (E = {E:.6g} Pa, "
                f"rho = {rho:.6g} kg/m^3) is {why}; {units}",
            )
        )
        return errors
    if not isinstance(m, Material):
        return errors
    from peridynamics.families.pmb.material import BondBasedMaterial

    g, dim = deck.geometry, deck.dim
    plane = getattr(g, "plane", None) if dim == 2 else None
    area = cross_section(g)
    delta = deck.discretisation.delta
    try:
        mat = BondBasedMaterial(E, rho, m.micromodulus_profile, m.micromodulus)
        c0 = mat.micromodulus_constant(dim, delta, area, plane)
    except (OverflowError, ZeroDivisionError, ValueError):
        c0 = math.inf
    if not _finite_positive(c0):
        if m.micromodulus is not None:
            key = "material.micromodulus"
        elif max(off_e, off_rho) > 3:  # E or rho 1000 x off a typical solid
            key = blame
        elif deck.discretisation.horizon is not None:
            key = "discretisation.horizon"
        else:
            key = "discretisation.spacing"
        errors.append(
            (
                key,
                f"the micromodulus c = {c0:.3g} N/m^6 (E = {E:.6g} Pa, horizon = "
                f"{delta:.6g} m) is not a finite number > 0; {units}, lengths in m",
            )
        )
        return errors
    g0 = deck.damage.fracture_energy
    if deck.damage.model != "none" and g0 is not None:
        try:
            s0 = mat.critical_stretch(g0, dim, delta, area, plane)
        except (OverflowError, ZeroDivisionError, ValueError):
            s0 = math.nan
        if not _finite_positive(s0):
            errors.append(
                (
                    "damage.fracture_energy",
                    f"the critical stretch from G0 = {g0:.6g} J/m^2 and E = {E:.6g} Pa is "
                    f"{s0:.3g}, not a finite number > 0; check the units (J/m^2, Pa)",
                )
            )
    return errors
