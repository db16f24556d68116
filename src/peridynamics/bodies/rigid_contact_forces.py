"""Contact of rigid bodies with deformable points: the Python API over the kernels of
:mod:`peridynamics.kernels.rigid_contact` and :mod:`peridynamics.kernels.rigid_points_contact`.

A rigid body is given by its :class:`Pose` (world point = ``R p + c`` for a body-frame
point p) and its :class:`Twist` (velocity ``v_c`` of the point c and angular velocity
omega, a scalar about z in 2-D). Both contact classes ADD the force density on the
deformable points to the solver's force array and return a :class:`ContactResult`
with the reaction on the body, for the rigid-body dynamics.

Normal force (Parks et al. 2008, the short-range contact of
:class:`peridynamics.evaluation.short_range_contact.ShortRangeContact` with a wall): a
deformable point i at
``y_i`` with gap ``g = phi(R^T (y_i - c)) - r_c < 0`` gets

.. math:: F_n = c_s V_i \\frac{-g}{d_c} n, \\qquad d_c = 2 r_c,

the pair law ``c_s (d_c - r) / d_c V_j`` of a partner of the mirror volume ``V_j = V_i``
at ``r = phi + r_c``, i.e. a virtual point ``r_c`` behind the surface. It derives from
the energy ``V_i^2 c_s g^2 / (2 d_c)`` (``V_i F_n = -dPhi/dy_i``) and stiffens the point by
``c_s V_i / d_c`` (N/m^3 per m), to add to the explicit stable time-step bound.

Friction (Coulomb, static ``mu_s`` >= kinetic ``mu_k``) with the explicit
"velocity-stopping" regularisation: with ``v_t`` the tangential part of the velocity of
the point relative to the body surface, ``v_i - (v_c + omega x (y - c))``, the force
density that stops the slip in one step is ``rho_i |v_t| / dt``; if it is at most
``mu_s |F_n|`` the point sticks, ``F_t = -rho_i v_t / dt``, else it slides,
``F_t = -mu_k |F_n| v_t / |v_t|``. The friction power ``sum V_i F_t . v_t`` is <= 0.
Coulomb friction between particles: Cundall & Strack (1979). The stick/slide test on
the force that would bring the tangential relative velocity to zero within one step is
that of the frictional contact algorithm of the material-point method (Bardenhagen et
al. 2000): it needs no tangential spring and no history, and sticking is exact after
one explicit step. Pass the velocity the solver holds when it evaluates the forces
(velocity Verlet: the half-step ``v_{n+1/2}``; the next full kick ``dt F / rho`` then
brings ``v_t`` to zero).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from peridynamics.bodies.shapes import Shape
from peridynamics.evaluation.short_range_contact import check_friction
from peridynamics.kernels import rigid_contact as shape_kernels
from peridynamics.kernels import rigid_points_contact as point_kernels

F = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Pose:
    """Rigid-body placement: world point = ``rotation @ p + translation``.

    Parameters
    ----------
    rotation : ndarray, shape (dim, dim)
        Proper orthogonal matrix R (checked to 1e-8).
    translation : ndarray, shape (dim,)
        c (m), the world position of the body-frame origin.
    """

    rotation: F
    translation: F

    def __post_init__(self) -> None:
        r = np.ascontiguousarray(np.asarray(self.rotation, dtype=np.float64))
        c = np.ascontiguousarray(np.asarray(self.translation, dtype=np.float64))
        d = c.shape[0] if c.ndim == 1 else -1
        if d not in (2, 3) or r.shape != (d, d):
            raise ValueError(f"need rotation (dim, dim) and translation (dim,), dim 2|3: "
                             f"got {r.shape} and {c.shape}")  # fmt: skip
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(c))):
            raise ValueError("pose must be finite")
        if np.abs(r.T @ r - np.eye(d)).max() > 1e-8 or np.linalg.det(r) < 0:
            raise ValueError("rotation must be a proper orthogonal matrix (to 1e-8)")
        object.__setattr__(self, "rotation", r)
        object.__setattr__(self, "translation", c)

    @property
    def dim(self) -> int:
        """2 or 3."""
        return int(self.translation.shape[0])

    @classmethod
    def identity(cls, dim: int) -> Pose:
        """Body frame = world frame."""
        return cls(np.eye(dim), np.zeros(dim))

    @classmethod
    def planar(cls, angle: float, translation: ArrayLike) -> Pose:
        """2-D pose: rotation by ``angle`` (rad, counter-clockwise), then translation (m)."""
        a = float(angle)
        rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        return cls(rot, np.asarray(translation, dtype=np.float64))


@dataclass(frozen=True, eq=False)
class Twist:
    """Rigid-body velocity: ``v(y) = linear + angular x (y - c)``.

    Parameters
    ----------
    linear : ndarray, shape (dim,)
        Velocity of the pose translation c (m/s).
    angular : float or ndarray, shape (3,)
        Angular velocity (rad/s): a scalar (about z) in 2-D, a world 3-vector in 3-D.
    """

    linear: F
    angular: float | F = 0.0

    def omega3(self, dim: int) -> F:
        """The angular velocity as a world 3-vector (2-D: ``(0, 0, omega)``)."""
        w = np.asarray(self.angular, dtype=np.float64)
        if dim == 2:
            if w.ndim != 0:
                raise ValueError(f"2-D angular velocity must be a scalar, got shape {w.shape}")
            return np.array([0.0, 0.0, float(w)])
        if w.shape != (3,):
            raise ValueError(f"3-D angular velocity must have shape (3,), got {w.shape}")
        return np.ascontiguousarray(w)

    def linear3(self, dim: int) -> F:
        """``linear`` padded to 3 components, checked against ``dim``."""
        v = np.asarray(self.linear, dtype=np.float64)
        if v.shape != (dim,):
            raise ValueError(f"linear velocity must have shape ({dim},), got {v.shape}")
        return np.concatenate([v, np.zeros(3 - dim)])

    @classmethod
    def zero(cls, dim: int) -> Twist:
        """A body at rest."""
        return cls(np.zeros(dim), 0.0 if dim == 2 else np.zeros(3))


@dataclass(frozen=True)
class ContactResult:
    """Reaction of the deformable points on a rigid body (one evaluation).

    Attributes
    ----------
    force : ndarray, shape (dim,)
        Total force on the body ``-sum_i V_i F_i`` (N).
    torque : float or ndarray, shape (3,)
        Its moment about the pose translation c, ``sum (y_i - c) x (-V_i F_i)`` (N m):
        a scalar (z) in 2-D.
    friction_power : float
        ``sum_i V_i F_t,i . v_t,i`` (W), <= 0: the rate of frictional dissipation is
        its opposite.
    n_contacts : int
        Number of deformable points in contact.
    """

    force: F
    torque: float | F
    friction_power: float
    n_contacts: int


def _result(out: F, dim: int) -> ContactResult:
    torque: float | F = float(out[5]) if dim == 2 else out[3:6].copy()
    return ContactResult(out[:dim].copy(), torque, float(out[6]), int(out[7]))


def _positive(name: str, value: float, unit: str) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a finite value > 0 {unit}, got {value}")
    return v


class _Buffers:
    """Per-point reduction rows, reallocated only when the number of points changes."""

    def __init__(self) -> None:
        self.rows = np.empty((0, shape_kernels.N_ROW))
        self.out = np.empty(shape_kernels.N_ROW)

    def fit(self, n: int) -> None:
        if self.rows.shape[0] != n:
            self.rows = np.empty((n, shape_kernels.N_ROW))


class RigidContact:
    """Base of :class:`RigidShapeContact` and :class:`RigidPointsContact`: the common
    contact API (``add_force``, ``energy``) and argument checks."""

    dim: int

    def __init__(self, stiffness: float, friction_static: float, friction_kinetic: float):
        self.stiffness = _positive("stiffness", stiffness, "N/m^6")
        self.friction_static, self.friction_kinetic = check_friction(
            friction_static, friction_kinetic
        )
        self._buf = _Buffers()

    def add_force(self, y: F, v: F, volume: F, density: float | F, pose: Pose, twist: Twist,
                  dt: float, force: F) -> ContactResult:  # fmt: skip
        """ADD the contact force density (N/m^3) to ``force``; see the subclasses."""
        raise NotImplementedError

    def energy(self, y: F, volume: F, pose: Pose) -> float:
        """Contact energy (J) at positions ``y`` (n, dim) and ``pose``."""
        raise NotImplementedError

    def _inputs(self, y, v, volume, density, pose, twist, dt, force) -> tuple:
        ya = np.asarray(y, dtype=np.float64)
        n = ya.shape[0]
        if ya.shape != (n, self.dim) or pose.dim != self.dim:
            raise ValueError(f"y must have shape (n, {self.dim}) and the pose dim {self.dim}")
        for name, a in (("v", v), ("force", force)):
            if a.shape != ya.shape:
                raise ValueError(f"{name} must have shape {ya.shape}, got {a.shape}")
        vol = np.asarray(volume, dtype=np.float64)
        if vol.shape != (n,):
            raise ValueError(f"volume must have shape ({n},), got {vol.shape}")
        rho = np.asarray(density, dtype=np.float64)
        rho = np.full(n, float(rho)) if rho.ndim == 0 else rho
        if rho.shape != (n,):
            raise ValueError(f"density must be a scalar or have shape ({n},)")
        step = 1.0
        if self.friction_static > 0:
            step = _positive("dt", dt, "s")
        self._buf.fit(n)
        return ya, np.asarray(v, dtype=np.float64), vol, rho, step


class RigidShapeContact(RigidContact):
    """Contact of an analytic rigid :class:`~peridynamics.bodies.shapes.Shape` with
    deformable points (module doc for the model).

    Parameters
    ----------
    shape : Shape
        The body in its own frame (2-D or 3-D).
    contact_radius : float
        r_c (m) > 0: points closer than r_c to the surface (or inside) are in contact;
        ``d_c = 2 r_c`` (half the pair contact distance is the natural choice).
    stiffness : float
        c_s (N/m^6) > 0, as in
        :class:`peridynamics.evaluation.short_range_contact.ShortRangeContact`.
    friction_static, friction_kinetic : float, optional
        mu_s >= mu_k >= 0 (default 0: frictionless, and the velocities are not read).
    """

    def __init__(self, shape: Shape, contact_radius: float, stiffness: float,
                 friction_static: float = 0.0, friction_kinetic: float = 0.0) -> None:  # fmt: skip
        super().__init__(stiffness, friction_static, friction_kinetic)
        self.shape = shape
        self.dim = shape.dim
        self.contact_radius = _positive("contact_radius", contact_radius, "m")
        self._params = np.ascontiguousarray(shape.params)

    @property
    def contact_distance(self) -> float:
        """d_c = 2 r_c (m)."""
        return 2.0 * self.contact_radius

    def add_force(self, y: F, v: F, volume: F, density: float | F, pose: Pose, twist: Twist,
                  dt: float, force: F) -> ContactResult:  # fmt: skip
        """ADD the contact force density (N/m^3) on the points to ``force`` (n, dim).

        ``y`` (n, dim): current positions x + u (m); ``v`` (n, dim): velocities (m/s);
        ``volume`` (n,) (m^3); ``density`` (kg/m^3), scalar or (n,); ``dt``: time step
        (s), read only with friction. Returns the reaction on the body.
        """
        ya, va, vol, rho, step = self._inputs(y, v, volume, density, pose, twist, dt, force)
        b = self._buf
        shape_kernels.rigid_shape_rows(
            ya, va, vol, rho, self.shape.kind, self._params, pose.rotation, pose.translation,
            twist.linear3(self.dim), twist.omega3(self.dim), self.contact_radius,
            self.stiffness, self.friction_static, self.friction_kinetic, step, force, b.rows,
        )  # fmt: skip
        shape_kernels.sum_rows(b.rows, b.out)
        return _result(b.out, self.dim)

    def energy(self, y: F, volume: F, pose: Pose) -> float:
        """Contact energy ``sum_i V_i^2 c_s g_i^2 / (2 d_c)`` over ``g_i < 0`` (J)."""
        ya = np.asarray(y, dtype=np.float64)
        w = np.empty(ya.shape[0])
        shape_kernels.rigid_shape_energy(
            ya, np.asarray(volume, dtype=np.float64), self.shape.kind, self._params,
            pose.rotation, pose.translation, self.contact_radius, self.stiffness, w,
        )  # fmt: skip
        return float(np.sum(w))

    def signed_distance(self, y: F, pose: Pose) -> tuple[F, F]:
        """Signed distance (n,) (m, < 0 inside) and outward world normal (n, dim) of the
        world points ``y`` (n, dim)."""
        ya = np.asarray(y, dtype=np.float64)
        phi = np.empty(ya.shape[0])
        normal = np.zeros_like(ya)
        shape_kernels.shape_distance(
            ya, self.shape.kind, self._params, pose.rotation, pose.translation, phi, normal
        )
        return phi, normal


class RigidPointsContact(RigidContact):
    """Contact of a rigid body made of points with deformable points.

    Each body point k (body frame ``p_k``, volume ``V_k``) acts on a deformable point i
    closer than ``d_c`` with the pair law of the short-range contact,
    ``F_i += c_s (d_c - r) / d_c V_k e`` (e from the body point to i; energy
    ``V_i V_k c_s (d_c - r)^2 / (2 d_c)``), plus the friction rule of the module doc
    against the body point's velocity ``v_c + omega x (y_k - c)``: each contact takes
    its share ``fn_k / sum_k fn_k`` of the stopping force, so a point touching several
    body points is not stopped several times over; sticking is decided on the total
    load. The body points are bucketed once into a body-frame grid of cells of side
    >= d_c (grown if the grid would exceed 4 m + 4096 cells).

    Parameters
    ----------
    points : ndarray, shape (m, dim)
        Body-frame positions (m), e.g. ``(x - c0) @ R0`` for points cut from a cloud at
        the initial pose (R0, c0).
    volume : ndarray, shape (m,)
        Their volumes (m^3).
    contact_distance : float
        d_c (m) > 0.
    stiffness, friction_static, friction_kinetic :
        As for :class:`RigidShapeContact`.
    """

    def __init__(self, points: F, volume: F, contact_distance: float, stiffness: float,
                 friction_static: float = 0.0, friction_kinetic: float = 0.0) -> None:  # fmt: skip
        super().__init__(stiffness, friction_static, friction_kinetic)
        p = np.asarray(points, dtype=np.float64)
        m = p.shape[0]
        if p.ndim != 2 or p.shape[1] not in (2, 3) or m == 0 or not np.all(np.isfinite(p)):
            raise ValueError(f"points must be finite with shape (m > 0, 2|3), got {p.shape}")
        vol = np.asarray(volume, dtype=np.float64)
        if vol.shape != (m,):
            raise ValueError(f"volume must have shape ({m},), got {vol.shape}")
        self.dim = p.shape[1]
        self.contact_distance = _positive("contact_distance", contact_distance, "m")
        lo, hi = p.min(axis=0), p.max(axis=0)
        side = self.contact_distance * (1.0 + 1e-9)  # rounding never skips a cell
        while True:
            ncell = (np.floor((hi - lo) / side) + 1).astype(np.int64)
            if math.prod(int(k) for k in ncell) <= 4 * m + 4096:
                break
            side *= 1.5
        stride = np.cumprod(np.concatenate([ncell[1:], [1]])[::-1])[::-1]
        coords = np.minimum(np.floor((p - lo) / side).astype(np.int64), ncell - 1)
        keys = coords @ stride
        order = np.argsort(keys, kind="stable")
        self.cell_side = float(side)
        self.points = np.ascontiguousarray(p[order])
        self.point_volume = np.ascontiguousarray(vol[order])
        self._lo, self._ncell = lo, ncell
        n_cells = int(np.prod(ncell))
        self._cell_start = np.searchsorted(keys[order], np.arange(n_cells + 1)).astype(np.int64)

    def add_force(self, y: F, v: F, volume: F, density: float | F, pose: Pose, twist: Twist,
                  dt: float, force: F) -> ContactResult:  # fmt: skip
        """ADD the contact force density (N/m^3) to ``force``; arguments and result as
        :meth:`RigidShapeContact.add_force`."""
        ya, va, vol, rho, step = self._inputs(y, v, volume, density, pose, twist, dt, force)
        b = self._buf
        omega_body = twist.omega3(self.dim)
        if self.dim == 3:
            omega_body = np.ascontiguousarray(pose.rotation.T @ omega_body)
        point_kernels.rigid_points_force(
            ya, va, vol, rho, self.points, self.point_volume, self._lo, 1.0 / self.cell_side,
            self._ncell, self._cell_start, pose.rotation, pose.translation,
            twist.linear3(self.dim), omega_body, self.contact_distance, self.stiffness,
            self.friction_static, self.friction_kinetic, step, force, b.rows,
        )  # fmt: skip
        shape_kernels.sum_rows(b.rows, b.out)
        return _result(b.out, self.dim)

    def energy(self, y: F, volume: F, pose: Pose) -> float:
        """Contact energy ``sum_i sum_k V_i V_k c_s (d_c - r)^2 / (2 d_c)`` (J)."""
        ya = np.asarray(y, dtype=np.float64)
        w = np.empty(ya.shape[0])
        point_kernels.rigid_points_energy(
            ya, np.asarray(volume, dtype=np.float64), self.points, self.point_volume, self._lo,
            1.0 / self.cell_side, self._ncell, self._cell_start, pose.rotation,
            pose.translation, self.contact_distance, self.stiffness, w,
        )  # fmt: skip
        return float(np.sum(w))
