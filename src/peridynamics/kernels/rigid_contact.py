"""Contact of an analytic rigid shape with deformable points: Numba kernels.

Used by :class:`peridynamics.bodies.rigid_contact_forces.RigidShapeContact`, which documents the
physics; the NumPy twins are in :mod:`peridynamics.kernels.reference_rigid_contact`.
One kernel handles every shape through its integer code and flat parameter vector
(:mod:`peridynamics.bodies.shapes`: plane 0, box 1, sphere 2, cylinder 3).

For each deformable point i at ``y_i`` (world frame) the body-frame position is
``p = R^T (y_i - c)`` (pose: world point = ``R p + c``), the gap ``g = phi(p) - r_c``
and, for ``g < 0``, the force density (N/m^3) on the point

    F_n = c_s V_i (-g) / d_c n,        d_c = 2 r_c,  n = R n_body,

(the pair law of the short-range contact, Parks et al. 2008, against a virtual point of
volume V_i at distance ``phi + r_c``),

plus the Coulomb friction ``F_t`` of :func:`friction` (stick: stop the relative
tangential velocity ``v_t`` in one step; slide: ``mu_k |F_n|`` against ``v_t``). The
reductions (force and torque on the body, friction power, contacts) are per-point rows
(:func:`rigid_shape_rows`) summed in index order (:func:`sum_rows`), so the result
does not depend on the number of threads.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

#: fast-math without the no-NaN / no-inf assumptions: a point flown to inf or NaN must
#: still fail the contact and grid-range tests (an out-of-grid cell index would read out
#: of bounds)
# strict floating point: with fast-math, a kernel compiled in the process and the same
# kernel loaded from Numba's cache gave different bits (a resumed run then differed from
# an uninterrupted one; tests/regression/test_bodies_checkpoint.py with a cold cache)
_hot = njit(parallel=True, fastmath=False, error_model="numpy", cache=True)
#: columns of the per-point reduction rows: force on the body (3), torque about c (3),
#: friction power, contact flag
N_ROW = 8


@njit(inline="always")
def _unit(k):
    return (1.0 if k == 0 else 0.0), (1.0 if k == 1 else 0.0), (1.0 if k == 2 else 0.0)


@njit(inline="always")
def _disc(d0, d1, d2, radius):
    r = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    if r > 0.0:
        return r - radius, d0 / r, d1 / r, d2 / r
    return r - radius, 1.0, 0.0, 0.0  # the centre: +e_0


@njit(inline="always")
def shape_sdf(kind, prm, dim, p0, p1, p2):
    """Signed distance (m) and outward unit normal ``(phi, n0, n1, n2)`` of the
    body-frame point ``(p0, p1, p2)`` (``p2`` = 0 and ``n2`` = 0 in 2-D); the rules of
    :mod:`peridynamics.bodies.shapes`."""
    if kind == 0:  # plane: point, normal
        if dim == 2:
            return (p0 - prm[0]) * prm[2] + (p1 - prm[1]) * prm[3], prm[2], prm[3], 0.0
        phi = (p0 - prm[0]) * prm[3] + (p1 - prm[1]) * prm[4] + (p2 - prm[2]) * prm[5]
        return phi, prm[3], prm[4], prm[5]
    d0 = p0 - prm[0]
    d1 = p1 - prm[1]
    d2 = p2 - prm[2] if dim == 3 else 0.0
    if kind == 1:  # box: centre, half extents
        s0 = 1.0 if d0 >= 0.0 else -1.0
        s1 = 1.0 if d1 >= 0.0 else -1.0
        s2 = 1.0 if d2 >= 0.0 else -1.0
        q0 = abs(d0) - prm[dim]
        q1 = abs(d1) - prm[dim + 1]
        q2 = abs(d2) - prm[dim + 2] if dim == 3 else -np.inf
        a0, a1, a2 = max(q0, 0.0), max(q1, 0.0), max(q2, 0.0)
        out = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        if out > 0.0:
            return out, s0 * a0 / out, s1 * a1 / out, s2 * a2 / out
        if q0 >= q1 and q0 >= q2:  # nearest face, first axis on a tie
            return q0, s0, 0.0, 0.0
        if q1 >= q2:
            return q1, 0.0, s1, 0.0
        return q2, 0.0, 0.0, s2
    if kind == 2 or dim == 2:  # sphere / disc, and the 2-D cylinder
        return _disc(d0, d1, d2, prm[dim])
    # 3-D capped cylinder: centre, radius, half-length, axis
    a = int(prm[5])
    if a == 0:
        z, r0, r1, r2 = d0, 0.0, d1, d2
    elif a == 1:
        z, r0, r1, r2 = d1, d0, 0.0, d2
    else:
        z, r0, r1, r2 = d2, d0, d1, 0.0
    rho = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    if rho > 0.0:
        e0, e1, e2 = r0 / rho, r1 / rho, r2 / rho
    else:  # on the axis
        e0, e1, e2 = _unit((a + 1) % 3)
    sz = 1.0 if z >= 0.0 else -1.0
    z0, z1, z2 = _unit(a)
    q0 = rho - prm[3]
    q1 = abs(z) - prm[4]
    b0, b1 = max(q0, 0.0), max(q1, 0.0)
    out = np.sqrt(b0 * b0 + b1 * b1)
    if out > 0.0:
        w0, w1 = b0 / out, sz * b1 / out
        return out, w0 * e0 + w1 * z0, w0 * e1 + w1 * z1, w0 * e2 + w1 * z2
    if q0 >= q1:  # the mantle is nearest
        return q0, e0, e1, e2
    return q1, sz * z0, sz * z1, sz * z2


@njit(inline="always")
def _to_body(i, y, rot, trans):
    """Body-frame coordinates ``R^T (y_i - c)`` (third = 0 in 2-D)."""
    dim = y.shape[1]
    p0 = p1 = p2 = 0.0
    for b in range(dim):
        t = y[i, b] - trans[b]
        p0 += rot[b, 0] * t
        p1 += rot[b, 1] * t
        if dim == 3:
            p2 += rot[b, 2] * t
    return p0, p1, p2


@njit(inline="always")
def _rotate(rot, dim, a0, a1, a2):
    """``R a`` for a body-frame vector (third = 0 in 2-D)."""
    if dim == 2:
        return rot[0, 0] * a0 + rot[0, 1] * a1, rot[1, 0] * a0 + rot[1, 1] * a1, 0.0
    return (
        rot[0, 0] * a0 + rot[0, 1] * a1 + rot[0, 2] * a2,
        rot[1, 0] * a0 + rot[1, 1] * a1 + rot[1, 2] * a2,
        rot[2, 0] * a0 + rot[2, 1] * a1 + rot[2, 2] * a2,
    )


@njit(inline="always")
def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit(inline="always")
def friction(w0, w1, w2, n0, n1, n2, fn, load, rho, mu_s, mu_k, dt):
    """Coulomb friction force density (N/m^3) of one contact: returns
    ``(F_t0, F_t1, F_t2, P)`` with ``P = F_t . v_t`` (W/m^3, <= 0).

    ``w`` (m/s) is the velocity of the point relative to the surface, ``n`` the unit
    normal, ``fn`` the normal force density magnitude of this contact and ``load`` (>=
    ``fn``) the sum over all the point's contacts (N/m^3), ``rho`` the density
    (kg/m^3). With ``v_t = w - n (n . w)``: when the stopping force density
    ``rho |v_t| / dt <= mu_s load`` the point sticks and this contact takes its share
    ``fn / load`` of the stopping force, ``F_t = -(fn / load) rho v_t / dt``; else it
    slides, ``F_t = -mu_k fn v_t / |v_t|``. One contact (``load = fn``): the whole
    stopping force, which brings ``v_t`` to zero in one explicit step.
    """
    wn = w0 * n0 + w1 * n1 + w2 * n2
    t0, t1, t2 = w0 - wn * n0, w1 - wn * n1, w2 - wn * n2
    vt2 = t0 * t0 + t1 * t1 + t2 * t2
    if vt2 == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    vt = np.sqrt(vt2)
    if rho * vt <= mu_s * load * dt:
        k = (fn / load) * (rho / dt)
    else:
        k = mu_k * fn / vt
    return -k * t0, -k * t1, -k * t2, -k * vt2


@njit(inline="always")
def _shape_point(i, y, v, volume, density, kind, prm, rot, trans, vlin, omega, r_c, c_s, mu_s,
                 mu_k, dt):  # fmt: skip
    """Force density (N/m^3), friction power density (W/m^3) and gap (m) of point i."""
    dim = y.shape[1]
    p0, p1, p2 = _to_body(i, y, rot, trans)
    phi, m0, m1, m2 = shape_sdf(kind, prm, dim, p0, p1, p2)
    g = phi - r_c
    if not g < 0.0:
        return 0.0, 0.0, 0.0, 0.0, g
    n0, n1, n2 = _rotate(rot, dim, m0, m1, m2)
    fn = c_s * volume[i] * (-g) / (2.0 * r_c)
    f0, f1, f2 = fn * n0, fn * n1, fn * n2
    if mu_s > 0.0:
        r0 = y[i, 0] - trans[0]
        r1 = y[i, 1] - trans[1]
        r2 = y[i, 2] - trans[2] if dim == 3 else 0.0
        s0, s1, s2 = _cross(omega[0], omega[1], omega[2], r0, r1, r2)
        w0 = v[i, 0] - vlin[0] - s0
        w1 = v[i, 1] - vlin[1] - s1
        w2 = v[i, 2] - vlin[2] - s2 if dim == 3 else 0.0
        t0, t1, t2, pw = friction(w0, w1, w2, n0, n1, n2, fn, fn, density[i], mu_s, mu_k, dt)
        return f0 + t0, f1 + t1, f2 + t2, pw, g
    return f0, f1, f2, 0.0, g


@njit(inline="always")
def _write_row(i, y, vi, trans, f0, f1, f2, pw, rows):
    """Reduction row of point i: ``-V_i F_i`` (N), its torque about ``trans`` (N m),
    ``V_i P_i`` (W) and the count 1."""
    dim = y.shape[1]
    b0, b1, b2 = -vi * f0, -vi * f1, -vi * f2
    r0 = y[i, 0] - trans[0]
    r1 = y[i, 1] - trans[1]
    r2 = y[i, 2] - trans[2] if dim == 3 else 0.0
    t0, t1, t2 = _cross(r0, r1, r2, b0, b1, b2)
    rows[i, 0], rows[i, 1], rows[i, 2] = b0, b1, b2
    rows[i, 3], rows[i, 4], rows[i, 5] = t0, t1, t2
    rows[i, 6] = vi * pw
    rows[i, 7] = 1.0


@_hot
def rigid_shape_rows(y, v, volume, density, kind, prm, rot, trans, vlin, omega, r_c, c_s,
                     mu_s, mu_k, dt, force, rows):  # fmt: skip
    """ADD the contact force density (N/m^3) of a rigid shape to ``force`` (n, dim) and
    write the per-point reduction rows ``rows`` (n, 8): force on the body ``-V_i F_i``
    (N, 3 columns), its torque about ``trans`` (N m, 3), friction power
    ``V_i F_t . v_t`` (W) and the contact flag (1.0 when ``g < 0``); zero rows for the
    points not in contact. :func:`sum_rows` adds them up.

    ``vlin`` (>= dim,) is the velocity of ``trans`` (m/s); ``omega`` is always a world
    3-vector (rad/s; 2-D: ``(0, 0, omega_z)``). In 2-D the third force column and the
    in-plane torque columns are 0.
    """
    n, dim = y.shape
    for i in prange(n):
        f0, f1, f2, pw, g = _shape_point(
            i, y, v, volume, density, kind, prm, rot, trans, vlin, omega, r_c, c_s, mu_s,
            mu_k, dt,
        )  # fmt: skip
        if g < 0.0:
            force[i, 0] += f0
            force[i, 1] += f1
            if dim == 3:
                force[i, 2] += f2
            _write_row(i, y, volume[i], trans, f0, f1, f2, pw, rows)
        else:
            for c in range(N_ROW):
                rows[i, c] = 0.0


@njit(cache=True)
def sum_rows(rows, out):
    """``out`` (8,) = the sum of the rows (n, 8) with a non-zero contact flag, in index
    order: the same bits for any number of threads, and much faster than
    ``rows.sum(axis=0)`` when few points touch."""
    for c in range(N_ROW):
        out[c] = 0.0
    for i in range(rows.shape[0]):
        if rows[i, N_ROW - 1] != 0.0:
            for c in range(N_ROW):
                out[c] += rows[i, c]


@njit(parallel=True, cache=True)
def rigid_shape_energy(y, volume, kind, prm, rot, trans, r_c, c_s, w):
    """Per-point contact energy ``w_i = V_i^2 c_s g^2 / (2 d_c)`` (J) for ``g < 0``,
    (n,)."""
    n = y.shape[0]
    dim = y.shape[1]
    for i in prange(n):
        p0, p1, p2 = _to_body(i, y, rot, trans)
        g = shape_sdf(kind, prm, dim, p0, p1, p2)[0] - r_c
        w[i] = volume[i] * volume[i] * c_s * g * g / (4.0 * r_c) if g < 0.0 else 0.0


@njit(parallel=True, cache=True)
def shape_distance(y, kind, prm, rot, trans, phi, normal):
    """Signed distance ``phi`` (n,) (m) and outward world normal ``normal`` (n, dim) of
    the world points ``y`` (n, dim) to the shape at pose (``rot``, ``trans``)."""
    n, dim = y.shape
    for i in prange(n):
        p0, p1, p2 = _to_body(i, y, rot, trans)
        d, m0, m1, m2 = shape_sdf(kind, prm, dim, p0, p1, p2)
        n0, n1, n2 = _rotate(rot, dim, m0, m1, m2)
        phi[i] = d
        normal[i, 0] = n0
        normal[i, 1] = n1
        if dim == 3:
            normal[i, 2] = n2
