"""The stable explicit step with mass-proportional damping and linear bond viscosity.

Both integrators of :class:`~peridynamics.solvers.explicit.ExplicitSolver` evaluate the
forces at u_n with the mid-step velocity v_{n-1/2} = (u_n - u_{n-1}) / dt (velocity
Verlet's drift velocity; central difference's (u_n - u_{n-1}) / dt), and both are, in
displacements, the three-level scheme

    M (u_{n+1} - 2 u_n + u_{n-1}) / dt^2 + C (u_n - u_{n-1}) / dt + K u_n = 0

for the linearised model M a + C v + K u = 0 (M the lumped masses, K the bond stiffness,
C = c_d M + C_v the mass damping ``solver.damping`` and the linear bond viscosity).

**Derivation.** Multiplying the scheme by u_{n+1} - u_{n-1} gives, for symmetric
M, K, C >= 0, with w = u_{n+1} - u_n and ubar = (u_{n+1} + u_n) / 2,

    E_{n+1/2} = w^T (M / dt^2 - K / 4 - C / (2 dt)) w + ubar^T K ubar,
    E_{n+1/2} - E_{n-1/2} = -(u_{n+1} - u_{n-1})^T C (u_{n+1} - u_{n-1}) / (2 dt) <= 0,

so the scheme is stable when 4 M - dt^2 K - 2 dt C is positive definite. For one mode
of frequency omega and mass damping c (1/s) that is omega^2 dt^2 + 2 c dt < 4, the root
of which is the bound of Belytschko, Liu & Moran (2000), section 6.3, for central
differences with the damping ratio xi = c / (2 omega) of the highest frequency:

    dt <= (2 / omega) (sqrt(1 + xi^2) - xi) = 4 / (b + sqrt(b^2 + 4 omega^2)),  b = 2 omega xi.

The elastic limit dt_el (Silling & Askari (2005), minimised over points) certifies
omega_max <= 2 / dt_el. Bond by bond the viscous coefficient is at most gamma times the
elastic one (gamma (s) the largest ratio, the 1-D rate constant of PD wave dispersion
(n.d.), eq. 39), so C_v <= gamma K, and with K <= omega_max^2 M the condition holds when

    omega^2 dt^2 + 2 dt (c_d + gamma omega^2) < 4,   omega = 2 / dt_el,

that is dt <= dt_el (sqrt(1 + xi^2) - xi) = dt_el / (sqrt(1 + xi^2) + xi) with the
Rayleigh damping ratio of the fastest mode xi = c_d dt_el / 4 + gamma / dt_el. Without
damping it is dt_el; for large damping it tends to 2 / c_d (mass damping) or
dt_el^2 / (2 gamma) (viscosity). The form with the sum in the denominator has no
cancellation. The quadratic viscosity (amplitude dependent), contact and rigid bodies
are not in the bound.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class StableStep:
    """The stable explicit step and what lowers it.

    Parameters
    ----------
    elastic : float
        dt_el (s), the undamped bound (inf for a model without bonds).
    damping : float
        Mass-proportional damping coefficient c_d (1/s), ``solver.damping``.
    gamma : float
        Largest ratio of viscous to elastic bond coefficient (s), from
        ``material.viscosity.linear``; 0 without viscosity.
    """

    elastic: float
    damping: float = 0.0
    gamma: float = 0.0

    @property
    def omega(self) -> float:
        """The bound 2 / dt_el on the highest frequency (rad/s)."""
        return 2.0 / self.elastic if self.elastic > 0 else math.inf

    @property
    def xi_damping(self) -> float:
        """Damping ratio of the fastest mode from the mass damping, c_d dt_el / 4."""
        return self.damping * self.elastic / 4.0 if self.damping > 0 else 0.0

    @property
    def xi_viscous(self) -> float:
        """Damping ratio of the fastest mode from the linear viscosity, gamma / dt_el."""
        return self.gamma / self.elastic if self.gamma > 0 else 0.0

    @property
    def xi(self) -> float:
        """Damping ratio of the fastest mode, xi = c_d / (2 omega) + gamma omega / 2."""
        return self.xi_damping + self.xi_viscous

    @property
    def value(self) -> float:
        """The stable step (s): 4 / (b + sqrt(b^2 + 4 omega^2)), b = c_d + gamma omega^2
        (= dt_el / (sqrt(1 + xi^2) + xi); 2 / c_d without bonds)."""
        if not self.elastic > 0:
            return self.elastic
        w = self.omega
        b = (self.damping if self.damping > 0 else 0.0) + (
            self.gamma * w * w if self.gamma > 0 else 0.0
        )
        if b == 0.0:
            return self.elastic
        # 2 / (b/2 + hypot(b, 2 w)/2): no overflow below the largest float
        return 2.0 / (0.5 * b + 0.5 * math.hypot(b, 2.0 * w))

    def limited_by(self, factor: float = 1.5) -> str | None:
        """The deck key that lowers the step by more than ``factor`` (the larger of the
        two damping ratios), or None."""
        if not self.value * factor < self.elastic:
            return None
        if self.xi_damping >= self.xi_viscous:
            return "solver.damping"
        return "material.viscosity.linear"
