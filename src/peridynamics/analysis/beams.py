"""Closed-form reference solutions for beams: end-loaded cantilever and double cantilever beam.

Cantilever (plane stress). A rectangular beam of length L, depth H and thickness t (m), Young's
modulus E (Pa) and Poisson's ratio nu, clamped at x = 0 and loaded at x = L by a shear force P
(N, positive in +y) distributed parabolically over the end section. With x measured from the
clamp, y from the neutral axis (-H/2 <= y <= H/2) and I = t H**3 / 12 (m^4), the elasticity
solution of Timoshenko & Goodier (1970), section 21, written as in the adaptive-analysis benchmark
of Augarde & Deeks (2008), is

    u_x = -(P y / (6 E I)) [(6 L - 3 x) x + (2 + nu) (y**2 - H**2 / 4)]
    u_y =  (P / (6 E I)) [3 nu y**2 (L - x) + (4 + 5 nu) H**2 x / 4 + (3 L - x) x**2]

(m). It satisfies u = 0 at the clamp's neutral axis (x = 0, y = 0) and has the stresses
sigma_xx = -P (L - x) y / I, sigma_yy = 0 and tau_xy = P (H**2 / 4 - y**2) / (2 I) (Pa), so the
top and bottom faces are traction free. The section x = 0 is not fully clamped: the solution
prescribes the (small) warping displacements above, which a finite-element model with u = 0 on
the whole edge does not reproduce. The tip deflection on the neutral axis is

    u_y(L, 0) = P L**3 / (3 E I) + (4 + 5 nu) P L / (2 E t H).

Timoshenko beam theory (Timoshenko 1921; Timoshenko & Gere, *Mechanics of Materials*) gives
P L**3 / (3 E I) + P L / (k G A) with G = E / (2 (1 + nu)), A = t H and the shear correction
factor k = 5/6 of a rectangular section; Euler-Bernoulli theory keeps only P L**3 / (3 E I).

Double cantilever beam (DCB, mode I). Two arms of height h and width B (m) separated by a crack
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
S. P. Timoshenko and J. N. Goodier, *Theory of Elasticity*, 3rd ed. (McGraw-Hill, 1970),
section 21 (bending of a cantilever loaded at the end).
C. E. Augarde and A. J. Deeks, "The use of Timoshenko's exact solution for a cantilever beam in
adaptive analysis", *Finite Elements in Analysis and Design* 44 (2008) 595-601.
M. F. Kanninen, "An augmented double cantilever beam model for studying crack propagation and
arrest", *International Journal of Fracture* 9 (1973) 83-92.
J. G. Williams, "End corrections for orthotropic DCB specimens", *Composites Science and
Technology* 35 (1989) 367-376.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "dcb_chi",
    "dcb_compliance",
    "dcb_critical_load",
    "dcb_lefm_curve",
    "euler_bernoulli_tip_deflection",
    "timoshenko_beam_tip_deflection",
    "timoshenko_goodier_cantilever",
    "timoshenko_goodier_tip_deflection",
]

F = NDArray[np.float64]
Plane = Literal["stress", "strain"]


def _check_positive(**values: float) -> None:
    for name, value in values.items():
        if not value > 0.0:
            raise ValueError(f"{name} must be positive, got {value!r}")


def _check_poisson(nu: float) -> None:
    if not -1.0 < nu < 0.5:
        raise ValueError(f"nu must lie in (-1, 0.5), got {nu!r}")


def _second_moment(height: float, thickness: float) -> float:
    """Second moment of area t H**3 / 12 (m^4) of a rectangular section."""
    return thickness * height**3 / 12.0


def _plane_modulus(E: float, nu: float, plane: str) -> float:
    """E' (Pa): E in plane stress, E / (1 - nu**2) in plane strain."""
    if plane == "stress":
        return E
    if plane == "strain":
        return E / (1.0 - nu**2)
    raise ValueError(f"plane must be 'stress' or 'strain', got {plane!r}")


# --------------------------------------------------------------------------------------------
# End-loaded cantilever
# --------------------------------------------------------------------------------------------


def timoshenko_goodier_cantilever(
    x: ArrayLike,
    y: ArrayLike,
    load: float,
    length: float,
    height: float,
    thickness: float,
    E: float,
    nu: float,
) -> tuple[F, F]:
    """Plane-stress displacements of a cantilever under a parabolic end shear.

    Timoshenko & Goodier (1970), section 21, in the form of Augarde & Deeks (2008): see the
    module docstring for the formulas and the boundary conditions they satisfy.

    Parameters
    ----------
    x : array_like
        Distance from the clamped end (m), 0 <= x <= ``length``.
    y : array_like
        Distance from the neutral axis (m), -``height``/2 <= y <= ``height``/2. Broadcast
        against ``x``.
    load : float
        Resultant end shear force P (N), signed: positive in +y, negative downwards.
    length : float
        Beam length L (m).
    height : float
        Beam depth H (m).
    thickness : float
        Out-of-plane thickness t (m).
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio.

    Returns
    -------
    ux, uy : ndarray
        Displacements (m), shaped like ``x`` and ``y`` broadcast together. Both scale linearly
        with ``load``.
    """
    _check_positive(length=length, height=height, thickness=thickness, E=E)
    _check_poisson(nu)
    xa, ya = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    inertia = _second_moment(height, thickness)
    c = load / (6.0 * E * inertia)
    quarter_h2 = 0.25 * height**2
    ux = -c * ya * ((6.0 * length - 3.0 * xa) * xa + (2.0 + nu) * (ya**2 - quarter_h2))
    uy = c * (
        3.0 * nu * ya**2 * (length - xa)
        + (4.0 + 5.0 * nu) * quarter_h2 * xa
        + (3.0 * length - xa) * xa**2
    )
    return ux, uy


def timoshenko_goodier_tip_deflection(
    load: float, length: float, height: float, thickness: float, E: float, nu: float
) -> float:
    """Neutral-axis tip deflection u_y(L, 0) of the Timoshenko & Goodier cantilever (m).

    P L**3 / (3 E I) + (4 + 5 nu) P L / (2 E t H), Timoshenko & Goodier (1970), section 21;
    signed like ``load`` (N). Lengths in m, ``E`` in Pa.
    """
    _check_positive(length=length, height=height, thickness=thickness, E=E)
    _check_poisson(nu)
    bending = load * length**3 / (3.0 * E * _second_moment(height, thickness))
    shear = (4.0 + 5.0 * nu) * load * length / (2.0 * E * thickness * height)
    return bending + shear


def timoshenko_beam_tip_deflection(
    load: float,
    length: float,
    height: float,
    thickness: float,
    E: float,
    nu: float,
    shear_factor: float = 5.0 / 6.0,
) -> float:
    """Tip deflection of an end-loaded cantilever by Timoshenko beam theory.

    P L**3 / (3 E I) + P L / (k G A) with G = E / (2 (1 + nu)) and A = t H (Timoshenko 1921;
    Timoshenko & Gere, *Mechanics of Materials*, shear deflections).

    Parameters
    ----------
    load : float
        End force P (N), signed.
    length, height, thickness : float
        Beam length L, depth H and thickness t (m).
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio.
    shear_factor : float, optional
        Shear correction factor k; 5/6 for a rectangular section.

    Returns
    -------
    float
        Tip deflection (m), signed like ``load``.
    """
    _check_positive(
        length=length, height=height, thickness=thickness, E=E, shear_factor=shear_factor
    )
    _check_poisson(nu)
    shear_modulus = E / (2.0 * (1.0 + nu))
    bending = load * length**3 / (3.0 * E * _second_moment(height, thickness))
    shear = load * length / (shear_factor * shear_modulus * thickness * height)
    return bending + shear


def euler_bernoulli_tip_deflection(
    load: float, length: float, height: float, thickness: float, E: float
) -> float:
    """Tip deflection P L**3 / (3 E I) of an end-loaded Euler-Bernoulli cantilever (m).

    ``load`` P in N (signed), ``length``, ``height`` and ``thickness`` in m, ``E`` in Pa;
    I = t H**3 / 12 (Timoshenko & Gere, *Mechanics of Materials*, deflections of beams).
    """
    _check_positive(length=length, height=height, thickness=thickness, E=E)
    return load * length**3 / (3.0 * E * _second_moment(height, thickness))


# --------------------------------------------------------------------------------------------
# Double cantilever beam (mode I), corrected beam theory
# --------------------------------------------------------------------------------------------


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
    _check_positive(E=E)
    _check_poisson(nu)
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
    _check_positive(arm_height=arm_height, thickness=thickness)
    modulus = _plane_modulus(E, nu, plane)
    a_eff = np.asarray(a, dtype=float) + dcb_chi(E, nu) * arm_height
    return 8.0 * a_eff**3 / (modulus * thickness * arm_height**3)


def _dcb_k1(arm_height: float, thickness: float, modulus: float, fracture_energy: float) -> float:
    """K1 = B sqrt(E' G_c h**3 / 12) (N m): the product P_c a_e at propagation."""
    _check_positive(arm_height=arm_height, thickness=thickness, fracture_energy=fracture_energy)
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
    modulus = _plane_modulus(E, nu, plane)
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
    modulus = _plane_modulus(E, nu, plane)
    k1 = _dcb_k1(arm_height, thickness, modulus, fracture_energy)
    with np.errstate(divide="ignore"):
        load = k1 / np.sqrt(d * modulus * thickness * arm_height**3 / (8.0 * k1))
    if crack_length is not None:
        if crack_length < 0.0:
            raise ValueError(f"crack_length must be non-negative, got {crack_length!r}")
        compliance = dcb_compliance(crack_length, arm_height, thickness, E, nu, plane)
        load = np.minimum(d / compliance, load)
    return load
