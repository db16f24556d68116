"""Strain-energy-density (SED) softening of bond-based PD (SED-PD (2021), eqs 14-24).

Each point i carries its strain energy density W_i = 1/4 sum_j mu c s^2 |xi| V_j
(eq. 22), evaluated with the *initial* micromodulus so that softening does not lower
its own driving energy (our reconstruction, docs/theory_rock.md). Its effective
modulus steps down irreversibly:

* W_i <  W_A,i                 E_i = E                              (elastic)
* W_A,i <= W_i < W_C,i         E_i = E (N + 1 - n) / N, n = 1..N     (eqs 18-20)
  with n = min(N, 1 + floor(N (W_i - W_A,i) / (W_C,i - W_A,i))) (N equal energy bands)
* W_i >= W_C,i                 E_i = residual x E (0.05 E, eq. 21)

The point micromodulus is c_i = c E_i / E and a bond uses (c_i + c_j) / 2 (eq. 24).
Bonds still break independently at their critical stretch.

Choices the paper leaves open (our reconstruction, docs/theory_rock.md; all options
here):

* the thresholds are not printed. Default (our reconstruction): W_A,i = 1/2 E s0_i^2,
  the energy density of the linear element at the onset of damage, with s0_i the
  point's (Weibull) critical stretch; ``threshold_stretch`` replaces s0_i by a fixed
  stretch; W_C,i = k_C W_A,i with ``k_c`` = 4 by default;
* N = ``levels`` = 10 by default; the paper prints (N + 1 - n)/N without the factor E,
  which dimensionally must multiply E (a correction of the printed formula);
* ``residual`` = 0.05;
* ``energy``: "total" sums every bond as eq. 22 prints; "tensile" counts only stretched
  bonds (s > 0), so that compression alone does not soften (see docs/theory_rock.md for
  what each gives in uniaxial compression).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class SEDSoftening:
    """Parameters of SED softening (see the module docstring)."""

    levels: int = 10
    k_c: float = 4.0
    residual: float = 0.05
    threshold_stretch: float | None = None
    energy: str = "total"

    def __post_init__(self) -> None:
        if self.levels < 1:
            raise ValueError(f"sed_softening.levels must be >= 1, got {self.levels}")
        if not (math.isfinite(self.k_c) and self.k_c > 1):
            raise ValueError(f"sed_softening.k_c must be > 1 (W_C > W_A), got {self.k_c}")
        if not 0 < self.residual <= 1:
            raise ValueError(f"sed_softening.residual must be in (0, 1], got {self.residual}")
        if self.energy not in ("total", "tensile"):
            raise ValueError(
                f"sed_softening.energy must be 'total' or 'tensile', got {self.energy!r}"
            )
        if self.threshold_stretch is not None and not self.threshold_stretch > 0:
            raise ValueError("sed_softening.threshold_stretch must be > 0")

    def thresholds(
        self, youngs_modulus: float, point_s0: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(W_A, W_C) per point (J/m^3), shape (n,) each; inf where s0 is inf."""
        s = (
            point_s0
            if self.threshold_stretch is None
            else np.where(np.isfinite(point_s0), self.threshold_stretch, np.inf)
        )
        w_a = 0.5 * youngs_modulus * s**2
        return w_a, self.k_c * w_a

    def factor(self, level: NDArray[np.int64]) -> NDArray[np.float64]:
        """E_i / E for the levels 0 .. N + 1."""
        n = self.levels
        f = np.where(level == 0, 1.0, (n + 1 - level) / n)
        return np.where(level == n + 1, self.residual, f)
