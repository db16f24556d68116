"""Pre-cracks: cut every bond whose segment crosses a crack.

2-D cracks are segments ``(p, q)``; 3-D cracks are planar rectangles given by a
corner ``p0`` and the two edge vectors ``a`` and ``b`` (corners p0, p0+a, p0+b, p0+a+b).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray


@dataclass(frozen=True)
class SegmentCrack:
    """2-D crack from ``start`` to ``end`` (m)."""

    start: tuple[float, float]
    end: tuple[float, float]

    def crosses(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whether the bond segments a->b (shape (n, 2) each) cross the crack.

        Touching counts as crossing (a bond through a crack tip is cut).
        """
        p = np.asarray(self.start, dtype=float)
        q = np.asarray(self.end, dtype=float)
        r = q - p
        s = b - a

        def cross(u: NDArray, v: NDArray) -> NDArray:
            return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

        denom = cross(np.broadcast_to(r, s.shape), s)
        ap = a - p
        with np.errstate(divide="ignore", invalid="ignore"):
            t = cross(ap, s) / denom  # position along the crack
            w = cross(ap, np.broadcast_to(r, s.shape)) / denom  # position along the bond
        eps = 1e-12
        hit = (np.abs(denom) > 0) & (t >= -eps) & (t <= 1 + eps) & (w >= -eps) & (w <= 1 + eps)
        return hit


@dataclass(frozen=True)
class RectangleCrack:
    """3-D planar crack: corner ``origin`` and edge vectors ``edge_a``, ``edge_b`` (m)."""

    origin: tuple[float, float, float]
    edge_a: tuple[float, float, float]
    edge_b: tuple[float, float, float]

    def crosses(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whether bond segments a->b (shape (n, 3)) pierce the rectangle."""
        p0 = np.asarray(self.origin, dtype=float)
        ea = np.asarray(self.edge_a, dtype=float)
        eb = np.asarray(self.edge_b, dtype=float)
        nrm = np.cross(ea, eb)
        da = (a - p0) @ nrm
        db = (b - p0) @ nrm
        opposite = (da * db <= 0) & (da != db)
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = np.where(opposite, da / np.where(opposite, da - db, 1.0), 0.0)
        hit_pt = a + lam[:, None] * (b - a)
        rel = hit_pt - p0
        # coordinates in the (ea, eb) basis via the 2x2 Gram system
        g = np.array([[ea @ ea, ea @ eb], [ea @ eb, eb @ eb]])
        rhs = np.column_stack([rel @ ea, rel @ eb])
        coef = np.linalg.solve(g, rhs.T).T
        eps = 1e-12
        inside = np.all((coef >= -eps) & (coef <= 1 + eps), axis=1)
        return opposite & inside


Crack = SegmentCrack | RectangleCrack


def make_crack(points: Sequence[ArrayLike]) -> Crack:
    """Build a crack from 2 points (2-D segment) or 3 points (3-D rectangle p0, p1, p2).

    For three points the rectangle has edges p1 - p0 and p2 - p0, which must be
    perpendicular.
    """
    pts = [np.asarray(p, dtype=float) for p in points]
    if len(pts) == 2 and all(p.shape == (2,) for p in pts):
        if not np.linalg.norm(pts[1] - pts[0]) > 0:
            raise ValueError("a 2-D crack needs two different end points (zero length)")
        return SegmentCrack(tuple(pts[0]), tuple(pts[1]))  # type: ignore[arg-type]
    if len(pts) == 3 and all(p.shape == (3,) for p in pts):
        ea, eb = pts[1] - pts[0], pts[2] - pts[0]
        if not (np.linalg.norm(ea) > 0 and np.linalg.norm(eb) > 0):
            raise ValueError("a 3-D crack needs two edges of non-zero length (zero area)")
        if abs(ea @ eb) > 1e-9 * np.linalg.norm(ea) * np.linalg.norm(eb):
            raise ValueError("rectangle crack edges p1 - p0 and p2 - p0 must be perpendicular")
        return RectangleCrack(tuple(pts[0]), tuple(ea), tuple(eb))  # type: ignore[arg-type]
    raise ValueError("a crack is 2 points of 2 coordinates (2-D) or 3 points of 3 (3-D)")


#: bonds per range of the bounding-box test of :func:`crossing_bonds` (bounded memory)
CHUNK_BONDS = 1 << 21


def crossing_bonds(
    x: NDArray[np.float64], bond_i: NDArray, bond_j: NDArray, cracks: Sequence[Crack]
) -> NDArray[np.bool_]:
    """Mask of bonds (n_bonds,) that cross any crack. Only bonds near a crack are tested.

    The bounding-box test runs over ranges of :data:`CHUNK_BONDS` bonds (its transients
    stay bounded); the bonds near a crack are then tested in one call, as before."""
    cut = np.zeros(len(bond_i), dtype=bool)
    for crack in cracks:  # a handful of cracks, each vectorised over bonds
        if isinstance(crack, SegmentCrack):
            corners = np.array([crack.start, crack.end])
        else:
            p0, ea, eb = (np.asarray(v) for v in (crack.origin, crack.edge_a, crack.edge_b))
            corners = np.array([p0, p0 + ea, p0 + eb, p0 + ea + eb])
        lo, hi = corners.min(axis=0), corners.max(axis=0)
        idx = np.concatenate(
            [_near_box(x, bond_i, bond_j, lo, hi, s) for s in range(0, len(bond_i), CHUNK_BONDS)]
            or [np.zeros(0, dtype=np.intp)]
        )
        if idx.size:
            cut[idx[crack.crosses(x[bond_i[idx]], x[bond_j[idx]])]] = True
    return cut


def _near_box(
    x: NDArray[np.float64],
    bond_i: NDArray,
    bond_j: NDArray,
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    start: int,
) -> NDArray[np.intp]:
    """Indices of the bonds ``start:start + CHUNK_BONDS`` whose segment's bounding box
    meets the box ``[lo, hi]`` (widened by 1e-12 m)."""
    stop = min(start + CHUNK_BONDS, len(bond_i))
    a, b = x[bond_i[start:stop]], x[bond_j[start:stop]]
    near = np.all((np.maximum(a, b) >= lo - 1e-12) & (np.minimum(a, b) <= hi + 1e-12), axis=1)
    return np.flatnonzero(near) + start
