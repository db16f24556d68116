"""Isotropic elastic moduli from Young's modulus E and Poisson's ratio nu: the one helper
every model family takes its moduli from.

Idealisations: ``dim == 3`` (a 3-D solid), ``dim == 2`` with ``plane == "strain"``
(eps_zz = 0) or ``plane == "stress"`` (sigma_zz = 0; any other plane is read as plane
stress where a 2-D law is asked for). Units: E and every modulus in Pa, nu
dimensionless.

* shear modulus ``mu = E / (2 (1 + nu))``;
* 3-D bulk modulus ``K = E / (3 (1 - 2 nu))``;
* d-dimensional bulk modulus of the in-plane law (``sigma = lambda' tr(eps) I + 2 mu
  eps``, ``k_d = lambda' + 2 mu / d``): K in 3-D, ``E / (2 (1 + nu)(1 - 2 nu))`` in
  plane strain, ``E / (2 (1 - nu))`` in plane stress;
* Lame constant lambda' of the idealisation: ``E nu / ((1 + nu)(1 - 2 nu))`` (3-D and
  plane strain), ``E nu / (1 - nu^2)`` (plane stress);
* in-plane uniaxial-stress moduli (E', nu'): (E, nu) in 3-D and plane stress,
  ``(E / (1 - nu^2), nu / (1 - nu))`` in plane strain.

It also holds the check of (E, nu, rho) that the isotropic families share and the
constant-profile PMB micromodulus of a given E (what contact stiffness and viscous rate
constants are scaled with in every family).
"""

from __future__ import annotations

import math


def check_isotropic_constants(E: float, nu: float, rho: float, model: str) -> None:
    """Raise ValueError naming the deck key unless E > 0 (Pa), -1 < nu < 0.5 (bulk and
    shear moduli > 0) and rho > 0 (kg/m^3) are finite numbers; ``model`` names the
    family in the message."""
    if not (isinstance(E, int | float) and math.isfinite(E) and E > 0):
        raise ValueError(f"material.youngs_modulus must be a finite value > 0 Pa, got {E}")
    if not (isinstance(nu, int | float) and math.isfinite(nu) and -1.0 < nu < 0.5):
        raise ValueError(
            f"material.poisson_ratio must lie in (-1, 0.5) for the {model} model "
            f"(bulk and shear moduli > 0), got {nu}"
        )
    if not (isinstance(rho, int | float) and math.isfinite(rho) and rho > 0):
        raise ValueError(f"material.density must be a finite value > 0 kg/m^3, got {rho}")


def shear_modulus(E: float, nu: float) -> float:
    """mu = E / (2 (1 + nu)) (Pa)."""
    return E / (2.0 * (1.0 + nu))


def bulk_modulus(E: float, nu: float) -> float:
    """3-D bulk modulus K = E / (3 (1 - 2 nu)) (Pa)."""
    return E / (3.0 * (1.0 - 2.0 * nu))


def plane_bulk_modulus(E: float, nu: float, plane: str | None) -> float:
    """2-D bulk modulus kappa (Pa): E / (2 (1 + nu)(1 - 2 nu)) in plane strain,
    E / (2 (1 - nu)) otherwise (plane stress)."""
    if plane == "strain":
        return E / (2.0 * (1.0 + nu) * (1.0 - 2.0 * nu))
    return E / (2.0 * (1.0 - nu))


def dimensional_bulk_modulus(E: float, nu: float, dim: int, plane: str | None) -> float:
    """k_d (Pa): K in 3-D, :func:`plane_bulk_modulus` in 2-D."""
    if dim == 3:
        return bulk_modulus(E, nu)
    return plane_bulk_modulus(E, nu, plane)


def lame(E: float, nu: float, dim: int, plane: str | None) -> float:
    """lambda' (Pa) of the idealisation: plane stress (``dim == 2`` and plane not
    ``"strain"``) E nu / (1 - nu^2), else E nu / ((1 + nu)(1 - 2 nu))."""
    if dim == 2 and plane != "strain":
        return E * nu / (1.0 - nu * nu)
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))


def in_plane_moduli(E: float, nu: float, dim: int, plane: str | None) -> tuple[float, float]:
    """(E', nu') of the in-plane uniaxial-stress response (Pa, -): (E, nu) in 3-D and
    plane stress, (E / (1 - nu^2), nu / (1 - nu)) in plane strain."""
    if dim == 2 and plane == "strain":
        return E / (1.0 - nu * nu), nu / (1.0 - nu)
    return E, nu


def pmb_micromodulus(
    E: float, dim: int, horizon: float, cross_section: float, plane: str | None
) -> float:
    """Constant-profile bond-based micromodulus c of Young's modulus E (N/m^6), energy
    equivalence (docs/theory_bond_based.md): 2 E / (A delta^2) (1-D),
    48 E / (5 pi h delta^3) (plane strain), 9 E / (pi h delta^3) (plane stress),
    12 E / (pi delta^4) (3-D)."""
    d = horizon
    if dim == 1:
        return 2.0 * E / (cross_section * d**2)
    if dim == 2:
        if plane == "strain":
            return 48.0 * E / (5.0 * math.pi * cross_section * d**3)
        return 9.0 * E / (math.pi * cross_section * d**3)
    return 12.0 * E / (math.pi * d**4)
