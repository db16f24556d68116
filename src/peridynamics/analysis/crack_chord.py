"""The direction in which a crack leaves a point (a re-entrant corner, a notch tip):
the chord from that point to the first vertex of the crack's path at least a given
distance from it (used by ``examples/micropolar/make_figures.py`` for the L-shaped
panel and by the verify case ``micropolar_l_panel``).

Unlike :meth:`peridynamics.analysis.crack_polyline.CrackPath.angle_over`, which goes
a given arc length along the path, the reach here is the straight distance from the
origin, so a path that wanders near the corner does not shorten the chord.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["chord_angle_from"]


def chord_angle_from(
    vertices: ArrayLike, origin: ArrayLike, reach: float, heading: ArrayLike = (1.0, 0.0)
) -> float:
    """Angle (deg) of the chord from ``origin`` to the first path vertex at least
    ``reach`` from it, counter-clockwise from ``heading`` for a heading along +x,
    mirrored for a heading along -x (upward from the horizontal, the crack heading
    left: ``heading=(-1, 0)``).

    Parameters
    ----------
    vertices : array_like, shape (n, 2)
        The crack path's vertices in order from its start, m.
    origin : array_like, shape (2,)
        Where the chord starts, m.
    reach : float
        Least distance of the chord's end from ``origin``, m (> 0).
    heading : array_like, shape (2,)
        The direction the angle is measured from: (1, 0) or (-1, 0).

    Returns
    -------
    float
        The angle, deg; NaN when no vertex is that far.
    """
    if not reach > 0.0:
        raise ValueError(f"reach must be positive, got {reach!r}")
    v = np.asarray(vertices, dtype=float).reshape(-1, 2)
    o = np.asarray(origin, dtype=float)
    h = np.asarray(heading, dtype=float)
    if h.shape != (2,) or abs(abs(h[0]) - 1.0) > 1e-12 or h[1] != 0.0:
        raise ValueError(f"heading must be (1, 0) or (-1, 0), got {h.tolist()}")
    far = np.flatnonzero(np.linalg.norm(v - o, axis=1) >= reach)
    if not len(far):
        return math.nan
    dx, dy = v[far[0]] - o
    return float(np.degrees(np.arctan2(dy, h[0] * dx)))
