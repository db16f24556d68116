"""Plain NumPy twins of the rigid-body contact kernels, for the tests.

:mod:`peridynamics.kernels.rigid_contact` (analytic shapes) and
:mod:`peridynamics.kernels.rigid_points_contact` (bodies of points, here brute force
over all (point, body point) pairs). No Python loop over points. Each force twin
returns ``(F, body_force, torque, power, count)``: the force density (n, dim) (N/m^3),
the force on the body ``-sum V_i F_i`` (dim,) (N), its torque about the pose
translation as a 3-vector (N m; 2-D: ``(0, 0, tau_z)``), the friction power
``sum V_i F_t . v_t`` (W) and the number of points in contact.

An analytic shape is any object with ``evaluate(p) -> (phi, normal)``, the signed
distance (m,) and outward normal (m, dim) of body-frame points p (m, dim) (the shapes of
:mod:`peridynamics.bodies.shapes` are such objects); this module imports none of them.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from numpy.typing import NDArray

F = NDArray[np.float64]


class Shape(Protocol):
    """A signed-distance shape in its body frame (module doc)."""

    def evaluate(self, p: F) -> tuple[F, F]:
        """Signed distance (m,) (m) and outward unit normal (m, dim) of body-frame points."""
        ...


def _pad3(a: F) -> F:
    """(n, dim) -> (n, 3), zeros appended in 2-D."""
    return np.pad(a, ((0, 0), (0, 3 - a.shape[1])))


def shape_distance_reference(shape: Shape, rot: F, trans: F, y: F) -> tuple[F, F]:
    """Signed distance (n,) (m) and outward world normal (n, dim) of the world points
    ``y`` (n, dim) to ``shape`` at the pose world = ``rot @ p + trans``."""
    phi, normal = shape.evaluate((y - trans) @ rot)  # rows of R^T (y - c)
    return phi, normal @ rot.T


def coulomb_reference(
    w: F, n: F, fn: F, load: F, rho: F, mu_s: float, mu_k: float, dt: float
) -> tuple[F, F]:
    """Friction force density (m, dim) and ``F_t . v_t`` (m,) of m contacts: relative
    velocity ``w``, unit normal ``n`` (m, dim), normal force density ``fn`` and total
    load ``load`` of the point (m,) (N/m^3), density ``rho`` (m,); the rule of
    :func:`peridynamics.kernels.rigid_contact.friction`."""
    vt = w - n * np.sum(n * w, axis=1)[:, None]
    speed = np.linalg.norm(vt, axis=1)
    stick = rho * speed <= mu_s * load * dt
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(stick, fn / load * rho / dt, mu_k * fn / speed)
    k = np.where(speed > 0, k, 0.0)
    ft = -k[:, None] * vt
    return ft, np.sum(ft * vt, axis=1)


def _reductions(y: F, trans: F, volume: F, force: F, power: F, on: NDArray) -> tuple:
    body = -(volume[:, None] * force)[on]
    torque = np.cross(_pad3((y - trans)[on]), _pad3(body))
    return (
        body.sum(axis=0),
        torque.sum(axis=0),
        float(np.sum(volume[on] * power[on])),
        int(on.sum()),
    )


def rigid_shape_force_reference(
    y: F, v: F, volume: F, density: F, shape: Shape, rot: F, trans: F, vlin: F,
    omega: F, r_c: float, c_s: float, mu_s: float, mu_k: float, dt: float,
) -> tuple:  # fmt: skip
    """Contact of an analytic shape (module doc for the returned tuple); ``omega`` is
    the world angular velocity as a 3-vector, ``vlin`` (dim,) the velocity of the pose
    translation."""
    n, dim = y.shape
    phi, normal = shape_distance_reference(shape, rot, trans, y)
    g = phi - r_c
    on = g < 0
    fn = np.where(on, c_s * volume * (-g) / (2 * r_c), 0.0)
    force = fn[:, None] * normal
    power = np.zeros(n)
    if mu_s > 0:
        wall = vlin[:dim] + np.cross(omega, _pad3(y - trans))[:, :dim]
        ft, p = coulomb_reference(v - wall, normal, fn, fn, density, mu_s, mu_k, dt)
        force += np.where(on[:, None], ft, 0.0)
        power = np.where(on, p, 0.0)
    return (force, *_reductions(y, trans, volume, force, power, on))


def rigid_shape_energy_reference(
    y: F, volume: F, shape: Shape, rot: F, trans: F, r_c: float, c_s: float
) -> float:
    """Contact energy ``sum V_i^2 c_s g^2 / (2 d_c)`` over ``g < 0`` (J)."""
    g = shape_distance_reference(shape, rot, trans, y)[0] - r_c
    return float(np.sum(np.where(g < 0, volume**2 * c_s * g * g / (4 * r_c), 0.0)))


def _pairs(y: F, points: F, rot: F, trans: F, d_c: float) -> tuple[F, F, NDArray]:
    """World pair vectors ``y_i - y_k`` (n, m, dim), distances (n, m) and contact mask."""
    yk = points @ rot.T + trans
    e = y[:, None, :] - yk[None, :, :]
    r = np.sqrt(np.sum(e * e, axis=-1))
    return e, r, (r < d_c) & (r > 0)


def rigid_points_force_reference(
    y: F, v: F, volume: F, density: F, points: F, pvol: F, rot: F, trans: F, vlin: F,
    omega: F, d_c: float, c_s: float, mu_s: float, mu_k: float, dt: float,
) -> tuple:  # fmt: skip
    """Contact of a rigid body of body-frame ``points`` (m, dim) with volumes ``pvol``
    (m,), brute force over all pairs (module doc for the returned tuple)."""
    n, dim = y.shape
    e, r, mask = _pairs(y, points, rot, trans, d_c)
    safe = np.where(mask, r, 1.0)
    fn = np.where(mask, c_s * (d_c - r) / d_c * pvol[None, :], 0.0)
    unit = e / safe[..., None]
    force = np.sum(fn[..., None] * unit, axis=1)
    power = np.zeros(n)
    if mu_s > 0:
        ii, kk = np.nonzero(mask)
        yk = points @ rot.T + trans
        wall = vlin[:dim] + np.cross(omega, _pad3(yk - trans))[:, :dim]
        load = fn.sum(axis=1)
        ft, p = coulomb_reference(
            v[ii] - wall[kk], unit[ii, kk], fn[ii, kk], load[ii], density[ii], mu_s, mu_k, dt
        )
        for c in range(dim):  # the <= 3 components
            force[:, c] += np.bincount(ii, weights=ft[:, c], minlength=n)
        power = np.bincount(ii, weights=p, minlength=n).astype(np.float64)
    on = np.asarray(mask.any(axis=1), dtype=bool)
    return (force, *_reductions(y, trans, volume, force, power, on))


def rigid_points_energy_reference(
    y: F, volume: F, points: F, pvol: F, rot: F, trans: F, d_c: float, c_s: float
) -> float:
    """Contact energy ``sum_i sum_k V_i V_k c_s (d_c - r)^2 / (2 d_c)`` (J)."""
    _, r, _ = _pairs(y, points, rot, trans, d_c)
    w = np.where(r < d_c, (d_c - r) ** 2, 0.0) * np.outer(volume, pvol)
    return float(c_s / (2 * d_c) * np.sum(w))
