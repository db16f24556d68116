"""Share the broken-bond crack length (area) of
:class:`peridynamics.analysis.crack_length.CrackMeter` among tracked cracks: each bond
goes to the crack whose polylines pass nearest its midpoint, within a radius.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["attribute_to_polylines"]


def _segment_distance(p: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distance (m) of points ``p`` (k, dim) from the polyline ``v`` (q, dim), shape (k,)."""
    if v.shape[0] == 1:
        return np.sqrt(np.einsum("ij,ij->i", p - v[0], p - v[0]))
    best = np.full(p.shape[0], np.inf)
    for a, b in zip(v[:-1], v[1:], strict=True):  # over the polyline's segments
        d = b - a
        dd = float(d @ d)
        t = np.clip(((p - a) @ d) / dd, 0.0, 1.0) if dd > 0 else np.zeros(p.shape[0])
        r = p - (a + t[:, None] * d)
        np.minimum(best, np.einsum("ij,ij->i", r, r), out=best)
    return np.sqrt(best)


def attribute_to_polylines(
    points: ArrayLike,
    weights: ArrayLike,
    cracks: Mapping[str, Sequence[ArrayLike]],
    radius: float,
) -> tuple[dict[str, float], float]:
    """Share broken-bond crack among tracked cracks: each bond goes to the crack whose
    polylines pass nearest its midpoint, if within ``radius``.

    Parameters
    ----------
    points : array_like, shape (k, dim)
        Bond midpoints (m), e.g. :meth:`CrackMeter.midpoints`.
    weights : array_like, shape (k,)
        Crack length (m) or area (m^2) of each bond (:meth:`CrackMeter.weights`).
    cracks : mapping of str to sequence of array_like, each shape (q, dim)
        Polylines of each crack (m): the main path and its branches.
    radius : float
        Largest distance from a crack (m); farther bonds are unattributed. Two horizons
        cover the band of broken bonds around a crack (one horizon each side).

    Returns
    -------
    per_crack : dict of str to float
        Crack length (area) attributed to each crack.
    unattributed : float
        The rest: bonds farther than ``radius`` from every crack.
    """
    p = np.asarray(points, dtype=np.float64)
    w = np.asarray(weights, dtype=np.float64)
    names = list(cracks)
    dist = np.full((len(names), p.shape[0]), np.inf)
    for k, name in enumerate(names):  # over tracked cracks (a handful)
        for line in cracks[name]:  # over their branches
            v = np.asarray(line, dtype=np.float64).reshape(-1, p.shape[1] if p.size else 1)
            if v.shape[0] and p.shape[0]:
                np.minimum(dist[k], _segment_distance(p, v), out=dist[k])
    if not names:
        return {}, float(w.sum())
    nearest = np.argmin(dist, axis=0) if p.shape[0] else np.zeros(0, dtype=np.intp)
    near = dist[nearest, np.arange(p.shape[0])] <= radius
    share = np.bincount(nearest[near], weights=w[near], minlength=len(names))
    return {n: float(share[k]) for k, n in enumerate(names)}, float(w[~near].sum())
