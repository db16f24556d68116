"""Closed-form reference solutions for an end-loaded cantilever beam.

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

The double cantilever beam (DCB, mode I) is :mod:`peridynamics.analysis.dcb`.

References
----------
S. P. Timoshenko and J. N. Goodier, *Theory of Elasticity*, 3rd ed. (McGraw-Hill, 1970),
section 21 (bending of a cantilever loaded at the end).
C. E. Augarde and A. J. Deeks, "The use of Timoshenko's exact solution for a cantilever beam in
adaptive analysis", *Finite Elements in Analysis and Design* 44 (2008) 595-601.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "check_poisson",
    "check_positive",
    "euler_bernoulli_tip_deflection",
    "plane_modulus",
    "second_moment",
    "timoshenko_beam_tip_deflection",
    "timoshenko_goodier_cantilever",
    "timoshenko_goodier_tip_deflection",
]

F = NDArray[np.float64]
Plane = Literal["stress", "strain"]


def check_positive(**values: float) -> None:
    """ValueError unless every value is positive (the keyword names it)."""
    for name, value in values.items():
        if not value > 0.0:
            raise ValueError(f"{name} must be positive, got {value!r}")


def check_poisson(nu: float) -> None:
    """ValueError unless -1 < nu < 0.5."""
    if not -1.0 < nu < 0.5:
        raise ValueError(f"nu must lie in (-1, 0.5), got {nu!r}")


def second_moment(height: float, thickness: float) -> float:
    """Second moment of area t H**3 / 12 (m^4) of a rectangular section."""
    return thickness * height**3 / 12.0


def plane_modulus(E: float, nu: float, plane: str) -> float:
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
    check_positive(length=length, height=height, thickness=thickness, E=E)
    check_poisson(nu)
    xa, ya = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    inertia = second_moment(height, thickness)
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
    check_positive(length=length, height=height, thickness=thickness, E=E)
    check_poisson(nu)
    bending = load * length**3 / (3.0 * E * second_moment(height, thickness))
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
    check_positive(
        length=length, height=height, thickness=thickness, E=E, shear_factor=shear_factor
    )
    check_poisson(nu)
    shear_modulus = E / (2.0 * (1.0 + nu))
    bending = load * length**3 / (3.0 * E * second_moment(height, thickness))
    shear = load * length / (shear_factor * shear_modulus * thickness * height)
    return bending + shear


def euler_bernoulli_tip_deflection(
    load: float, length: float, height: float, thickness: float, E: float
) -> float:
    """Tip deflection P L**3 / (3 E I) of an end-loaded Euler-Bernoulli cantilever (m).

    ``load`` P in N (signed), ``length``, ``height`` and ``thickness`` in m, ``E`` in Pa;
    I = t H**3 / 12 (Timoshenko & Gere, *Mechanics of Materials*, deflections of beams).
    """
    check_positive(length=length, height=height, thickness=thickness, E=E)
    return load * length**3 / (3.0 * E * second_moment(height, thickness))
