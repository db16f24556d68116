"""Viscous bond forces that damp the spurious short-wave oscillation of PD.

PD wave dispersion (n.d.), section 3.2, adds to every bond a force along its deformed
direction that depends on the bond strain rate zeta = (eta_dot . n) / |xi| (eq. 52):

* linear ("bulk"):  f_1 = b1 alpha_p zeta,               alpha_p = rho v0 / V_H     (eq. 53)
* quadratic:        f_2 = sign(zeta) alpha_q (b2 zeta)^2, alpha_q = rho delta / V_H  (eq. 55)
* polynomial:       f = f_1 + f_2                                                    (eq. 56)

with v0 = sqrt(E / rho) and V_H the horizon volume: 2 delta A (1-D), pi delta^2 h (2-D),
4 pi delta^3 / 3 (3-D). b1 and b2 are dimensionless; the paper does not print the values
it used, so the defaults of the polynomial form, b1 = 0.5 and b2 = 2.0, are our proposal
(of the order of the classical artificial viscosities of von Neumann & Richtmyer 1950 and
Landshoff 1955). In 1-D,
b1 alpha_p equals gamma c of the rate form f_vs = gamma f_dot (eqs 36-39) with
gamma = b1 delta / (4 v0) (units: s).

Units: alpha_p in kg/(m^5 s), alpha_q in kg/m^5, f in N/m^6 (force per volume squared,
like the elastic bond force).
"""

from __future__ import annotations

import math
from dataclasses import dataclass


def horizon_volume(dim: int, horizon: float, cross_section: float) -> float:
    """V_H (m^3): 2 delta A in 1-D, pi delta^2 h in 2-D, 4/3 pi delta^3 in 3-D.

    ``cross_section`` is the bar area A (1-D) or the thickness h (2-D); unused in 3-D.
    """
    if dim == 1:
        return 2.0 * horizon * cross_section
    if dim == 2:
        return math.pi * horizon**2 * cross_section
    if dim == 3:
        return 4.0 / 3.0 * math.pi * horizon**3
    raise ValueError(f"dimension must be 1, 2 or 3, got {dim}")


@dataclass(frozen=True)
class BondViscosity:
    """Polynomial bond viscosity f = b1 alpha_p zeta + sign(zeta) alpha_q (b2 zeta)^2.

    Parameters
    ----------
    linear : float
        b1 >= 0 (dimensionless); 0 switches the linear term off.
    quadratic : float
        b2 >= 0 (dimensionless); 0 switches the quadratic term off.
    """

    linear: float = 0.0
    quadratic: float = 0.0

    def __post_init__(self) -> None:
        for name in ("linear", "quadratic"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(
                    f"viscosity.{name} must be a finite number >= 0 (dimensionless), got {value}"
                )

    @property
    def active(self) -> bool:
        """False when both coefficients are zero (then the model is plain PD, bitwise)."""
        return self.linear > 0 or self.quadratic > 0

    def coefficients(
        self, dim: int, horizon: float, cross_section: float, youngs_modulus: float, density: float
    ) -> tuple[float, float]:
        """(lin, quad) = (b1 alpha_p, b2^2 alpha_q) for the kernel
        f = lin zeta + quad zeta |zeta| (N s/m^6 and N s^2/m^6)."""
        vh = horizon_volume(dim, horizon, cross_section)
        v0 = math.sqrt(youngs_modulus / density)
        alpha_p = density * v0 / vh
        alpha_q = density * horizon / vh
        return self.linear * alpha_p, self.quadratic**2 * alpha_q

    def rate_constant_1d(self, horizon: float, youngs_modulus: float, density: float) -> float:
        """gamma (s) of the 1-D rate form f_vs = gamma f_dot equivalent to the linear term:
        b1 alpha_p = gamma c with c = 2E/(A delta^2) gives gamma = b1 delta / (4 v0)."""
        return self.linear * horizon / (4.0 * math.sqrt(youngs_modulus / density))
