"""Crack post-processing: crack-tip position and speed, branch counting."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def crack_tip(
    x: NDArray,
    damage: NDArray,
    origin: NDArray,
    direction: NDArray | None,
    threshold: float,
    ignore: NDArray | None = None,
) -> float:
    """Distance (m) from ``origin`` of the damaged point farthest along ``direction``.

    With ``direction=None`` the Euclidean distance is used. Points flagged in ``ignore``
    (n,) bool -- e.g. those already damaged by a pre-crack at t = 0 -- do not count.
    Returns 0 if no other point has ``damage >= threshold``.
    """
    hit = damage >= threshold
    if ignore is not None:
        hit &= ~ignore
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
    a: NDArray, b: NDArray, damage: NDArray, column: float, spacing: float, threshold: float
) -> int:
    """Number of separate damaged bands crossing the line ``a = column`` (2-D).

    ``a`` and ``b`` (n,) are point coordinates along and across the crack direction.
    Points within half a spacing of the line with ``damage >= threshold`` are sorted by
    ``b``; a gap of more than 2.5 spacings starts a new band.
    """
    on = (np.abs(a - column) <= 0.5 * spacing + 1e-12) & (damage >= threshold)
    if not np.any(on):
        return 0
    across = np.sort(b[on])
    return int(1 + np.sum(np.diff(across) > 2.5 * spacing))


def branching(
    x: NDArray,
    damage: NDArray,
    spacing: float,
    threshold: float,
    origin: NDArray,
    direction: NDArray | None = None,
) -> tuple[int, float | None]:
    """Largest number of damaged bands crossing lines normal to ``direction`` ahead of
    ``origin`` (2-D), and the distance (m) from the origin of the first line crossed by
    two or more bands (None if the crack never splits). ``direction`` defaults to +x.
    """
    d = np.array([1.0, 0.0]) if direction is None else np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    rel = x[:, :2] - np.asarray(origin, dtype=float)[:2]
    a = rel[:, 0] * d[0] + rel[:, 1] * d[1]  # no BLAS: see Evaluator.strain_energy
    b = -rel[:, 0] * d[1] + rel[:, 1] * d[0]
    ahead = a >= -1e-12
    if not np.any(ahead):
        return 0, None
    columns = np.arange(0.0, float(a[ahead].max()) + spacing, spacing)
    best, first = 0, None
    for col in columns:  # over lines across the crack path (a few hundred)
        k = count_branches(a, b, damage, float(col), spacing, threshold)
        best = max(best, k)
        if k >= 2 and first is None:
            first = float(col)
    return best, first
