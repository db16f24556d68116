"""Vectorised geometric predicates ("regions") used to build node sets.

A :class:`Region` maps reference positions x, shape (n_points, dim), to a boolean
mask, shape (n_points,). Regions combine with ``&`` (intersection),
``|`` (union) and ``~`` (complement)::

    top = Box(lo=[-inf, 0.039], hi=[inf, inf])
    hole = Circle(center=[0.05, 0.02], radius=0.005)
    ring = Circle([0.05, 0.02], 0.01) & ~hole
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

BoolArray = NDArray[np.bool_]


class Region(ABC):
    """Base class: a predicate over reference positions.

    ``pointwise`` says whether a point's membership depends on its own position only
    (True for the geometric shapes); a region that looks at the other points (the
    outermost layer, the nearest point, a list of indices) sets it False, and
    :func:`is_pointwise` tells whether a combination is.
    """

    pointwise: bool = True

    @abstractmethod
    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        """Return the boolean mask, shape ``(n_points,)``, of points inside."""

    def __call__(self, x: NDArray[np.float64]) -> BoolArray:
        x = np.asarray(x, dtype=np.float64)
        if x.ndim == 1:
            x = x[:, None]
        return self.mask(x)

    def __and__(self, other: Region) -> Region:
        return _Combined("and", (self, other))

    def __or__(self, other: Region) -> Region:
        return _Combined("or", (self, other))

    def __invert__(self) -> Region:
        return _Not(self)


@dataclass(frozen=True)
class _Combined(Region):
    op: str
    parts: tuple[Region, ...]

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        masks = [p(x) for p in self.parts]
        out = masks[0].copy()
        for m in masks[1:]:
            out = (out & m) if self.op == "and" else (out | m)
        return out


@dataclass(frozen=True)
class _Not(Region):
    part: Region

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        return ~self.part(x)


class Everywhere(Region):
    """Every point."""

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        return np.ones(len(x), dtype=bool)


def _vec(v: ArrayLike, dim: int | None = None) -> NDArray[np.float64]:
    arr = np.atleast_1d(np.asarray(v, dtype=np.float64))
    if dim is not None and arr.shape != (dim,):
        raise ValueError(f"expected a vector of length {dim}, got shape {arr.shape}")
    return arr


@dataclass(frozen=True, init=False)
class Box(Region):
    """Axis-aligned box ``lo <= x <= hi`` (inclusive, with a tolerance ``tol`` in m).

    ``lo``/``hi`` may contain ``-inf``/``inf`` for half-open slabs.
    """

    lo: tuple[float, ...]
    hi: tuple[float, ...]
    tol: float

    def __init__(self, lo: ArrayLike, hi: ArrayLike, tol: float = 1e-12) -> None:
        lo_a, hi_a = _vec(lo), _vec(hi)
        if lo_a.shape != hi_a.shape:
            raise ValueError("Box: lo and hi must have the same length")
        if np.any(lo_a > hi_a):
            raise ValueError(f"Box: lo {lo_a.tolist()} must be <= hi {hi_a.tolist()}")
        object.__setattr__(self, "lo", tuple(lo_a.tolist()))
        object.__setattr__(self, "hi", tuple(hi_a.tolist()))
        object.__setattr__(self, "tol", float(tol))

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        lo, hi = np.asarray(self.lo), np.asarray(self.hi)
        if len(lo) != x.shape[1]:
            raise ValueError(f"Box has {len(lo)} components but points are {x.shape[1]}-D")
        return np.all((x >= lo - self.tol) & (x <= hi + self.tol), axis=1)


@dataclass(frozen=True, init=False)
class Ball(Region):
    """Points within ``radius`` of ``center`` (a disc in 2-D, a sphere in 3-D)."""

    center: tuple[float, ...]
    radius: float

    def __init__(self, center: ArrayLike, radius: float) -> None:
        if radius <= 0:
            raise ValueError("radius must be > 0")
        object.__setattr__(self, "center", tuple(_vec(center).tolist()))
        object.__setattr__(self, "radius", float(radius))

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        c = np.asarray(self.center)
        if len(c) != x.shape[1]:
            raise ValueError(f"center has {len(c)} components but points are {x.shape[1]}-D")
        return np.sum((x - c) ** 2, axis=1) <= self.radius**2 * (1 + 1e-12)


Circle = Ball
Sphere = Ball


@dataclass(frozen=True, init=False)
class CylinderRegion(Region):
    """Finite 3-D cylinder: axis from ``base`` along unit ``axis`` over ``length``."""

    base: tuple[float, float, float]
    axis: tuple[float, float, float]
    radius: float
    length: float

    def __init__(self, base: ArrayLike, axis: ArrayLike, radius: float, length: float) -> None:
        a = _vec(axis, 3)
        norm = float(np.linalg.norm(a))
        if norm == 0 or radius <= 0 or length <= 0:
            raise ValueError("cylinder needs a non-zero axis, radius > 0 and length > 0")
        object.__setattr__(self, "base", tuple(_vec(base, 3).tolist()))
        object.__setattr__(self, "axis", tuple((a / norm).tolist()))
        object.__setattr__(self, "radius", float(radius))
        object.__setattr__(self, "length", float(length))

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        d = x - np.asarray(self.base)
        s = d @ np.asarray(self.axis)
        r2 = np.sum(d**2, axis=1) - s**2
        tol = 1e-12 * max(self.length, self.radius)
        return (s >= -tol) & (s <= self.length + tol) & (r2 <= self.radius**2 * (1 + 1e-12))


@dataclass(frozen=True, init=False)
class Polygon(Region):
    """Closed 2-D polygon (vertices in order, either orientation); even-odd rule."""

    vertices: tuple[tuple[float, float], ...]

    def __init__(self, vertices: Sequence[Sequence[float]]) -> None:
        v = np.asarray(vertices, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3:
            raise ValueError("polygon needs at least 3 vertices of 2 coordinates")
        object.__setattr__(self, "vertices", tuple(map(tuple, v.tolist())))

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        if x.shape[1] != 2:
            raise ValueError("Polygon regions are 2-D")
        v = np.asarray(self.vertices)
        px, py = x[:, 0], x[:, 1]
        inside = np.zeros(len(x), dtype=bool)
        on_edge = np.zeros(len(x), dtype=bool)
        scale = float(np.ptp(v, axis=0).max())
        for k in range(len(v)):  # loop over polygon edges, vectorised over points
            (x1, y1), (x2, y2) = v[k], v[(k + 1) % len(v)]
            cond = (y1 > py) != (y2 > py)
            with np.errstate(divide="ignore", invalid="ignore"):
                xint = (x2 - x1) * (py - y1) / (y2 - y1) + x1
            inside ^= cond & (px < xint)
            # points on the boundary count as inside
            ex, ey = x2 - x1, y2 - y1
            L2 = ex * ex + ey * ey
            t = np.clip(((px - x1) * ex + (py - y1) * ey) / L2, 0.0, 1.0)
            dist2 = (x1 + t * ex - px) ** 2 + (y1 + t * ey - py) ** 2
            on_edge |= dist2 <= (1e-12 * scale) ** 2
        return inside | on_edge


@dataclass(frozen=True, init=False)
class HalfSpace(Region):
    """Points with ``dot(x - point, normal) >= 0``."""

    point: tuple[float, ...]
    normal: tuple[float, ...]

    def __init__(self, point: ArrayLike, normal: ArrayLike) -> None:
        n = _vec(normal)
        if not np.any(n):
            raise ValueError("normal must be non-zero")
        object.__setattr__(self, "point", tuple(_vec(point).tolist()))
        object.__setattr__(self, "normal", tuple((n / np.linalg.norm(n)).tolist()))

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        d = (x - np.asarray(self.point)) @ np.asarray(self.normal)
        return d >= -1e-12 * max(1.0, float(np.abs(x).max(initial=0.0)))


@dataclass(frozen=True, init=False)
class NearestPoint(Region):
    """The single point closest to ``location`` (ties: lowest index).

    With ``max_distance`` (m), a location farther than that from every point is an error
    (a probe placed outside the body or in a hole).
    """

    pointwise = False

    location: tuple[float, ...]
    max_distance: float

    def __init__(self, location: ArrayLike, max_distance: float = np.inf) -> None:
        object.__setattr__(self, "location", tuple(_vec(location).tolist()))
        object.__setattr__(self, "max_distance", float(max_distance))

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        out = np.zeros(len(x), dtype=bool)
        if len(x):
            d2 = np.sum((x - np.asarray(self.location)) ** 2, axis=1)
            k = int(np.argmin(d2))
            if np.sqrt(d2[k]) > self.max_distance:
                raise ValueError(
                    f"point {list(self.location)} is {np.sqrt(d2[k]):.3g} m from the nearest "
                    f"point of the body (more than {self.max_distance:.3g} m): is it outside "
                    "the body or in a hole?"
                )
            out[k] = True
        return out


@dataclass(frozen=True, init=False)
class Layer(Region):
    """The outermost layer of the body on the side of ``normal``.

    Selects points whose projection on the unit ``normal`` lies within ``depth`` (m) of
    the largest projection over all points passed to :meth:`mask` (the body's surface).
    With ``depth = k * spacing`` on a grid this is exactly ``k`` rows at any resolution.
    ``top`` (m), when given, replaces that largest projection (the body's, when
    :meth:`mask` sees only a part of it: a rank's points).
    """

    pointwise = False

    normal: tuple[float, ...]
    depth: float
    top: float | None

    def __init__(self, normal: ArrayLike, depth: float, top: float | None = None) -> None:
        n = _vec(normal)
        if not np.any(n):
            raise ValueError("normal must be non-zero")
        if not depth > 0:
            raise ValueError("depth must be > 0")
        object.__setattr__(self, "normal", tuple((n / np.linalg.norm(n)).tolist()))
        object.__setattr__(self, "depth", float(depth))
        object.__setattr__(self, "top", None if top is None else float(top))

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        proj = x @ np.asarray(self.normal)
        if proj.size == 0:
            return np.zeros(0, dtype=bool)
        top = proj.max() if self.top is None else self.top
        return proj > top - self.depth * (1.0 - 1e-6)


def is_pointwise(region: Region) -> bool:
    """Whether every point's membership in ``region`` depends on its position only
    (through ``&``, ``|`` and ``~``), so any subset of the points can be tested alone."""
    if isinstance(region, _Combined):
        return all(is_pointwise(p) for p in region.parts)
    if isinstance(region, _Not):
        return is_pointwise(region.part)
    return bool(region.pointwise)


def map_leaves(region: Region, fn: Callable[[Region], Region]) -> Region:
    """``region`` with every leaf (a region that is not ``&``, ``|`` or ``~`` of others)
    replaced by ``fn(leaf)``, the combination kept."""
    if isinstance(region, _Combined):
        return _Combined(region.op, tuple(map_leaves(p, fn) for p in region.parts))
    if isinstance(region, _Not):
        return _Not(map_leaves(region.part, fn))
    return fn(region)
