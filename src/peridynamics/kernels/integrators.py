"""Fused explicit-integration updates (Numba), in place on (n_points, n_components)
arrays; ``inv_mass`` (n_points, n_components) is the inverse mass density of each
component (1/rho for displacements, the inverse rotational inertia for rotations), or
(n_points, 1) when every component of a point has the same mass (read once per point)."""

from __future__ import annotations

from numba import njit, prange

_kernel = njit(parallel=True, fastmath=False, cache=True)


@_kernel
def kick_drift(u, v, force, body, inv_mass, dt):
    """Velocity Verlet first half: v += dt/2 * a; u += dt * v, with a = (f + b) / rho."""
    n, d = u.shape
    h = 0.5 * dt
    per_point = inv_mass.shape[1] == 1
    for i in prange(n):
        for c in range(d):
            w = inv_mass[i, 0] if per_point else inv_mass[i, c]
            v[i, c] += h * (force[i, c] + body[i, c]) * w
            u[i, c] += dt * v[i, c]


@_kernel
def kick(v, force, body, inv_mass, dt):
    """Velocity Verlet second half: v += dt/2 * a."""
    n, d = v.shape
    h = 0.5 * dt
    per_point = inv_mass.shape[1] == 1
    for i in prange(n):
        for c in range(d):
            w = inv_mass[i, 0] if per_point else inv_mass[i, c]
            v[i, c] += h * (force[i, c] + body[i, c]) * w


@_kernel
def central_difference(u, u_prev, v, force, body, inv_mass, dt):
    """Central difference (Lu & Wang (2016), eq. 10): u+ = 2u - u- + dt^2 a.

    On return ``u_prev`` holds the old ``u`` and ``v`` the mid-step velocity
    (u+ - u) / dt.
    """
    n, d = u.shape
    dt2 = dt * dt
    per_point = inv_mass.shape[1] == 1
    for i in prange(n):
        for c in range(d):
            w = inv_mass[i, 0] if per_point else inv_mass[i, c]
            un = u[i, c]
            new = 2.0 * un - u_prev[i, c] + dt2 * (force[i, c] + body[i, c]) * w
            u_prev[i, c] = un
            u[i, c] = new
            v[i, c] = (new - un) / dt


@_kernel
def end_of_step_velocity(u, u_prev, v, force, body, inv_mass, dt):
    """Central difference: v(t) = (u - u_prev)/dt + dt/2 a(t), the velocity at the end of
    the step (equal to velocity Verlet's), after the forces at t are known."""
    n, d = u.shape
    h = 0.5 * dt
    per_point = inv_mass.shape[1] == 1
    for i in prange(n):
        for c in range(d):
            w = inv_mass[i, 0] if per_point else inv_mass[i, c]
            v[i, c] = (u[i, c] - u_prev[i, c]) / dt + h * (force[i, c] + body[i, c]) * w


@_kernel
def column_sums(a, out):
    """``out`` (d,) = the sum of each column of ``a`` (n, d): what the stability check
    needs for the mean displacement (NumPy's ``a.sum(axis=0)`` runs one inner loop of d
    per row, 10x slower for d = 2)."""
    n, d = a.shape
    for c in range(d):
        acc = 0.0
        for i in prange(n):
            acc += a[i, c]
        out[c] = acc
