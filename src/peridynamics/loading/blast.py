"""Blast pressure pulse of a spherical free-air burst of TNT (Kingery & Bulmash 1984).

This is the blast load of PD wave dispersion (n.d.), sections 4.1.2 (bar loaded by blasts) and
4.2 (ring). The paper gives only "a pressure history, negative phase ignored"; this project
reconstructs it (docs/theory_viscosity.md) as the normally reflected pressure ``P_r`` and
impulse ``I_r`` of :func:`peridynamics.loading.blast_parameters.kingery_bulmash`, applied as a
triangular pulse of the UFC fictitious duration ``t_r = 2 I_r / P_r`` (default) or as a modified
Friedlander pulse; the negative phase is ignored.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

from scipy.optimize import brentq

from peridynamics.loading.blast_parameters import BlastParameters, kingery_bulmash
from peridynamics.loading.time_functions import TimeFunction

__all__ = ["BlastPulse", "friedlander_decay"]


def _friedlander_ratio(b: float) -> float:
    """Integral of (1 - s) exp(-b s) over s in [0, 1] = (b - 1 + exp(-b)) / b**2 (1/2 at b = 0)."""
    if b < 1e-4:
        return 0.5 - b / 6.0 + b * b / 24.0
    return (b + math.expm1(-b)) / (b * b)


def friedlander_decay(peak_Pa: float, duration_s: float, impulse_Pa_s: float) -> float:
    """Decay coefficient b > 0 of the modified Friedlander pulse with a prescribed impulse.

    Solves (``scipy.optimize.brentq``) for b in

        I = P t_d (b - 1 + exp(-b)) / b**2,

    the integral over [0, t_d] of p(t) = P (1 - t/t_d) exp(-b t/t_d) (docs/theory_viscosity.md).
    The right-hand side decreases from P t_d / 2 (b -> 0, triangle) to 0 (b -> inf), so a solution
    exists only for 0 < I < P t_d / 2.

    Parameters
    ----------
    peak_Pa : float
        Peak pressure P (Pa), > 0.
    duration_s : float
        Positive-phase duration t_d (s), > 0.
    impulse_Pa_s : float
        Target impulse I (Pa s), > 0.

    Returns
    -------
    float
        The dimensionless decay coefficient b.

    Raises
    ------
    ValueError
        If no b > 0 reproduces the impulse (I >= P t_d / 2).
    """
    target = impulse_Pa_s / (peak_Pa * duration_s)
    if not 0.0 < target < 0.5:
        raise ValueError(
            f"no Friedlander decay b > 0 gives impulse I = {impulse_Pa_s:.6g} Pa s with peak "
            f"P = {peak_Pa:.6g} Pa and duration t_d = {duration_s:.6g} s: it needs I < P t_d / 2 = "
            f"{0.5 * peak_Pa * duration_s:.6g} Pa s (I / (P t_d) = {target:.4g}); the "
            "Kingery-Bulmash duration is probably extrapolated here -- use shape='triangular'"
        )
    # f(b) < 1/b, so f(2/target) < target/2 < target; f(0+) = 1/2 > target.
    return float(
        brentq(
            lambda b: _friedlander_ratio(b) - target,
            1e-12,
            2.0 / target,
            xtol=1e-14,
            rtol=1e-13,
            maxiter=200,
        )
    )


@dataclass(frozen=True)
class BlastPulse(TimeFunction):
    """Normally reflected blast pressure history p(t) in Pa (positive phase only).

    ``__call__`` returns the PRESSURE (Pa); the boundary condition multiplies it by its own
    dimensionless scale.  ``t`` is measured from the shock arrival shifted by ``delay``:
    with tau = t - delay, p = 0 for tau < 0 and after the positive phase (negative phase ignored;
    PD wave dispersion (n.d.), section 4.1.2; docs/theory_viscosity.md).  Parameters are
    computed once at construction with :func:`kingery_bulmash` (which warns with
    ``BlastRangeWarning`` when Z is out of range).

    The two pulse shapes:

    ``"triangular"`` (recommended, UFC 3-340-02 fictitious reflected duration)
        p(tau) = P_r (1 - tau/t_r) for 0 <= tau <= t_r, t_r = 2 I_r / P_r, so that int p = I_r.
    ``"friedlander"`` (modified Friedlander)
        p(tau) = P_r (1 - tau/t_d) exp(-b tau/t_d) for 0 <= tau <= t_d, t_d = Kingery-Bulmash
        positive duration t_0, b > 0 solved so that int_0^t_d p = I_r (see
        :func:`friedlander_decay`); a ValueError is raised if I_r >= P_r t_d / 2.

    Parameters
    ----------
    charge_kg : float
        TNT charge mass W (kg).
    standoff_m : float
        Stand-off R (m).
    shape : {"triangular", "friedlander"}
        Pulse shape.
    delay : float
        Start time of the pulse (s), finite and >= 0.
    """

    charge_kg: float
    standoff_m: float
    shape: Literal["triangular", "friedlander"] = "triangular"
    delay: float = 0.0
    _parameters: BlastParameters = field(init=False, repr=False, compare=False)
    _duration: float = field(init=False, repr=False, compare=False)
    _decay: float | None = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.shape not in ("triangular", "friedlander"):
            raise ValueError(f"shape must be 'triangular' or 'friedlander', got {self.shape!r}")
        try:
            delay = float(self.delay)
        except (TypeError, ValueError):
            raise ValueError(
                f"delay must be a finite number >= 0 (s), got {self.delay!r}"
            ) from None
        if not math.isfinite(delay) or delay < 0.0:
            raise ValueError(f"delay must be a finite number >= 0 (s), got {self.delay!r}")
        params = kingery_bulmash(self.charge_kg, self.standoff_m)
        decay: float | None
        if self.shape == "triangular":
            duration = params.reflected_duration_s
            decay = None
        else:
            duration = params.positive_duration_s
            decay = friedlander_decay(
                params.reflected_pressure_Pa, duration, params.reflected_impulse_Pa_s
            )
        object.__setattr__(self, "_parameters", params)
        object.__setattr__(self, "_duration", float(duration))
        object.__setattr__(self, "_decay", decay)

    @property
    def parameters(self) -> BlastParameters:
        """The Kingery-Bulmash blast parameters (SI units)."""
        return self._parameters

    @property
    def peak_Pa(self) -> float:
        """Peak pressure P_r (Pa), reached at tau = 0+."""
        return self._parameters.reflected_pressure_Pa

    @property
    def duration_s(self) -> float:
        """Pulse duration (s): t_r = 2 I_r / P_r (triangular) or t_d = t_0 (Friedlander)."""
        return self._duration

    @property
    def decay(self) -> float | None:
        """Friedlander decay coefficient b (dimensionless); None for the triangular pulse."""
        return self._decay

    @property
    def impulse_Pa_s(self) -> float:
        """Integral of the pulse over time (Pa s): P_r t_r / 2 (triangular) or
        P_r t_d (b - 1 + exp(-b)) / b**2 (Friedlander); equals I_r by construction."""
        if self._decay is None:
            return 0.5 * self.peak_Pa * self._duration
        return self.peak_Pa * self._duration * _friedlander_ratio(self._decay)

    def __call__(self, t: float) -> float:
        tau = float(t) - float(self.delay)
        if tau < 0.0 or tau > self._duration:
            return 0.0
        s = tau / self._duration
        if self._decay is None:
            return float(self.peak_Pa * (1.0 - s))
        return float(self.peak_Pa * (1.0 - s) * math.exp(-self._decay * s))
