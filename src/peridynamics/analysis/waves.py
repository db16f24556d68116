"""Wave-propagation post-processing: exact d'Alembert pulses, error measures against
them, the dominant period of a history and its energy spectral density (PD wave
dispersion (n.d.), sections 4.1.1-4.1.2)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

F = NDArray[np.float64]


def dalembert(
    x: ArrayLike, t: float, source: Callable[[float], float], speed: float, x0: float = 0.0
) -> F:
    """u(x, t) = u_in(t - (x - x0) / c): a wave entering a semi-infinite bar at x0 and
    moving right at speed c without reflection (valid before it reaches the far end)."""
    xs = np.asarray(x, dtype=float)
    return np.array([source(t - (xi - x0) / speed) for xi in xs.ravel()]).reshape(xs.shape)


def wave_errors(
    x: ArrayLike, u: ArrayLike, exact: ArrayLike, amplitude: float, behind: float
) -> dict[str, float]:
    """Error measures of a numerical wave profile against the exact one.

    Returns ``l2_error_vs_exact`` = ||u - u_exact||_2 / ||u_exact||_2,
    ``trailing_oscillation`` = max |u - u_exact| over x < ``behind`` (the part of the bar
    the exact pulse has already left, where it is 0) divided by ``amplitude``, and
    ``peak_ratio`` = max |u| / max |u_exact|.
    """
    x, u, ue = (np.asarray(a, dtype=float) for a in (x, u, exact))
    if not amplitude > 0:
        raise ValueError("amplitude must be > 0")
    norm = float(np.linalg.norm(ue))
    if norm == 0:
        raise ValueError("the exact profile is zero everywhere: nothing to compare with")
    err = np.abs(u - ue)
    tail = x < behind
    return {
        "l2_error_vs_exact": float(np.linalg.norm(u - ue)) / norm,
        "trailing_oscillation": float(err[tail].max() / amplitude) if tail.any() else 0.0,
        "peak_ratio": float(np.abs(u).max() / np.abs(ue).max()),
    }


def pulse_comparison(
    x: ArrayLike,
    u: ArrayLike,
    t: float,
    shape: str,
    amplitude: float,
    duration: float,
    speed: float,
    source_position: float = 0.0,
    tail_margin: float = 0.0,
) -> tuple[F, dict[str, float]]:
    """The exact profile of a ``sine`` or ``square`` input pulse (amplitude x the
    ``sine_pulse`` / ``square_pulse`` time function) entering at ``source_position`` at
    ``speed``, and :func:`wave_errors` of ``u`` against it with the trailing region
    ending ``tail_margin`` behind the exact pulse's tail. Returns (exact, errors)."""
    from peridynamics.loading.time_functions import SinePulse, SquarePulse

    if shape not in ("sine", "square"):
        raise ValueError(f"shape must be 'sine' or 'square', got {shape!r}")
    f = SinePulse(duration) if shape == "sine" else SquarePulse(duration)
    exact = dalembert(x, t, lambda s: amplitude * f(s), speed, source_position)
    behind = source_position + speed * (t - duration) - tail_margin
    return exact, wave_errors(x, u, exact, amplitude, behind)


def dominant_period(t: ArrayLike, y: ArrayLike, min_period: float = 0.0) -> float:
    """Dominant period (s) of a uniformly sampled history from its autocorrelation: the
    lag of the highest autocorrelation peak after the first zero crossing (and after
    ``min_period``), refined by a parabola through the three samples around it."""
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    if len(t) < 8 or len(t) != len(y):
        raise ValueError("need at least 8 samples of t and y of equal length")
    dt = float(np.mean(np.diff(t)))
    if not np.allclose(np.diff(t), dt, rtol=1e-6, atol=0):
        raise ValueError("the history must be uniformly sampled")
    z = y - y.mean()
    n = len(z)
    spec = np.fft.rfft(z, 2 * n)
    ac = np.fft.irfft(spec * np.conj(spec))[:n]
    if ac[0] <= 0:
        raise ValueError("the history is constant: no period")
    ac /= ac[0]
    neg = np.flatnonzero(ac < 0)
    if neg.size == 0:
        raise ValueError("the autocorrelation never changes sign: no period in the record")
    start = max(int(neg[0]), int(np.ceil(min_period / dt)))
    if start >= n - 2:
        raise ValueError("the record is too short to contain one period")
    k = start + int(np.argmax(ac[start : n - 1]))
    a, b, c = ac[k - 1], ac[k], ac[k + 1]
    den = a - 2 * b + c
    shift = 0.5 * (a - c) / den if den != 0 else 0.0
    return (k + shift) * dt


def energy_spectral_density(t: ArrayLike, y: ArrayLike) -> tuple[F, F]:
    """(f (Hz), |Y(f)|^2 dt^2) of a uniformly sampled history: the energy spectral density
    of PD wave dispersion (n.d.), Figs 15-19 (one-sided, unnormalised by the record length)."""
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    dt = float(np.mean(np.diff(t)))
    spec = np.fft.rfft(y) * dt
    freq = np.asarray(np.fft.rfftfreq(len(y), dt), dtype=np.float64)
    return freq, np.asarray(np.abs(spec) ** 2, dtype=np.float64)
