"""Crack post-processing: crack-tip position and speed, branch counting."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def crack_tip(
    x: NDArray, damage: NDArray, origin: NDArray, direction: NDArray | None, threshold: float
) -> float:
    """Distance (m) from ``origin`` of the damaged point farthest along ``direction``.

    With ``direction=None`` the Euclidean distance is used. Returns 0 if no point has
    ``damage >= threshold``.
    """
    hit = damage >= threshold
    if not np.any(hit):
        return 0.0
    d = x[hit] - origin
    if direction is None:
        return float(np.sqrt(np.max(np.sum(d * d, axis=1))))
    n = direction / np.linalg.norm(direction)
    return float(max(0.0, np.max(np.sum(d * n, axis=1))))  # no BLAS in the time loop


def tip_speed(times: NDArray, positions: NDArray, window: int = 3) -> NDArray:
    """Crack-tip speed (m/s) from a position history by a centred finite difference
    over ``window`` records on each side (a short smoothing of grid-induced jumps)."""
    t = np.asarray(times, dtype=float)
    p = np.asarray(positions, dtype=float)
    n = len(t)
    v = np.zeros(n)
    for k in range(n):  # over history records, not points or bonds
        a, b = max(0, k - window), min(n - 1, k + window)
        if t[b] > t[a]:
            v[k] = (p[b] - p[a]) / (t[b] - t[a])
    return v


def count_branches(
    x: NDArray, damage: NDArray, column_x: float, spacing: float, threshold: float
) -> int:
    """Number of separate damaged bands crossing the line x = column_x (2-D).

    Points within half a spacing of the line with ``damage >= threshold`` are sorted by
    y; a gap of more than 2.5 spacings starts a new band.
    """
    on = (np.abs(x[:, 0] - column_x) <= 0.5 * spacing + 1e-12) & (damage >= threshold)
    if not np.any(on):
        return 0
    y = np.sort(x[on, 1])
    return int(1 + np.sum(np.diff(y) > 2.5 * spacing))


def branching(
    x: NDArray, damage: NDArray, spacing: float, threshold: float, x_from: float
) -> tuple[int, float | None]:
    """Largest number of damaged bands over the columns x >= ``x_from`` and the first
    column (m) where two or more bands cross (None if the crack never splits)."""
    cols = np.unique(np.round(x[x[:, 0] >= x_from, 0] / spacing * 2) / 2 * spacing)
    best, first = 0, None
    for cx in cols:  # over grid columns (a few hundred), vectorised inside
        k = count_branches(x, damage, float(cx), spacing, threshold)
        best = max(best, k)
        if k >= 2 and first is None:
            first = float(cx)
    return best, first
