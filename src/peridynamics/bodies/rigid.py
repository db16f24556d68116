"""Rigid bodies: platens, supports, indenters and strikers.

A rigid body has no bonds and no force evaluation of its own; it touches the deformable
points through contact (:mod:`peridynamics.kernels.rigid_contact`), and the contact
force on it is its **reaction**, recorded every history step. Its motion is either

* ``prescribed``: translation with velocity ``v0 f(t)`` (``f`` a time function), no
  rotation (a platen, a loading pin, a fixed support when ``v0 = 0``); or
* ``free``: translation and rotation under the contact forces (a striker): three
  degrees of freedom in 2-D, six in 3-D. The integrator is velocity Verlet on the
  linear momentum and the angular momentum in the world frame, with the rotation
  advanced by the exact exponential (Rodrigues) of ``dt omega``, ``omega = R I^-1 R^T L``.
  Without contact both momenta are conserved to round-off.

The State holds, per rigid body (rows in deck order): ``rigid_position`` (m, 3),
displacement of its reference point (the centroid of a finite shape); ``rigid_velocity``
(m, 3); ``rigid_rotation`` (m, 9) the rotation matrix row by row; ``rigid_momentum``
(m, 3) the angular momentum (kg m^2/s; in 2-D only z); ``rigid_force`` (m, 3) and
``rigid_torque`` (m, 3), the contact resultants of the last evaluation (N, N m). The
energy dissipated by friction is the State field ``friction_work`` of the evaluator.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.communicator import active_comm
from peridynamics.state import State

#: State fields of the rigid bodies: name -> components per body
RIGID_FIELDS = {
    "rigid_position": 3,
    "rigid_velocity": 3,
    "rigid_rotation": 9,
    "rigid_momentum": 3,
    "rigid_force": 3,
    "rigid_torque": 3,
}


def rotation_step(omega: NDArray[np.float64], dt: float) -> NDArray[np.float64]:
    """exp(dt [omega]x), the rotation by the angle |omega| dt about omega (Rodrigues),
    shape (3, 3)."""
    w = np.asarray(omega, dtype=float) * dt
    angle = math.sqrt(float(w @ w))
    if angle == 0.0:
        return np.eye(3)
    k = w / angle
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(angle) * kx + (1.0 - math.cos(angle)) * (kx @ kx)


@dataclass
class RigidBody:
    """One rigid body.

    Parameters
    ----------
    name : str
    dim : int
        2 or 3.
    contact : object with an ``evaluate`` method
        ``evaluate(y, v, volume, density, rotation, center, velocity, omega, dt, force)``
        that returns ``(force_on_body (dim,), torque (3,), friction_power, n_contacts)``
        The contact law of its shape (analytic or points), in the body frame.
    center : (dim,) initial position of the reference point (m).
    motion : {"prescribed", "free"}
    velocity : (dim,) prescribed velocity scale, or the initial velocity of a free body
        (m/s).
    time_function : callable t -> float, optional
        Multiplier of the prescribed velocity (default 1).
    mass : float
        kg (free bodies; ``inf`` for prescribed ones).
    inertia : (3, 3) inertia tensor about the reference point in the body frame (kg m^2)
        (free bodies).
    angular_velocity : (3,) initial angular velocity of a free body (rad/s).
    """

    name: str
    dim: int
    contact: Any
    center: NDArray[np.float64]
    motion: str = "prescribed"
    velocity: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    time_function: Callable[[float], float] | None = None
    mass: float = math.inf
    inertia: NDArray[np.float64] = field(default_factory=lambda: np.eye(3))
    angular_velocity: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        if self.motion not in ("prescribed", "free"):
            raise ValueError(f"rigid body {self.name!r}: motion must be prescribed or free")
        if self.motion == "free" and not (math.isfinite(self.mass) and self.mass > 0):
            raise ValueError(f"rigid body {self.name!r}: a free body needs a finite mass > 0")
        self.center = _pad3(self.center)
        self.velocity = _pad3(self.velocity)
        self.angular_velocity = _pad3(self.angular_velocity)
        self.inertia = np.asarray(self.inertia, dtype=float).reshape(3, 3)
        if self.motion == "free":
            if self.dim == 2:
                if not self.inertia[2, 2] > 0:
                    raise ValueError(f"rigid body {self.name!r}: inertia about z must be > 0")
                self.angular_velocity[:2] = 0.0
            elif np.any(np.linalg.eigvalsh(self.inertia) <= 0):
                raise ValueError(f"rigid body {self.name!r}: the inertia tensor must be positive")
            self.inv_inertia = np.linalg.inv(self.inertia) if self.dim == 3 else None

    def speed_scale(self, t: float) -> float:
        """The prescribed velocity's multiplier at t."""
        return 1.0 if self.time_function is None else float(self.time_function(t))

    def omega(self, rotation: NDArray[np.float64], momentum: NDArray[np.float64]) -> NDArray:
        """World angular velocity (3,) from the rotation (3, 3) and angular momentum."""
        if self.motion != "free":
            return np.zeros(3)
        if self.dim == 2:
            return np.array([0.0, 0.0, momentum[2] / self.inertia[2, 2]])
        assert self.inv_inertia is not None
        return rotation @ (self.inv_inertia @ (rotation.T @ momentum))


def _pad3(v: object) -> NDArray[np.float64]:
    a = np.zeros(3)
    b = np.asarray(v, dtype=float).reshape(-1)
    a[: b.size] = b
    return a


class RigidSystem:
    """Every rigid body of a model: their State fields, contact forces and motion.

    Parameters
    ----------
    bodies : sequence of RigidBody
    volume : (n,) nodal volumes of the deformable points (m^3).
    density : (n,) their mass densities (kg/m^3).
    """

    def __init__(self, bodies: list[RigidBody], volume: NDArray, density: NDArray) -> None:
        self.bodies = list(bodies)
        names = [b.name for b in self.bodies]
        if len(set(names)) != len(names):
            raise ValueError(f"rigid body names must be unique, got {names}")
        self.volume = np.ascontiguousarray(volume, dtype=float)
        self.density = np.ascontiguousarray(density, dtype=float)
        #: the run's communicator: under MPI the contact acts on this rank's owned
        #: points and the resultants are summed over the ranks (every rank holds every
        #: rigid body's few degrees of freedom and moves them alike)
        self.comm = active_comm()
        self.time_step = 1.0  # set by an explicit solver (the friction law needs it)
        #: translation applied at set-up to bodies with ``touch`` (name -> (dim,) m)
        self.seating: dict[str, list[float]] = {}

    @property
    def n_bodies(self) -> int:
        return len(self.bodies)

    def index(self, name: str) -> int:
        """Row of the rigid body ``name``."""
        for k, b in enumerate(self.bodies):
            if b.name == name:
                return k
        raise KeyError(name)

    def init_fields(self, state: State) -> None:
        """Allocate and initialise the rigid-body fields of a new State."""
        m = self.n_bodies
        for name, comps in RIGID_FIELDS.items():
            state[name] = np.zeros((m, comps))
        rot = state["rigid_rotation"]
        for k, b in enumerate(self.bodies):
            rot[k] = np.eye(3).ravel()
            if b.motion == "free":
                state["rigid_velocity"][k] = b.velocity
                w = b.angular_velocity
                state["rigid_momentum"][k] = (
                    b.inertia @ w if b.dim == 3 else np.array([0.0, 0.0, b.inertia[2, 2] * w[2]])
                )
            else:
                state["rigid_velocity"][k] = b.velocity * b.speed_scale(0.0)

    # -- forces ------------------------------------------------------------------------
    def add_force(self, state: State, u: NDArray, v: NDArray, x: NDArray, force: NDArray) -> float:
        """ADD the contact force density of every rigid body on the deformable points to
        ``force`` (n, dim); store each body's resultant and torque in the State. Returns
        the friction power of this evaluation (W, <= 0). Under MPI the owned points only:
        resultants and torques are summed over the ranks, the power is this rank's part
        (``friction_work`` is a per-rank partial sum)."""
        s = state
        own = self.comm.owned
        y = (x + u)[own]
        v, volume, density, force = v[own], self.volume[own], self.density[own], force[own]
        d = x.shape[1]
        power = 0.0
        for k, b in enumerate(self.bodies):
            rot3 = s["rigid_rotation"][k].reshape(3, 3)
            rot = rot3[:d, :d]
            c = b.center[:d] + s["rigid_position"][k, :d]
            omega = b.omega(rot3, s["rigid_momentum"][k])
            f_body, torque, p, _ = b.contact.evaluate(
                y, v, volume, density, np.ascontiguousarray(rot), c,
                s["rigid_velocity"][k, :d], omega, self.time_step, force,
            )  # fmt: skip
            total = self.comm.sum_array(np.concatenate([f_body, torque]))
            s["rigid_force"][k] = 0.0
            s["rigid_force"][k, :d] = total[:d]
            s["rigid_torque"][k] = total[d:]
            power += p
        return power

    # -- motion ------------------------------------------------------------------------
    def half_kick(self, state: State, dt: float) -> None:
        """Free bodies: momenta += dt/2 x (force, torque) of the last evaluation."""
        s = state
        for k, b in enumerate(self.bodies):
            if b.motion == "free":
                s["rigid_velocity"][k] += 0.5 * dt * s["rigid_force"][k] / b.mass
                tq = s["rigid_torque"][k]
                if b.dim == 2:
                    s["rigid_momentum"][k, 2] += 0.5 * dt * tq[2]
                else:
                    s["rigid_momentum"][k] += 0.5 * dt * tq

    def drift(self, state: State, t: float, dt: float) -> None:
        """Positions and rotations from t to t + dt (prescribed: velocity at mid-step)."""
        s = state
        for k, b in enumerate(self.bodies):
            if b.motion == "free":
                s["rigid_position"][k] += dt * s["rigid_velocity"][k]
                rot = s["rigid_rotation"][k].reshape(3, 3)
                omega = b.omega(rot, s["rigid_momentum"][k])
                s["rigid_rotation"][k] = (rotation_step(omega, dt) @ rot).ravel()
            else:
                vel = b.velocity * b.speed_scale(t + 0.5 * dt)
                s["rigid_position"][k] += dt * vel
                s["rigid_velocity"][k] = b.velocity * b.speed_scale(t + dt)

    # -- diagnostics -------------------------------------------------------------------
    def outlines(self, state: State, x: NDArray) -> list[NDArray]:
        """2-D outlines (k, 2) of the rigid bodies in their current pose, for figures: a
        box as 4 corners, a disc as 48 points, a point set as its convex hull; a plane
        as a thin strip across the span of ``x`` (reference positions)."""
        out = []
        span = float(np.ptp(x, axis=0).max())
        for k, b in enumerate(self.bodies):
            law = getattr(b.contact, "law", None)
            shape: Any = getattr(law, "shape", None)
            rot = state["rigid_rotation"][k].reshape(3, 3)[:2, :2]
            g0 = b.center[:2]
            g = g0 + state["rigid_position"][k, :2]
            kind = type(shape).__name__
            if kind == "Box":
                c, h = np.asarray(shape.center), np.asarray(shape.half_extents)
                body = c + h * np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]])
            elif kind in ("Sphere", "Cylinder"):
                a = np.linspace(0.0, 2.0 * np.pi, 48, endpoint=False)
                body = np.asarray(shape.center) + shape.radius * np.c_[np.cos(a), np.sin(a)]
            elif kind == "Plane":
                p0, n = np.asarray(shape.point), np.asarray(shape.normal)
                t = np.array([-n[1], n[0]])
                mid = x.mean(axis=0)
                s0 = float((mid - p0) @ t)
                depth = 0.02 * span
                a0, a1 = p0 + (s0 - span) * t, p0 + (s0 + span) * t
                body = np.array([a0, a1, a1 - depth * n, a0 - depth * n])
            elif law is not None and hasattr(law, "points"):
                from scipy.spatial import ConvexHull

                pts = np.asarray(law.points) + g0
                body = pts[ConvexHull(pts).vertices]
            else:
                continue
            out.append((body - g0) @ rot.T + g)
        return out

    def kinetic_energy(self, state: State) -> float:
        """Kinetic energy of the free bodies (J)."""
        e = 0.0
        s = state
        for k, b in enumerate(self.bodies):
            if b.motion == "free":
                vel = s["rigid_velocity"][k]
                rot = s["rigid_rotation"][k].reshape(3, 3)
                mom = s["rigid_momentum"][k]
                e += 0.5 * b.mass * float(vel @ vel) + 0.5 * float(b.omega(rot, mom) @ mom)
        return e
