"""The polyline of one crack (:class:`CrackPath`) and the polyline geometry it uses:
arc lengths, points at an arc length and the angles of chords from a reference
direction. The extraction itself is :mod:`peridynamics.analysis.crack_path`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "CrackPath",
    "arc_lengths",
    "chord_angles",
    "point_at_arc",
    "polyline_angles",
    "unit_direction",
]


@dataclass(frozen=True)
class CrackPath:
    """One crack extracted from a damage field.

    Attributes
    ----------
    vertices : ndarray, shape (k, dim)
        Polyline of the main branch (the one reaching farthest from the seed along the
        cluster; the longest, up to the grid-scale difference of path and reach) from
        the seed to the tip, m. ``k >= 1``;
        an empty crack has the seed (or the seed region's centroid) as its only vertex.
    length : float
        Length of the polyline, m.
    initial_angle_deg : float
        Angle of the initial segment, degrees: the chord from the first vertex to the
        point of the polyline at arc length ``initial_length`` (clipped to ``length``),
        measured from ``reference_direction``. In 2-D it is signed, counter-clockwise
        positive, in (-180, 180]; in 3-D it is the unsigned angle in [0, 180]. NaN for
        an empty crack.
    angles_deg : ndarray, shape (k,)
        Direction of the path at each vertex from ``reference_direction``, degrees (same
        convention as ``initial_angle_deg``): the chord between the points of the
        polyline at arc lengths s - w/2 and s + w/2 (clipped to the ends), w the
        ``angle_window`` of :func:`extract_crack_path`. The raw angles of the segments,
        noisier by the grid-scale jitter of the vertices, are
        ``polyline_angles(vertices, reference_direction)``.
    arc_length : ndarray, shape (k,)
        Cumulative length along the polyline at each vertex, m (0 at the seed).
    tip : ndarray, shape (dim,)
        Last vertex: the point of the cluster farthest from the seed along the cluster, m.
    tip_index : int
        Index of the tip in the input point arrays; -1 for an empty crack.
    points : ndarray of int, shape (m,)
        Indices (into the input arrays) of the damaged points of the crack's cluster.
    geodesic : ndarray, shape (m,)
        Distance from the seed along the cluster of each of ``points``, m.
    initial_length : float
        Arc length the initial angle was measured over, m.
    reference_direction : ndarray, shape (dim,)
        Unit vector the angles are measured from.
    branches : tuple of ndarray, each shape (k_b, dim)
        Polylines of every branch kept, each from the seed to its own tip, m; the first
        is ``vertices``. Side branches are listed by decreasing length.
    branch_lengths : ndarray, shape (n_branches,)
        Length of each polyline of ``branches``, m.
    """

    vertices: NDArray[np.float64]
    length: float
    initial_angle_deg: float
    angles_deg: NDArray[np.float64]
    arc_length: NDArray[np.float64]
    tip: NDArray[np.float64]
    tip_index: int
    points: NDArray[np.intp]
    geodesic: NDArray[np.float64]
    initial_length: float
    reference_direction: NDArray[np.float64]
    branches: tuple[NDArray[np.float64], ...] = field(default_factory=tuple)
    branch_lengths: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))

    @property
    def n_branches(self) -> int:
        """Number of branches kept (0 for an empty crack, 1 for an unbranched one)."""
        return len(self.branches)

    @property
    def empty(self) -> bool:
        """True when no damaged point is connected to the seed."""
        return self.tip_index < 0

    def point_at(self, s: float) -> NDArray[np.float64]:
        """Point of the main polyline at arc length ``s`` (m, clipped to [0, length]).

        Returns
        -------
        ndarray, shape (dim,)
            Position, m.
        """
        return point_at_arc(self.vertices, self.arc_length, s)

    def angle_over(self, s: float) -> float:
        """Angle (degrees) of the chord from the first vertex to the point at arc length
        ``s`` (m), from ``reference_direction``; NaN for an empty crack."""
        if self.length <= 0.0:
            return math.nan
        return float(
            chord_angles(
                (self.point_at(s) - self.vertices[0])[None, :],
                self.reference_direction,
            )[0]
        )


def unit_direction(v: ArrayLike, dim: int) -> NDArray[np.float64]:
    """``v`` (dim,) normalised; ValueError for a wrong length, zero or non-finite."""
    a = np.asarray(v, dtype=np.float64).reshape(-1)
    if a.shape != (dim,):
        raise ValueError(f"reference_direction needs {dim} components, got {a.shape[0]}")
    n = float(np.linalg.norm(a))
    if n == 0.0 or not math.isfinite(n):
        raise ValueError("reference_direction must be non-zero and finite")
    return a / n


def chord_angles(seg: NDArray[np.float64], ref: NDArray[np.float64]) -> NDArray[np.float64]:
    """Angle (degrees) of each row of ``seg`` (j, dim) from the unit vector ``ref``."""
    if seg.shape[0] == 0:
        return np.zeros(0)
    dot = seg @ ref
    if seg.shape[1] == 2:
        cross = ref[0] * seg[:, 1] - ref[1] * seg[:, 0]
        return np.degrees(np.arctan2(cross, dot))
    norm = np.linalg.norm(seg, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.clip(dot / norm, -1.0, 1.0)
    return np.degrees(np.arccos(c))


def polyline_angles(
    vertices: ArrayLike, reference_direction: ArrayLike | None = None
) -> NDArray[np.float64]:
    """Angle of each segment of a polyline from a reference direction.

    Parameters
    ----------
    vertices : array_like, shape (k, dim)
        Polyline vertices, m.
    reference_direction : array_like, shape (dim,), optional
        Direction the angles are measured from (normalised here); default +x.

    Returns
    -------
    ndarray, shape (k - 1,)
        Degrees; signed (counter-clockwise positive) in 2-D, unsigned in 3-D.
    """
    v = np.asarray(vertices, dtype=np.float64)
    dim = v.shape[1]
    ref = unit_direction(
        np.eye(dim)[0] if reference_direction is None else reference_direction, dim
    )
    return chord_angles(np.diff(v, axis=0), ref)


def arc_lengths(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Cumulative length (k,) along the polyline ``v`` (k, dim) at each vertex, 0 first."""
    seg = np.linalg.norm(np.diff(v, axis=0), axis=1)
    return np.concatenate([[0.0], np.cumsum(seg)])


def point_at_arc(v: NDArray[np.float64], arc: NDArray[np.float64], s: float) -> NDArray[np.float64]:
    """Point of the polyline ``v`` with arc lengths ``arc`` at arc length ``s`` (clipped)."""
    if v.shape[0] == 1:
        return v[0].copy()
    s = min(max(float(s), 0.0), float(arc[-1]))
    return np.array([np.interp(s, arc, v[:, j]) for j in range(v.shape[1])])
