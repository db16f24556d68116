"""Analytic rigid shapes in their body frame: half-space, box, sphere (disc), cylinder.

Each shape is a small frozen dataclass with an integer code ``Shape.kind`` and a
flat float64 parameter vector :attr:`Shape.params`, so that one Numba kernel handles
every shape through the code (:func:`peridynamics.kernels.rigid_contact.shape_sdf`); no
Python object enters a kernel. The dimension (2 or 3) is the length of the centre (or
of the point, for a plane).

:meth:`Shape.evaluate` is the NumPy signed distance: ``phi(p)`` (m), negative inside
the solid, and the outward unit normal at the closest surface point, for points in
the body frame. It is exact inside and outside:

* outside, the normal is the unit gradient of ``phi``, i.e. ``(p - p_s) / |p - p_s|``
  with ``p_s`` the closest surface point (at an edge or corner of a box or at the rim
  of a cylinder, the direction from that edge);
* inside, ``phi`` is minus the distance to the nearest face and the normal is the
  outward normal of that face (on a tie the first axis wins for the box, the mantle
  wins over a cap for the cylinder).

Where the direction is undefined (the centre of a sphere, the axis of a cylinder when
the mantle is nearest) a fixed body axis is used: ``+e_0`` for the sphere,
``+e_{(axis + 1) % 3}`` for the cylinder. The box signed distance is the standard one,
``phi = |max(q, 0)| + min(max_c q_c, 0)`` with ``q = |p - centre| - h``.

Parameter layouts (``dim`` entries per vector):

==========  ====  ====================================================================
shape       kind  params
==========  ====  ====================================================================
Plane       0     point (dim), unit outward normal (dim); the solid is behind the plane
Box         1     centre (dim), half extents (dim), axis-aligned in the body frame
Sphere      2     centre (dim), radius; a disc in 2-D
Cylinder    3     centre (dim), radius, half-length, axis (0, 1 or 2); capped. In 2-D
                  the axis must be 2 (out of plane) and the section is a disc
==========  ====  ====================================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

#: shape codes read by the Numba kernels
PLANE = 0
BOX = 1
SPHERE = 2
CYLINDER = 3

F = NDArray[np.float64]


def _vector(name: str, value: ArrayLike, dim: int | None = None) -> tuple[float, ...]:
    a = np.asarray(value, dtype=np.float64).ravel()
    if a.size not in (2, 3) or (dim is not None and a.size != dim):
        want = f"{dim}" if dim is not None else "2 or 3"
        raise ValueError(f"{name} must have {want} components, got {a.size}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite, got {a}")
    return tuple(float(t) for t in a)


def _length(name: str, value: float) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a finite length > 0 m, got {value}")
    return v


def _points(p: ArrayLike, dim: int) -> F:
    a = np.asarray(p, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != dim:
        raise ValueError(f"points must have shape (m, {dim}), got {a.shape}")
    return a


def _sign(a: F) -> F:
    """+1 where ``a >= 0``, -1 elsewhere (0 counts as positive)."""
    return np.where(a >= 0.0, 1.0, -1.0)


@dataclass(frozen=True)
class Shape:
    """Base class: ``kind`` code, ``params`` vector, ``dim`` and :meth:`evaluate`."""

    kind: ClassVar[int] = -1

    @property
    def dim(self) -> int:
        """Space dimension, 2 or 3."""
        raise NotImplementedError

    @property
    def params(self) -> F:
        """Flat float64 parameter vector read by the kernels (layout: module doc)."""
        raise NotImplementedError

    def evaluate(self, p: ArrayLike) -> tuple[F, F]:
        """Signed distance and outward unit normal of body-frame points.

        Parameters
        ----------
        p : array_like, shape (m, dim)
            Points in the body frame (m).

        Returns
        -------
        phi : ndarray, shape (m,)
            Signed distance (m), negative inside the solid.
        normal : ndarray, shape (m, dim)
            Outward unit normal at the closest surface point.
        """
        raise NotImplementedError


@dataclass(frozen=True)
class Plane(Shape):
    """Half-space behind the plane through ``point`` with outward ``normal`` (normalised
    on construction)."""

    point: tuple[float, ...]
    normal: tuple[float, ...]
    kind: ClassVar[int] = PLANE

    def __post_init__(self) -> None:
        p = _vector("point", self.point)
        n = np.asarray(_vector("normal", self.normal, len(p)))
        norm = float(np.linalg.norm(n))
        if norm == 0.0:
            raise ValueError("normal must not be zero")
        object.__setattr__(self, "point", p)
        object.__setattr__(self, "normal", tuple(float(t) for t in n / norm))

    @property
    def dim(self) -> int:
        return len(self.point)

    @property
    def params(self) -> F:
        return np.array(self.point + self.normal)

    def evaluate(self, p: ArrayLike) -> tuple[F, F]:
        a = _points(p, self.dim)
        n = np.asarray(self.normal)
        phi = (a - np.asarray(self.point)) @ n
        return phi, np.broadcast_to(n, a.shape).copy()


@dataclass(frozen=True)
class Box(Shape):
    """Box with ``half_extents`` (m) around ``center``, axis-aligned in the body frame."""

    center: tuple[float, ...]
    half_extents: tuple[float, ...]
    kind: ClassVar[int] = BOX

    def __post_init__(self) -> None:
        c = _vector("center", self.center)
        h = _vector("half_extents", self.half_extents, len(c))
        for t in h:
            _length("half_extents", t)
        object.__setattr__(self, "center", c)
        object.__setattr__(self, "half_extents", h)

    @property
    def dim(self) -> int:
        return len(self.center)

    @property
    def params(self) -> F:
        return np.array(self.center + self.half_extents)

    def evaluate(self, p: ArrayLike) -> tuple[F, F]:
        d = _points(p, self.dim) - np.asarray(self.center)
        s = _sign(d)
        q = np.abs(d) - np.asarray(self.half_extents)
        qp = np.maximum(q, 0.0)
        outside = np.sqrt(np.sum(qp * qp, axis=1))
        phi = outside + np.minimum(q.max(axis=1), 0.0)
        normal = np.zeros_like(d)
        out = outside > 0.0
        normal[out] = s[out] * qp[out] / outside[out, None]
        rows = np.flatnonzero(~out)
        a = np.argmax(q[rows], axis=1)  # nearest face (first axis on a tie)
        normal[rows, a] = s[rows, a]
        return phi, normal


@dataclass(frozen=True)
class Sphere(Shape):
    """Ball (3-D) or disc (2-D) of ``radius`` (m) around ``center``."""

    center: tuple[float, ...]
    radius: float
    kind: ClassVar[int] = SPHERE

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _vector("center", self.center))
        object.__setattr__(self, "radius", _length("radius", self.radius))

    @property
    def dim(self) -> int:
        return len(self.center)

    @property
    def params(self) -> F:
        return np.array((*self.center, self.radius))

    def evaluate(self, p: ArrayLike) -> tuple[F, F]:
        return _disc(_points(p, self.dim) - np.asarray(self.center), self.radius)


def _disc(d: F, radius: float) -> tuple[F, F]:
    r = np.sqrt(np.sum(d * d, axis=1))
    normal = np.zeros_like(d)
    on = r > 0.0
    normal[on] = d[on] / r[on, None]
    normal[~on, 0] = 1.0  # the centre: +e_0
    return r - radius, normal


@dataclass(frozen=True)
class Cylinder(Shape):
    """Capped cylinder of ``radius`` and ``half_length`` (m) around ``center``, its axis
    along body axis ``axis``. In 2-D the axis must be 2 (out of the plane): a disc."""

    center: tuple[float, ...]
    radius: float
    half_length: float
    axis: int = 2
    kind: ClassVar[int] = CYLINDER

    def __post_init__(self) -> None:
        c = _vector("center", self.center)
        object.__setattr__(self, "center", c)
        object.__setattr__(self, "radius", _length("radius", self.radius))
        object.__setattr__(self, "half_length", _length("half_length", self.half_length))
        if self.axis not in ((0, 1, 2) if len(c) == 3 else (2,)):
            raise ValueError(
                f"axis must be 0, 1 or 2 in 3-D and 2 (out of plane) in 2-D, got {self.axis}"
                " (a 2-D cylinder seen from the side is a Box)"
            )

    @property
    def dim(self) -> int:
        return len(self.center)

    @property
    def params(self) -> F:
        return np.array((*self.center, self.radius, self.half_length, float(self.axis)))

    def evaluate(self, p: ArrayLike) -> tuple[F, F]:
        d = _points(p, self.dim) - np.asarray(self.center)
        if self.dim == 2:
            return _disc(d, self.radius)
        a = self.axis
        z = d[:, a]
        radial = d.copy()
        radial[:, a] = 0.0
        rho = np.sqrt(np.sum(radial * radial, axis=1))
        e_r = np.zeros_like(d)
        on = rho > 0.0
        e_r[on] = radial[on] / rho[on, None]
        e_r[~on, (a + 1) % 3] = 1.0  # on the axis
        e_z = np.zeros_like(d)
        e_z[:, a] = _sign(z)
        q0 = rho - self.radius
        q1 = np.abs(z) - self.half_length
        p0, p1 = np.maximum(q0, 0.0), np.maximum(q1, 0.0)
        outside = np.sqrt(p0 * p0 + p1 * p1)
        phi = outside + np.minimum(np.maximum(q0, q1), 0.0)
        safe = np.where(outside > 0.0, outside, 1.0)[:, None]
        n_out = (p0[:, None] * e_r + p1[:, None] * e_z) / safe
        n_in = np.where((q0 >= q1)[:, None], e_r, e_z)
        return phi, np.where((outside > 0.0)[:, None], n_out, n_in)
