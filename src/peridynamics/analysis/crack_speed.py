"""Crack-tip speeds from a history of crack-path lengths (:func:`tip_speed_from_paths`),
flagged, never clipped, where they exceed the Rayleigh speed of the model as run
(:func:`rayleigh_speed`, Viktorov (1967)).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["rayleigh_speed", "tip_speed_from_paths"]


def tip_speed_from_paths(
    times: ArrayLike,
    lengths: ArrayLike,
    rayleigh_speed: float | None = None,
    window: int = 5,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Crack-tip speed from a history of crack-path lengths.

    The speed at record i is the least-squares slope of length against time over the
    ``window`` records centred on i (clipped at both ends of the history), which smooths
    the grid-scale jumps of a path that grows one bond at a time.

    Parameters
    ----------
    times : array_like, shape (r,)
        Record times, s, increasing.
    lengths : array_like, shape (r,)
        Crack-path length at each time, m (``CrackPath.length``).
    rayleigh_speed : float, optional
        Rayleigh-wave speed c_R of the model as run, m/s (:func:`rayleigh_speed`).
    window : int, optional
        Records in the fitting window (>= 2; default 5).

    Returns
    -------
    speeds : ndarray, shape (r,)
        Tip speed, m/s. Never clipped: a speed above c_R is what the data say.
    flagged : ndarray of bool, shape (r,)
        True where the speed exceeds ``rayleigh_speed`` (all False without it): a speed
        no mode-I crack reaches in a linear elastic solid (Freund (1990)), to be checked
        (a jump between cracks, a branch overtaking the main path, too coarse a record).
    """
    t = np.asarray(times, dtype=np.float64).reshape(-1)
    s = np.asarray(lengths, dtype=np.float64).reshape(-1)
    if t.shape != s.shape:
        raise ValueError("times and lengths must have the same length")
    if window < 2:
        raise ValueError("window must be >= 2")
    r = t.size
    if r < 2:
        return np.zeros(r), np.zeros(r, dtype=bool)
    if np.any(np.diff(t) <= 0.0):
        raise ValueError("times must increase")
    scale = (t[-1] - t[0]) / (r - 1)
    tt = (t - t[0]) / scale  # dimensionless, O(1) steps: well-conditioned sums
    lo = np.clip(np.arange(r) - window // 2, 0, None)
    hi = np.clip(lo + window, None, r)
    lo = np.clip(hi - window, 0, None)

    def csum(a: NDArray[np.float64]) -> NDArray[np.float64]:
        c = np.concatenate([[0.0], np.cumsum(a)])
        return c[hi] - c[lo]

    cnt = (hi - lo).astype(np.float64)
    st, ss, stt, sts = csum(tt), csum(s), csum(tt * tt), csum(tt * s)
    den = cnt * stt - st * st
    with np.errstate(invalid="ignore", divide="ignore"):
        slope = np.where(den > 0.0, (cnt * sts - st * ss) / den, 0.0)
    speeds = slope / scale
    flagged = speeds > rayleigh_speed if rayleigh_speed is not None else np.zeros(r, dtype=bool)
    return speeds, np.asarray(flagged, dtype=bool)


def rayleigh_speed(
    E: float,
    nu: float | None,
    rho: float,
    plane: Literal["stress", "strain", "3d"] = "stress",
    method: Literal["viktorov", "exact"] = "viktorov",
) -> float:
    """Rayleigh-wave speed c_R of an isotropic elastic solid, m/s.

    Parameters
    ----------
    E : float
        Young's modulus (the 3-D one, as in the deck), Pa.
    nu : float or None
        Poisson's ratio; None takes the value bond-based PMB fixes: 1/3 in plane stress,
        1/4 in plane strain and 3-D.
    rho : float
        Density, kg/m^3.
    plane : {"stress", "strain", "3d"}
        Plane stress and plane strain share the shear modulus mu = E / (2 (1 + nu)).
        The in-plane equations of plane stress are those of plane strain with
        nu* = nu / (1 + nu) (same mu; c_s / c_p = sqrt((1 - nu) / 2)), so the plane
        stress value uses nu* in the formula below. Plane strain and 3-D use nu.
    method : {"viktorov", "exact"}
        "viktorov": c_R = c_s (0.862 + 1.14 nu) / (1 + nu), c_s = sqrt(mu / rho)
        (Viktorov (1967); below the exact root by less than 0.3 % for
        0.2 <= nu < 0.5, by 1.4 % at nu = 0).
        "exact": the root in (0, c_s) of the Rayleigh equation
        (2 - eta^2)^2 = 4 sqrt(1 - k^2 eta^2) sqrt(1 - eta^2), eta = c / c_s,
        k = c_s / c_p (Achenbach (1973)).

    Returns
    -------
    float
        c_R, m/s. For the PMB model in plane stress (nu = 1/3, nu* = 1/4):
        0.9176 c_s (Viktorov), 0.9194 c_s (exact).
    """
    if plane not in ("stress", "strain", "3d"):
        raise ValueError(f"plane must be 'stress', 'strain' or '3d', got {plane!r}")
    if nu is None:
        nu = 1.0 / 3.0 if plane == "stress" else 0.25
    if not (E > 0.0 and rho > 0.0 and -1.0 < nu < 0.5):
        raise ValueError("need E > 0, rho > 0 and -1 < nu < 0.5")
    mu = E / (2.0 * (1.0 + nu))
    c_s = math.sqrt(mu / rho)
    nv = nu / (1.0 + nu) if plane == "stress" else nu
    if method == "viktorov":
        return c_s * (0.862 + 1.14 * nv) / (1.0 + nv)
    if method != "exact":
        raise ValueError(f"method must be 'viktorov' or 'exact', got {method!r}")
    k2 = (1.0 - 2.0 * nv) / (2.0 * (1.0 - nv))
    # eta^6 - 8 eta^4 + (24 - 16 k^2) eta^2 - 16 (1 - k^2) = 0, a cubic in eta^2
    roots = np.roots([1.0, -8.0, 24.0 - 16.0 * k2, -16.0 * (1.0 - k2)])
    real = roots[(np.abs(roots.imag) < 1e-10) & (roots.real > 0.0) & (roots.real < 1.0)]
    return c_s * math.sqrt(float(real.real.min()))
