"""Closed-form reference solutions for the double cantilever beam (DCB, mode I).

Two arms of height h and width B (m) separated by a crack
of length a (m) measured from the load line, pulled apart by a force P (N). Corrected beam
theory (Kanninen 1973, beam on an elastic foundation; Williams 1989, the form below) replaces a
by an effective length a_e = a + chi h with

    chi = sqrt[(E / (11 G)) (3 - 2 (Gamma / (1 + Gamma))**2)],      Gamma = 1.18 E / G

for an isotropic material (E11 = E22 = E, G13 = G). The compliance, the load-line opening
Delta = C P being the total opening between the two load points, is

    C = Delta / P = 8 a_e**3 / (E' B h**3)     (m/N)

with E' = E in plane stress and E' = E / (1 - nu**2) in plane strain. The energy release rate
G_I = P**2 / (2 B) dC/da = 12 P**2 a_e**2 / (E' B**2 h**3) (J/m^2) reaches the fracture energy
G_c at the critical load

    P_c(a) = (B / a_e) sqrt(E' G_c h**3 / 12) = K1 / a_e,      K1 = B sqrt(E' G_c h**3 / 12)

(N; K1 in N m). Eliminating a_e between Delta = C P and P = K1 / a_e gives the stable
propagation branch of the linear-elastic fracture mechanics (LEFM) load-displacement curve,
independent of the crack length and of chi:

    P(Delta) = K1 / sqrt(Delta E' B h**3 / (8 K1))     (N).

The correction chi is computed from E and nu in both plane states (Williams' formula is written
for the moduli of the material, and the plane-strain change of E' is a second-order effect on
chi); ``plane`` changes only the modulus E' of the beam formulas.

References
----------
M. F. Kanninen, "An augmented double cantilever beam model for studying crack propagation and
arrest", *International Journal of Fracture* 9 (1973) 83-92.
J. G. Williams, "End corrections for orthotropic DCB specimens", *Composites Science and
Technology* 35 (1989) 367-376.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from peridynamics.analysis.beams import Plane, check_poisson, check_positive, plane_modulus

__all__ = [
    "dcb_chi",
    "dcb_compliance",
    "dcb_critical_load",
    "dcb_lefm_curve",
]

F = NDArray[np.float64]


def dcb_chi(E: float, nu: float) -> float:
    """Crack-length correction chi of corrected beam theory for an isotropic DCB.

    chi = sqrt[(E / (11 G)) (3 - 2 (Gamma / (1 + Gamma))**2)], Gamma = 1.18 E / G and
    G = E / (2 (1 + nu)) (Kanninen 1973; Williams 1989). Dimensionless; 0.645 for nu = 0.2.

    Parameters
    ----------
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio.

    Returns
    -------
    float
        chi; the effective crack length is a + chi h.
    """
    check_positive(E=E)
    check_poisson(nu)
    e_over_g = 2.0 * (1.0 + nu)
    gamma = 1.18 * e_over_g
    return math.sqrt(e_over_g / 11.0 * (3.0 - 2.0 * (gamma / (1.0 + gamma)) ** 2))


def dcb_compliance(
    a: ArrayLike,
    arm_height: float,
    thickness: float,
    E: float,
    nu: float,
    plane: Plane = "stress",
) -> F:
    """Load-line compliance 8 (a + chi h)**3 / (E' B h**3) of a DCB (m/N).

    Corrected beam theory (Kanninen 1973; Williams 1989); the opening Delta = C P is the total
    separation of the two load points.

    Parameters
    ----------
    a : array_like
        Crack length measured from the load line (m), >= 0.
    arm_height : float
        Height h of one arm (m).
    thickness : float
        Specimen width B (m).
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio.
    plane : {"stress", "strain"}
        E' = E in plane stress, E / (1 - nu**2) in plane strain.

    Returns
    -------
    ndarray
        Compliance (m/N), shaped like ``a``.
    """
    check_positive(arm_height=arm_height, thickness=thickness)
    modulus = plane_modulus(E, nu, plane)
    a_eff = np.asarray(a, dtype=float) + dcb_chi(E, nu) * arm_height
    return 8.0 * a_eff**3 / (modulus * thickness * arm_height**3)


def _dcb_k1(arm_height: float, thickness: float, modulus: float, fracture_energy: float) -> float:
    """K1 = B sqrt(E' G_c h**3 / 12) (N m): the product P_c a_e at propagation."""
    check_positive(arm_height=arm_height, thickness=thickness, fracture_energy=fracture_energy)
    return thickness * math.sqrt(modulus * fracture_energy * arm_height**3 / 12.0)


def dcb_critical_load(
    a: ArrayLike,
    arm_height: float,
    thickness: float,
    E: float,
    nu: float,
    fracture_energy: float,
    plane: Plane = "stress",
) -> F:
    """Critical load P_c = (B / a_e) sqrt(E' G_c h**3 / 12) of a DCB (N).

    The load at which the energy release rate 12 P**2 a_e**2 / (E' B**2 h**3) of corrected beam
    theory equals the fracture energy (Kanninen 1973; Williams 1989), a_e = a + chi h.

    Parameters
    ----------
    a : array_like
        Crack length from the load line (m).
    arm_height : float
        Height h of one arm (m).
    thickness : float
        Specimen width B (m).
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio.
    fracture_energy : float
        Critical energy release rate G_c (J/m^2).
    plane : {"stress", "strain"}
        E' = E in plane stress, E / (1 - nu**2) in plane strain.

    Returns
    -------
    ndarray
        P_c (N), shaped like ``a``.
    """
    modulus = plane_modulus(E, nu, plane)
    k1 = _dcb_k1(arm_height, thickness, modulus, fracture_energy)
    a_eff = np.asarray(a, dtype=float) + dcb_chi(E, nu) * arm_height
    return k1 / a_eff


def dcb_lefm_curve(
    delta: ArrayLike,
    arm_height: float,
    thickness: float,
    E: float,
    nu: float,
    fracture_energy: float,
    plane: Plane = "stress",
    *,
    crack_length: float | None = None,
) -> F:
    """LEFM load-opening curve P(Delta) of a DCB by corrected beam theory (N).

    Without ``crack_length``: the stable propagation branch
    P = K1 / sqrt(Delta E' B h**3 / (8 K1)), K1 = B sqrt(E' G_c h**3 / 12), which holds
    whatever the crack length (Kanninen 1973; Williams 1989); it is infinite at Delta = 0.
    With ``crack_length`` a0: the whole curve, min(Delta / C(a0), propagation branch), i.e. the
    linear loading line of the initial crack up to (C(a0) P_c(a0), P_c(a0)) followed by the
    propagation branch.

    Parameters
    ----------
    delta : array_like
        Total load-line opening Delta (m), >= 0.
    arm_height : float
        Height h of one arm (m).
    thickness : float
        Specimen width B (m).
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio.
    fracture_energy : float
        Critical energy release rate G_c (J/m^2).
    plane : {"stress", "strain"}
        E' = E in plane stress, E / (1 - nu**2) in plane strain.
    crack_length : float, optional
        Initial crack length a0 (m) from the load line; see above.

    Returns
    -------
    ndarray
        Load P (N), shaped like ``delta``.
    """
    d = np.asarray(delta, dtype=float)
    if np.any(d < 0.0):
        raise ValueError("delta must be non-negative")
    modulus = plane_modulus(E, nu, plane)
    k1 = _dcb_k1(arm_height, thickness, modulus, fracture_energy)
    with np.errstate(divide="ignore"):
        load = k1 / np.sqrt(d * modulus * thickness * arm_height**3 / (8.0 * k1))
    if crack_length is not None:
        if crack_length < 0.0:
            raise ValueError(f"crack_length must be non-negative, got {crack_length!r}")
        compliance = dcb_compliance(crack_length, arm_height, thickness, E, nu, plane)
        load = np.minimum(d / compliance, load)
    return load
