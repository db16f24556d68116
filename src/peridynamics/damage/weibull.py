"""Weibull heterogeneity of the critical stretch (SED-PD (2021), eqs 25-26).

Each point draws u_i from the Weibull law f(u) = (m/u0) (u/u0)^(m-1) exp[-(u/u0)^m]
by inversion, u_i = scale (-ln U_i)^(1/m) with U_i ~ U(0, 1) from NumPy's PCG64
generator seeded with ``seed`` (same seed, same field, on any machine). The varied
parameter is either the fracture energy G (default: s_i = s0 sqrt(G_i / u0), since
s ~ sqrt(G) in eq. 26) or the critical stretch itself (s_i = s0 u_i / u0). The paper
calls u0 "the mean" but uses it as the scale: ``u0_is="scale"`` (default) takes it as
the scale; ``u0_is="mean"`` rescales so the mean is u0 (scale u0 / Gamma(1 + 1/m)).
The bond threshold is the mean of its two points' values (done by the damage model).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class WeibullField:
    """Per-point multiplicative factors s_i / s0 from a seeded Weibull draw.

    Parameters
    ----------
    shape : float
        Weibull modulus m > 0 (SED-PD (2021), section 3.2, tests 2, 6, 10, 20, 50,
        100; adopts 10).
    seed : int
        Seed of the generator (>= 0).
    variable : {"fracture_energy", "critical_stretch"}
        Which parameter is Weibull distributed.
    u0_is : {"scale", "mean"}
        Reading of u0 (see the module docstring).
    """

    shape: float
    seed: int = 0
    variable: Literal["fracture_energy", "critical_stretch"] = "fracture_energy"
    u0_is: Literal["scale", "mean"] = "scale"

    def __post_init__(self) -> None:
        if not (math.isfinite(self.shape) and self.shape > 0):
            raise ValueError(f"weibull.shape must be > 0, got {self.shape}")
        if self.seed < 0:
            raise ValueError(f"weibull.seed must be >= 0, got {self.seed}")
        if self.variable not in ("fracture_energy", "critical_stretch"):
            raise ValueError(f"weibull.variable: unknown {self.variable!r}")
        if self.u0_is not in ("scale", "mean"):
            raise ValueError(f"weibull.u0_is: unknown {self.u0_is!r}")

    def sample(
        self, n: int, u0: float = 1.0, global_ids: NDArray[np.int64] | None = None
    ) -> NDArray[np.float64]:
        """Weibull values u_i (in the units of u0), shape (n,), or one per entry of
        ``global_ids``: the value of a point depends on its global id only (the stream
        is drawn up to the largest id), so any partition of the points into ranks draws
        the same field."""
        rng = np.random.default_rng(self.seed)
        if global_ids is None:
            uniform = rng.random(n)
        else:
            ids = np.asarray(global_ids)
            uniform = rng.random(int(ids.max()) + 1 if ids.size else 0)[ids]
        scale = u0 if self.u0_is == "scale" else u0 / math.gamma(1.0 + 1.0 / self.shape)
        # 1 - U is in (0, 1]: -log never sees 0
        return scale * (-np.log1p(-uniform)) ** (1.0 / self.shape)

    def stretch_factors(
        self, n: int, global_ids: NDArray[np.int64] | None = None
    ) -> NDArray[np.float64]:
        """s_i / s0, shape (n,): sqrt(G_i / u0) or u_i / u0 (by global id, see
        :meth:`sample`)."""
        u = self.sample(n, 1.0, global_ids)
        return np.sqrt(u) if self.variable == "fracture_energy" else u
