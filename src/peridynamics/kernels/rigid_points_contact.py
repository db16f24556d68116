"""Contact of a rigid body made of points (a striker or platen cut from a point cloud)
with deformable points: Numba kernels.

Used by :class:`peridynamics.bodies.rigid_contact_forces.RigidPointsContact`, which documents the
physics; the brute-force NumPy twin is in
:mod:`peridynamics.kernels.reference_rigid_contact`.

The body points ``p_k`` (m, dim) are bucketed once in the BODY frame into a dense grid
of cells of side >= ``d_c`` (keys with the last axis fastest; the points sorted by key,
``cell_start[k]:cell_start[k + 1]`` the slots of cell k). Per deformable point i (prange,
gather, no atomics) ``q = R^T (y_i - c)`` is located in the grid and the 3^dim cells
around it are visited (the last axis as one contiguous run of up to 3 cells). Each body
point closer than ``d_c`` pushes with the pair law of the short-range contact (Parks et
al. 2008),

    F_i += c_s (d_c - r) / d_c V_k e,     e = (q - p_k) / r,

computed in the body frame and rotated to the world frame once per point, plus the
Coulomb friction of :func:`peridynamics.kernels.rigid_contact.friction` against the
velocity ``v_c + omega x (y_k - c)`` of the body point, each contact taking its share
of the point's total normal load (a first pass over the neighbours sums it when the
friction is on).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from peridynamics.kernels.rigid_contact import (
    N_ROW,
    _cross,
    _rotate,
    _to_body,
    _write_row,
    friction,
)

# strict floating point: with fast-math, a kernel compiled in the process and the same
# kernel loaded from Numba's cache gave different bits (a resumed run then differed from
# an uninterrupted one; tests/regression/test_bodies_checkpoint.py with a cold cache)
_hot = njit(parallel=True, fastmath=False, error_model="numpy", cache=True)


@njit(inline="always")
def _cell_range(q, c, lo, inv_side, ncell):
    """Cells ``[a, b]`` along axis c within one cell of the body-frame coordinate q;
    empty (a > b) when q is more than one cell outside the grid or not finite."""
    t = (q - lo[c]) * inv_side
    if not (t >= -1.0 and t < ncell[c] + 1.0):
        return 1, 0
    k = int(np.floor(t))
    return max(k - 1, 0), min(k + 1, ncell[c] - 1)


@njit(inline="always")
def _to_body_vector(rot, dim, a0, a1, a2):
    """``R^T a`` for a world vector (third = 0 in 2-D)."""
    if dim == 2:
        return rot[0, 0] * a0 + rot[1, 0] * a1, rot[0, 1] * a0 + rot[1, 1] * a1, 0.0
    return (
        rot[0, 0] * a0 + rot[1, 0] * a1 + rot[2, 0] * a2,
        rot[0, 1] * a0 + rot[1, 1] * a1 + rot[2, 1] * a2,
        rot[0, 2] * a0 + rot[1, 2] * a1 + rot[2, 2] * a2,
    )


@njit(inline="always")
def _visit(q0, q1, q2, dim, pts, pvol, lo, inv_side, ncell, cell_start, d_c, c_s, mode,
           w0, w1, w2, om0, om1, om2, load, rho, mu_s, mu_k, dt):  # fmt: skip
    """Sum over the body points within ``d_c`` of the body-frame point q.

    ``mode`` 0: returns the normal load ``sum_k c_s (d_c - r) / d_c V_k`` (N/m^3) and
    the count. ``mode`` 1: returns the body-frame force density (normal + friction,
    N/m^3), the friction power density (W/m^3) and the count; ``w`` is
    ``R^T (v_i - v_c)`` and ``om`` the body-frame angular velocity.
    """
    a0, b0 = _cell_range(q0, 0, lo, inv_side, ncell)
    a1, b1 = _cell_range(q1, 1, lo, inv_side, ncell)
    if dim == 3:
        a2, b2 = _cell_range(q2, 2, lo, inv_side, ncell)
        s0, s1 = ncell[1] * ncell[2], ncell[2]
    else:
        a2, b2 = 0, 0
        s0, s1 = ncell[1], 0
    dc_sq = d_c * d_c
    f0 = f1 = f2 = pw = 0.0
    cnt = 0
    if a0 > b0 or a1 > b1 or a2 > b2:  # more than one cell outside the grid
        return f0, f1, f2, pw, cnt
    for c0 in range(a0, b0 + 1):
        for c1 in range(a1 if dim == 3 else 0, (b1 if dim == 3 else 0) + 1):
            if dim == 3:
                k0, k1 = c0 * s0 + c1 * s1 + a2, c0 * s0 + c1 * s1 + b2
            else:
                k0, k1 = c0 * s0 + a1, c0 * s0 + b1
            if k1 < k0:
                continue
            for s in range(cell_start[k0], cell_start[k1 + 1]):
                e0 = q0 - pts[s, 0]
                e1 = q1 - pts[s, 1]
                e2 = q2 - pts[s, 2] if dim == 3 else 0.0
                r2 = e0 * e0 + e1 * e1 + e2 * e2
                if r2 >= dc_sq or r2 == 0.0:
                    continue
                r = np.sqrt(r2)
                fn = c_s * (d_c - r) / d_c * pvol[s]
                cnt += 1
                if mode == 0:
                    f0 += fn
                    continue
                e0, e1, e2 = e0 / r, e1 / r, e2 / r
                f0 += fn * e0
                f1 += fn * e1
                f2 += fn * e2
                if mu_s > 0.0:
                    p2 = pts[s, 2] if dim == 3 else 0.0
                    x0, x1, x2 = _cross(om0, om1, om2, pts[s, 0], pts[s, 1], p2)
                    t0, t1, t2, p = friction(
                        w0 - x0, w1 - x1, w2 - x2, e0, e1, e2, fn, load, rho, mu_s, mu_k, dt
                    )
                    f0 += t0
                    f1 += t1
                    f2 += t2
                    pw += p
    return f0, f1, f2, pw, cnt


@_hot
def rigid_points_force(y, v, volume, density, pts, pvol, lo, inv_side, ncell, cell_start,
                       rot, trans, vlin, omega_body, d_c, c_s, mu_s, mu_k, dt, force,
                       rows):  # fmt: skip
    """ADD the contact force density (N/m^3) of a rigid body of points to ``force``.

    ``pts`` (m, dim) and ``pvol`` (m,) are the key-sorted body-frame points and volumes,
    ``lo`` (dim,), ``inv_side``, ``ncell`` (dim,) and ``cell_start`` (n_cells + 1,) their
    grid; ``omega_body`` (3,) is ``R^T omega`` (2-D: ``(0, 0, omega_z)``). Writes the
    reduction rows (n, 8) as :func:`peridynamics.kernels.rigid_contact.rigid_shape_rows`
    does, a point being in contact when it touches at least one body point.
    """
    n, dim = y.shape
    om0, om1, om2 = omega_body[0], omega_body[1], omega_body[2]
    for i in prange(n):
        q0, q1, q2 = _to_body(i, y, rot, trans)
        load = 0.0
        w0 = w1 = w2 = 0.0
        if mu_s > 0.0:
            load = _visit(
                q0, q1, q2, dim, pts, pvol, lo, inv_side, ncell, cell_start, d_c, c_s, 0,
                0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            )[0]  # fmt: skip
            d0 = v[i, 0] - vlin[0]
            d1 = v[i, 1] - vlin[1]
            d2 = v[i, 2] - vlin[2] if dim == 3 else 0.0
            w0, w1, w2 = _to_body_vector(rot, dim, d0, d1, d2)
        f0, f1, f2, pw, cnt = _visit(
            q0, q1, q2, dim, pts, pvol, lo, inv_side, ncell, cell_start, d_c, c_s, 1,
            w0, w1, w2, om0, om1, om2, load, density[i], mu_s, mu_k, dt,
        )  # fmt: skip
        if cnt == 0:
            for c in range(N_ROW):
                rows[i, c] = 0.0
            continue
        g0, g1, g2 = _rotate(rot, dim, f0, f1, f2)
        force[i, 0] += g0
        force[i, 1] += g1
        if dim == 3:
            force[i, 2] += g2
        _write_row(i, y, volume[i], trans, g0, g1, g2, pw, rows)


@njit(parallel=True, cache=True)
def rigid_points_energy(y, volume, pts, pvol, lo, inv_side, ncell, cell_start, rot, trans,
                        d_c, c_s, w):  # fmt: skip
    """Per-point contact energy ``w_i = V_i sum_k V_k c_s (d_c - r)^2 / (2 d_c)`` (J), (n,)."""
    n, dim = y.shape
    dc_sq = d_c * d_c
    for i in prange(n):
        q0, q1, q2 = _to_body(i, y, rot, trans)
        a0, b0 = _cell_range(q0, 0, lo, inv_side, ncell)
        a1, b1 = _cell_range(q1, 1, lo, inv_side, ncell)
        a2, b2 = _cell_range(q2, 2, lo, inv_side, ncell) if dim == 3 else (0, 0)
        acc = 0.0
        for c0 in range(a0, b0 + 1):
            for c1 in range(a1, b1 + 1):
                for c2 in range(a2, b2 + 1):
                    if dim == 3:
                        k = (c0 * ncell[1] + c1) * ncell[2] + c2
                    else:
                        k = c0 * ncell[1] + c1
                    for s in range(cell_start[k], cell_start[k + 1]):
                        e0 = q0 - pts[s, 0]
                        e1 = q1 - pts[s, 1]
                        e2 = q2 - pts[s, 2] if dim == 3 else 0.0
                        r2 = e0 * e0 + e1 * e1 + e2 * e2
                        if r2 < dc_sq:
                            g = d_c - np.sqrt(r2)
                            acc += pvol[s] * g * g
        w[i] = volume[i] * acc * c_s / (2.0 * d_c)
