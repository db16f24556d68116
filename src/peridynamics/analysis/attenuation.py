"""Stress-wave attenuation in rock bars (Lu & Wang (2016), eq. 19).

The amplitude of a stress pulse decays as sigma(x) = sigma0 exp(-beta x). Fitting beta to
peak amplitudes along the bar corrects a nominal spall strength measured at a gauge to
the stress that actually arrived at the spall plane:
sigma1 = sigma_nominal exp(-beta * path) (Lu & Wang (2016): 25.5 MPa -> 18.8 MPa with
beta = 0.52 1/m over the 0.39 + 0.20 = 0.59 m path).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike


def fit_attenuation(positions: ArrayLike, peaks: ArrayLike) -> tuple[float, float]:
    """Least-squares fit of ln|peak| = ln sigma0 - beta x.

    Parameters
    ----------
    positions : (n,) travel distances of the peaks (m), n >= 2.
    peaks : (n,) peak amplitudes (Pa); signs are ignored.

    Returns
    -------
    (sigma0, beta) : amplitude at x = 0 (Pa) and attenuation coefficient (1/m).
    """
    x = np.asarray(positions, dtype=float)
    p = np.abs(np.asarray(peaks, dtype=float))
    if x.shape != p.shape or x.size < 2:
        raise ValueError("need at least two (position, peak) pairs of equal length")
    if np.any(p <= 0):
        raise ValueError("peak amplitudes must be non-zero")
    slope, intercept = np.polyfit(x, np.log(p), 1)
    return float(np.exp(intercept)), float(-slope)


def corrected_strength(nominal: float, beta: float, path: float) -> float:
    """sigma1 = nominal exp(-beta path) (Lu & Wang (2016), eq. 19); units of ``nominal``."""
    if path < 0:
        raise ValueError("path must be >= 0 m")
    return float(nominal * np.exp(-beta * path))
