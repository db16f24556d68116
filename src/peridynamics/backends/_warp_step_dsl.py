# mypy: ignore-errors
"""Warp kernels of the explicit step (velocity Verlet, central difference, kinematic
conditions, body-force loads, mass damping, the stability check's reductions) in the
arithmetic order of :mod:`peridynamics.kernels.integrators` and
:mod:`peridynamics.loading.conditions`, so the CPU device gives the Numba bits."""

from __future__ import annotations

from peridynamics.backends._warp_dsl import wp

if wp is not None:
    # no FMA contraction: the CUDA device then gives the CPU device's bits (and the
    # Numba kernels' decisions); see docs/gpu.md
    wp.set_module_options({"fuse_fp": False})

    @wp.kernel
    def kick_drift(  # pragma: no cover - compiled by Warp
        u: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
        force: wp.array2d(dtype=wp.float64),
        body: wp.array2d(dtype=wp.float64),
        inv_mass: wp.array(dtype=wp.float64),
        dt: wp.float64,
    ) -> None:
        i = wp.tid()
        h = wp.float64(0.5) * dt
        w = inv_mass[i]
        for c in range(u.shape[1]):
            v[i, c] = v[i, c] + h * (force[i, c] + body[i, c]) * w
            u[i, c] = u[i, c] + dt * v[i, c]

    @wp.kernel
    def kick(  # pragma: no cover - compiled by Warp
        v: wp.array2d(dtype=wp.float64),
        force: wp.array2d(dtype=wp.float64),
        body: wp.array2d(dtype=wp.float64),
        inv_mass: wp.array(dtype=wp.float64),
        dt: wp.float64,
    ) -> None:
        i = wp.tid()
        h = wp.float64(0.5) * dt
        w = inv_mass[i]
        for c in range(v.shape[1]):
            v[i, c] = v[i, c] + h * (force[i, c] + body[i, c]) * w

    @wp.kernel
    def central_difference(  # pragma: no cover - compiled by Warp
        u: wp.array2d(dtype=wp.float64),
        u_prev: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
        force: wp.array2d(dtype=wp.float64),
        body: wp.array2d(dtype=wp.float64),
        inv_mass: wp.array(dtype=wp.float64),
        dt: wp.float64,
    ) -> None:
        i = wp.tid()
        dt2 = dt * dt
        w = inv_mass[i]
        for c in range(u.shape[1]):
            un = u[i, c]
            new = wp.float64(2.0) * un - u_prev[i, c] + dt2 * (force[i, c] + body[i, c]) * w
            u_prev[i, c] = un
            u[i, c] = new
            v[i, c] = (new - un) / dt

    @wp.kernel
    def end_of_step_velocity(  # pragma: no cover - compiled by Warp
        u: wp.array2d(dtype=wp.float64),
        u_prev: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
        force: wp.array2d(dtype=wp.float64),
        body: wp.array2d(dtype=wp.float64),
        inv_mass: wp.array(dtype=wp.float64),
        dt: wp.float64,
    ) -> None:
        i = wp.tid()
        h = wp.float64(0.5) * dt
        w = inv_mass[i]
        for c in range(u.shape[1]):
            v[i, c] = (u[i, c] - u_prev[i, c]) / dt + h * (force[i, c] + body[i, c]) * w

    @wp.kernel
    def set_displacement(  # pragma: no cover - compiled by Warp
        nodes: wp.array(dtype=wp.int32),
        c: wp.int32,
        u_value: wp.float64,
        v_value: wp.float64,
        u: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
    ) -> None:
        p = nodes[wp.tid()]
        u[p, c] = u_value
        v[p, c] = v_value

    @wp.kernel
    def drive_velocity(  # pragma: no cover - compiled by Warp
        nodes: wp.array(dtype=wp.int32),
        c: wp.int32,
        v_mid: wp.float64,
        v_now: wp.float64,
        dt: wp.float64,
        u: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
    ) -> None:
        p = nodes[wp.tid()]
        u[p, c] = u[p, c] + dt * (v_mid - v[p, c])
        v[p, c] = v_now

    @wp.kernel
    def set_velocity(  # pragma: no cover - compiled by Warp
        nodes: wp.array(dtype=wp.int32),
        c: wp.int32,
        v_value: wp.float64,
        v: wp.array2d(dtype=wp.float64),
    ) -> None:
        v[nodes[wp.tid()], c] = v_value

    @wp.kernel
    def add_load(  # pragma: no cover - compiled by Warp
        nodes: wp.array(dtype=wp.int32),
        value: wp.array2d(dtype=wp.float64),
        f: wp.float64,
        body: wp.array2d(dtype=wp.float64),
    ) -> None:
        t = wp.tid()
        p = nodes[t]
        for c in range(body.shape[1]):
            body[p, c] = body[p, c] + value[t, c] * f

    @wp.kernel
    def mass_damping(  # pragma: no cover - compiled by Warp
        coefficient: wp.array(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
        force: wp.array2d(dtype=wp.float64),
    ) -> None:
        i = wp.tid()
        for c in range(v.shape[1]):
            force[i, c] = force[i, c] - coefficient[i] * v[i, c]

    @wp.kernel
    def count_broken(  # pragma: no cover - compiled by Warp
        broken: wp.array(dtype=wp.int64),
        total: wp.array(dtype=wp.int64),
    ) -> None:
        b = broken[wp.tid()]
        if b != wp.int64(0):
            wp.atomic_add(total, 0, b)

    @wp.kernel
    def sum_columns(  # pragma: no cover - compiled by Warp
        a: wp.array2d(dtype=wp.float64),
        out: wp.array(dtype=wp.float64),
    ) -> None:
        i = wp.tid()
        for c in range(a.shape[1]):
            wp.atomic_add(out, c, a[i, c])

    @wp.kernel
    def first_bad_point(  # pragma: no cover - compiled by Warp
        u: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
        shift: wp.array(dtype=wp.float64),
        limit: wp.float64,
        stretch: wp.array(dtype=wp.float64),
        stretch_limit: wp.float64,
        first: wp.array(dtype=wp.int32),
    ) -> None:
        i = wp.tid()
        bad = stretch[i] > stretch_limit
        for c in range(u.shape[1]):
            a = u[i, c]
            b = v[i, c]
            if not (wp.isfinite(a) and wp.isfinite(b)):
                bad = True
            elif wp.abs(a - shift[c]) > limit:
                bad = True
        if bad:
            wp.atomic_min(first, 0, i)

    @wp.kernel
    def add_friction_work(  # pragma: no cover - compiled by Warp
        power: wp.array(dtype=wp.float64),
        dt: wp.float64,
        work: wp.array(dtype=wp.float64),
    ) -> None:
        p = power[wp.tid()]
        if p != wp.float64(0.0):
            wp.atomic_add(work, 0, -p * dt)
