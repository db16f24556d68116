"""Crack initiation at flaw tips and coalescence between flaws, from damage fields
(SED-PD (2021): wing cracks, coalescence of two flaws). 2-D.

All functions take point coordinates ``x`` (n, 2), the damage ``phi`` (n,) of a state
and the damage ``phi0`` (n,) at t = 0 (what the flaws themselves cause), and look at the
*new* damage phi - phi0.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

F = NDArray[np.float64]


def initiation_direction(
    x: ArrayLike,
    phi: ArrayLike,
    phi0: ArrayLike,
    tip: ArrayLike,
    radius: float,
    threshold: float = 0.2,
    min_points: int = 3,
) -> float | None:
    """Direction (degrees, counter-clockwise from +x, in (-180, 180]) of the new damage
    within ``radius`` of a flaw ``tip``: the mean of the unit vectors from the tip to
    the points whose damage rose by at least ``threshold``, weighted by that rise.

    Returns None when fewer than ``min_points`` points qualify (no crack there yet).
    """
    x, phi, phi0 = (np.asarray(a, dtype=float) for a in (x, phi, phi0))
    rel = x - np.asarray(tip, dtype=float)
    r = np.linalg.norm(rel, axis=1)
    rise = phi - phi0
    sel = (r <= radius) & (r > 0) & (rise >= threshold)
    if np.count_nonzero(sel) < min_points:
        return None
    mean = np.sum(rise[sel, None] * rel[sel] / r[sel, None], axis=0)
    if not np.any(mean):
        return None
    return float(np.degrees(np.arctan2(mean[1], mean[0])))


def angle_between_lines(a_deg: float, b_deg: float) -> float:
    """Smallest angle (degrees, 0-90) between two undirected lines."""
    d = abs((a_deg - b_deg) % 180.0)
    return float(min(d, 180.0 - d))


def bridges(
    x: ArrayLike,
    phi: ArrayLike,
    phi0: ArrayLike,
    near_a: ArrayLike,
    near_b: ArrayLike,
    spacing: float,
    threshold: float = 0.3,
) -> int:
    """Number of separate linkages between two flaws.

    A linkage is a cluster of newly damaged points (rise >= ``threshold``; neighbours
    within 1.5 spacings) *outside* both flaw zones ``near_a`` and ``near_b`` ((n,) bool
    masks of the points around each flaw) that comes within 1.5 spacings of both zones.
    Damage along the flaws themselves is left out, so two cracks that link the flaws at
    different places count as two even though both end on the same flaws. 0 before
    coalescence, 1 after the first linkage, 2 when a second, independent one forms.
    """
    x, phi, phi0 = (np.asarray(a, dtype=float) for a in (x, phi, phi0))
    near_a, near_b = np.asarray(near_a, bool), np.asarray(near_b, bool)
    new = np.flatnonzero(((phi - phi0) >= threshold) & ~near_a & ~near_b)
    if new.size == 0 or not near_a.any() or not near_b.any():
        return 0
    reach = 1.5 * spacing
    pairs = cKDTree(x[new]).query_pairs(reach, output_type="ndarray")
    n = new.size
    graph = coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])) if len(pairs) else ([], ([], [])),
        shape=(n, n),
    )
    _, labels = connected_components(graph, directed=False)
    d_a, _ = cKDTree(x[near_a]).query(x[new], distance_upper_bound=reach * 1.0001)
    d_b, _ = cKDTree(x[near_b]).query(x[new], distance_upper_bound=reach * 1.0001)
    touch_a = np.unique(labels[np.isfinite(d_a)])
    touch_b = np.unique(labels[np.isfinite(d_b)])
    return int(np.intersect1d(touch_a, touch_b).size)
