"""The contact law of one rigid body in its current pose, for
:class:`~peridynamics.bodies.rigid.RigidSystem`.

An analytic shape is given in the world frame at t = 0 (its body frame). The body turns
about its reference point ``G0`` (centroid) and translates by ``Delta``, so a body-frame
point ``p`` is at ``R (p - G0) + G0 + Delta = R p + trans`` with
``trans = G0 + Delta - R G0``, the pose of :mod:`peridynamics.bodies.rigid_contact_forces`. A point
set is stored relative to ``G0`` (``trans = G``). The laws return the torque about
``trans``; it is moved to the reference point here: ``tau_G = tau_trans - (G - trans) x F``,
and the velocity of ``trans`` is ``v_G + omega x (trans - G)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bodies import shapes
from peridynamics.bodies.rigid_contact_forces import (
    Pose,
    RigidPointsContact,
    RigidShapeContact,
    Twist,
)

F64 = NDArray[np.float64]


def shape_of(spec: Any, dim: int, thickness: float) -> shapes.Shape:
    """The analytic shape of a deck ``rigid_bodies.*.shape`` section (not ``points``)."""
    k = spec.kind()
    v = getattr(spec, k)

    def vec(name: str, a: Any) -> tuple[float, ...]:
        if len(a) != dim:
            raise ValueError(f"shape.{k}.{name} needs {dim} components, got {len(a)}")
        return tuple(float(t) for t in a)

    if k == "plane":
        return shapes.Plane(vec("point", v.point), vec("normal", v.normal))
    if k == "box":
        lo, hi = np.asarray(vec("min", v.min)), np.asarray(vec("max", v.max))
        return shapes.Box(tuple(0.5 * (lo + hi)), tuple(0.5 * (hi - lo)))
    if k == "sphere":
        return shapes.Sphere(vec("center", v.center), v.radius)
    center = vec("center", v.center)
    if dim == 2:  # a disc: the axis is out of the plane
        half = 0.5 * (v.length if v.length is not None else max(thickness, 1.0))
        return shapes.Cylinder(center, v.radius, half, 2)
    if v.length is None:
        raise ValueError("shape.cylinder.length is needed in 3-D (m)")
    return shapes.Cylinder(center, v.radius, 0.5 * v.length, "xyz".index(v.axis))


class BodyContact:
    """The contact law of one rigid body about its reference point ``G0``.

    Parameters
    ----------
    law : RigidShapeContact or RigidPointsContact
        :mod:`peridynamics.bodies.rigid_contact_forces`; an analytic shape is given in the
        world frame at t = 0, a point set relative to ``G0``.
    reference : (dim,) G0 (m).
    relative : bool
        True when the law's body frame has its origin at G0 (point sets).
    """

    def __init__(self, law: Any, reference: F64, relative: bool) -> None:
        self.law = law
        self.reference = np.asarray(reference, dtype=np.float64)
        self.relative = relative

    def evaluate(
        self,
        y: F64,
        v: F64,
        volume: F64,
        density: F64,
        rotation: F64,
        center: F64,
        velocity: F64,
        omega: F64,
        dt: float,
        force: F64,
    ) -> tuple[F64, F64, float, int]:
        """ADD the contact force density (N/m^3) to ``force`` (n, dim) for positions
        ``y`` and velocities ``v`` (n, dim), the body turned by ``rotation`` (dim, dim)
        with its reference point at ``center`` (dim,), moving with ``velocity`` (dim,)
        and angular velocity ``omega`` (3,). Returns the force on the body (dim,) (N),
        its torque about ``center`` (3,) (N m), the friction power (W, <= 0) and the
        number of points in contact."""
        d = y.shape[1]
        trans = center if self.relative else center - rotation @ self.reference
        arm = center - trans  # from the pose origin to the reference point
        w3 = np.asarray(omega, dtype=np.float64)
        w_arm = np.cross(w3, np.concatenate([-arm, np.zeros(3 - d)]))[:d]
        twist = Twist(velocity + w_arm, float(w3[2]) if d == 2 else w3)
        res = self.law.add_force(y, v, volume, density, Pose(rotation, trans), twist, dt, force)
        f3 = np.zeros(3)
        f3[:d] = res.force
        tq = np.zeros(3)
        if d == 2:
            tq[2] = float(res.torque)
        else:
            tq[:] = res.torque
        a3 = np.zeros(3)
        a3[:d] = arm
        torque = tq - np.cross(a3, f3)
        return np.asarray(res.force, dtype=np.float64), torque, res.friction_power, res.n_contacts


def contact_for_shape(
    shape: Any, reference: F64, radius: float, stiffness: float, mu_s: float, mu_k: float
) -> BodyContact:
    """The contact law of a rigid body: an analytic shape (contact radius ``radius``) or
    a point set (a PointCloud; pair contact distance ``2 radius``)."""
    if isinstance(shape, shapes.Shape):
        return BodyContact(
            RigidShapeContact(shape, radius, stiffness, mu_s, mu_k), reference, relative=False
        )
    pts = np.asarray(shape.x) - np.asarray(reference)
    law = RigidPointsContact(pts, shape.volume, 2.0 * radius, stiffness, mu_s, mu_k)
    return BodyContact(law, reference, relative=True)
