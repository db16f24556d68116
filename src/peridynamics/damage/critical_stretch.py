"""Critical-stretch damage (PMB): a bond breaks for good once s >= s0 (seed 000 eq. 5).

The bond threshold is the mean of its end points' critical stretch, so per-point
fields (Weibull heterogeneity, "no-fail" zones with s0 = inf) enter symmetrically.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.damage.weibull import WeibullField


@dataclass(frozen=True)
class CriticalStretch:
    """Brittle bond breaking at a critical stretch.

    Parameters
    ----------
    critical_stretch : float
        s0 (dimensionless, > 0), ``inf`` disables breaking.
    no_fail : (k,) int array, optional
        Points whose bonds never break (any bond touching them is kept).
    weibull : WeibullField, optional
        Per-point heterogeneity: s0_i = s0 x factor_i (seed 001 eqs 25-26).
    """

    critical_stretch: float
    no_fail: NDArray[np.intp] | None = None
    weibull: WeibullField | None = None

    def __post_init__(self) -> None:
        if not self.critical_stretch > 0 or math.isnan(self.critical_stretch):
            raise ValueError(f"critical_stretch must be > 0, got {self.critical_stretch}")

    def point_threshold(self, n_points: int) -> NDArray[np.float64]:
        """Per-point s0, shape (n_points,), inf on no-fail points."""
        s0 = np.full(n_points, float(self.critical_stretch))
        if self.weibull is not None:
            s0 = s0 * self.weibull.stretch_factors(n_points)
        if self.no_fail is not None and len(self.no_fail):
            s0[np.asarray(self.no_fail)] = np.inf
        return s0


def family_minimum(bonds: Bonds, s0: NDArray[np.float64]) -> NDArray[np.float64]:
    """Smallest bond threshold (s0_i + s0_j)/2 over each family, shape (n_points,)."""
    per_bond = 0.5 * (s0[bonds.bond_i] + s0[bonds.bond_j])
    return np.minimum.reduceat(per_bond, bonds.offsets[:-1])  # every family is non-empty


NO_DAMAGE = CriticalStretch(critical_stretch=math.inf)
