# mypy: ignore-errors
"""Warp kernels of :mod:`peridynamics.backends.warp_short_range_contact`: the short-range
contact of :class:`~peridynamics.evaluation.short_range_contact.ShortRangeContact` on the device
(Verlet-list rebuild test,
candidate search on a float64 :class:`warp.HashGrid`, frictionless and Coulomb force
passes). Every kernel runs one thread per point and writes only that point's entries
(no atomics); the arithmetic and the order of each sum are those of the Numba kernels
of :mod:`peridynamics.kernels.short_range_contact` and
:mod:`peridynamics.kernels.short_range_friction`.
"""

from __future__ import annotations

from peridynamics.backends._warp_dsl import wp

if wp is not None:
    # no FMA contraction: the CUDA device then gives the CPU device's bits (and the
    # Numba kernels' decisions); see docs/gpu.md
    wp.set_module_options({"fuse_fp": False})

    @wp.func
    def _dist_sq(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        i: wp.int32,
        j: wp.int32,
    ) -> wp.float64:
        """|y_j - y_i|^2, each component ``(x_j - x_i) + (u_j - u_i)``, summed in
        component order (the host's expression: (i, j) and (j, i) get the same bits)."""
        s = wp.float64(0.0)
        for c in range(x.shape[1]):
            e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
            s += e * e
        return s

    @wp.func
    def _excluded(  # pragma: no cover - compiled by Warp
        k: wp.int64,
        bond_ij: wp.array(dtype=wp.int64),
        bond_ji: wp.array(dtype=wp.int64),
        intact: wp.array(dtype=wp.uint8),
    ) -> bool:
        """True when the pair of slot k is joined by an intact bond (either direction)."""
        b = bond_ij[k]
        if b >= wp.int64(0):
            if intact[b] != wp.uint8(0):
                return True
        b = bond_ji[k]
        if b >= wp.int64(0):
            if intact[b] != wp.uint8(0):
                return True
        return False

    @wp.func
    def _find_bond(  # pragma: no cover - compiled by Warp
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        key: wp.array(dtype=wp.int64),
        i: wp.int32,
        j: wp.int32,
    ) -> wp.int64:
        """Index of bond (i, j) in the CSR bond list (rows sorted by ``key``), or -1."""
        lo = offsets[i]
        end = offsets[i + 1]
        hi = end
        target = key[j]
        while lo < hi:
            mid = (lo + hi) // wp.int64(2)
            if key[bond_j[mid]] < target:
                lo = mid + wp.int64(1)
            else:
                hi = mid
        if lo < end:
            if bond_j[lo] == j:
                return lo
        return wp.int64(-1)

    @wp.kernel
    def contact_check(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        u_ref: wp.array2d(dtype=wp.float64),
        limit_sq: wp.float64,
        flag: wp.array(dtype=wp.int32),
    ) -> None:
        """``flag[0] = 1`` if some point moved by more than sqrt(limit_sq) since the last
        build, ``flag[1] = 1`` if some current position is not finite (``flag`` zeroed
        before; every writer writes the same value)."""
        i = wp.tid()
        s = wp.float64(0.0)
        bad = wp.int32(0)
        for c in range(x.shape[1]):
            a = u[i, c] - u_ref[i, c]
            s += a * a
            if not wp.isfinite(x[i, c] + u[i, c]):
                bad = wp.int32(1)
        if s > limit_sq:
            flag[0] = 1
        if bad != 0:
            flag[1] = 1

    @wp.kernel
    def contact_positions(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        pts: wp.array(dtype=wp.vec3d),
    ) -> None:
        """Current positions ``x + u``, padded with zero coordinates to 3-D."""
        i = wp.tid()
        p = wp.vec3d(wp.float64(0.0), wp.float64(0.0), wp.float64(0.0))
        for c in range(x.shape[1]):
            p[c] = x[i, c] + u[i, c]
        pts[i] = p

    @wp.kernel
    def contact_count(  # pragma: no cover - compiled by Warp
        grid: wp.uint64,
        pts: wp.array(dtype=wp.vec3d),
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        radius: wp.float64,
        cutoff_sq: wp.float64,
        counts: wp.array(dtype=wp.int64),
    ) -> None:
        """``counts[i]`` = points j != i with ``|y_j - y_i|^2 <= cutoff_sq`` (the grid
        query over cells of side ``radius`` >= the cutoff returns a superset)."""
        i = wp.tid()
        cnt = wp.int64(0)
        query = wp.hash_grid_query(grid, pts[i], radius)
        j = wp.int32(0)
        while wp.hash_grid_query_next(query, j):
            if j != i:
                if _dist_sq(x, u, i, j) <= cutoff_sq:
                    cnt += wp.int64(1)
        counts[i] = cnt

    @wp.kernel
    def contact_fill(  # pragma: no cover - compiled by Warp
        grid: wp.uint64,
        pts: wp.array(dtype=wp.vec3d),
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        radius: wp.float64,
        cutoff_sq: wp.float64,
        pair_offsets: wp.array(dtype=wp.int64),
        key: wp.array(dtype=wp.int64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        pair_j: wp.array(dtype=wp.int32),
        bond_ij: wp.array(dtype=wp.int64),
        bond_ji: wp.array(dtype=wp.int64),
    ) -> None:
        """Row i of the Verlet list counted by :func:`contact_count`, sorted by ``key``
        (the host's row order), with the index of bond (i, j) and of bond (j, i) (-1 when
        the two points are not bonded)."""
        i = wp.tid()
        lo = pair_offsets[i]
        p = lo
        query = wp.hash_grid_query(grid, pts[i], radius)
        j = wp.int32(0)
        while wp.hash_grid_query_next(query, j):
            if j != i:
                if _dist_sq(x, u, i, j) <= cutoff_sq:
                    pair_j[p] = wp.int32(j)
                    p += wp.int64(1)
        hi = pair_offsets[i + 1]
        k = lo + wp.int64(1)
        while k < hi:  # insertion sort by key: rows are short
            v = pair_j[k]
            m = k
            while m > lo:  # (Warp's `and` does not short-circuit: no m - 1 < lo read)
                w = pair_j[m - wp.int64(1)]
                if key[w] <= key[v]:
                    break
                pair_j[m] = w
                m -= wp.int64(1)
            pair_j[m] = v
            k += wp.int64(1)
        k = lo
        while k < hi:
            jj = pair_j[k]
            bond_ij[k] = _find_bond(offsets, bond_j, key, i, jj)
            bond_ji[k] = _find_bond(offsets, bond_j, key, jj, i)
            k += wp.int64(1)

    @wp.kernel
    def contact_force(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        volume: wp.array(dtype=wp.float64),
        pair_offsets: wp.array(dtype=wp.int64),
        pair_j: wp.array(dtype=wp.int32),
        bond_ij: wp.array(dtype=wp.int64),
        bond_ji: wp.array(dtype=wp.int64),
        intact: wp.array(dtype=wp.uint8),
        d_c: wp.float64,
        c_s: wp.float64,
        force: wp.array2d(dtype=wp.float64),
    ) -> None:
        """ADD ``-sum_j c_s (d_c - r) / d_c (y_j - y_i) / r V_j`` over row i (r < d_c,
        r > 0, no intact bond) to ``force[i]``."""
        i = wp.tid()
        dim = x.shape[1]
        dc_sq = d_c * d_c
        scale = c_s / d_c
        f0 = force[i, 0]
        f1 = wp.float64(0.0)
        f2 = wp.float64(0.0)
        if dim > 1:
            f1 = force[i, 1]
        if dim > 2:
            f2 = force[i, 2]
        k = pair_offsets[i]
        end = pair_offsets[i + 1]
        while k < end:
            j = pair_j[k]
            r2 = _dist_sq(x, u, i, j)
            if r2 < dc_sq and r2 != wp.float64(0.0):
                if not _excluded(k, bond_ij, bond_ji, intact):
                    r = wp.sqrt(r2)
                    g = scale * (d_c - r) / r * volume[j]
                    f0 -= g * ((x[j, 0] - x[i, 0]) + (u[j, 0] - u[i, 0]))
                    if dim > 1:
                        f1 -= g * ((x[j, 1] - x[i, 1]) + (u[j, 1] - u[i, 1]))
                    if dim > 2:
                        f2 -= g * ((x[j, 2] - x[i, 2]) + (u[j, 2] - u[i, 2]))
            k += wp.int64(1)
        force[i, 0] = f0
        if dim > 1:
            force[i, 1] = f1
        if dim > 2:
            force[i, 2] = f2

    @wp.kernel
    def contact_load(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        volume: wp.array(dtype=wp.float64),
        pair_offsets: wp.array(dtype=wp.int64),
        pair_j: wp.array(dtype=wp.int32),
        bond_ij: wp.array(dtype=wp.int64),
        bond_ji: wp.array(dtype=wp.int64),
        intact: wp.array(dtype=wp.uint8),
        d_c: wp.float64,
        c_s: wp.float64,
        load: wp.array(dtype=wp.float64),
    ) -> None:
        """Normal load ``L_i = V_i c_s / d_c sum_j (d_c - r) V_j`` (N) over the contacts
        of i with r > 0."""
        i = wp.tid()
        dc_sq = d_c * d_c
        acc = wp.float64(0.0)
        k = pair_offsets[i]
        end = pair_offsets[i + 1]
        while k < end:
            j = pair_j[k]
            r2 = _dist_sq(x, u, i, j)
            if r2 < dc_sq and r2 != wp.float64(0.0):
                if not _excluded(k, bond_ij, bond_ji, intact):
                    acc += (d_c - wp.sqrt(r2)) * volume[j]
            k += wp.int64(1)
        load[i] = volume[i] * c_s / d_c * acc

    @wp.kernel
    def contact_force_friction(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
        volume: wp.array(dtype=wp.float64),
        density: wp.array(dtype=wp.float64),
        pair_offsets: wp.array(dtype=wp.int64),
        pair_j: wp.array(dtype=wp.int32),
        bond_ij: wp.array(dtype=wp.int64),
        bond_ji: wp.array(dtype=wp.int64),
        intact: wp.array(dtype=wp.uint8),
        d_c: wp.float64,
        c_s: wp.float64,
        mu_s: wp.float64,
        mu_k: wp.float64,
        dt: wp.float64,
        load: wp.array(dtype=wp.float64),
        force: wp.array2d(dtype=wp.float64),
        power: wp.array(dtype=wp.float64),
    ) -> None:
        """ADD the contact force density with Coulomb friction to ``force[i]`` and write
        i's share of the friction power ``power[i]`` (W): the arithmetic of
        :func:`peridynamics.kernels.short_range_friction.add_contact_force_friction`."""
        i = wp.tid()
        dim = x.shape[1]
        dc_sq = d_c * d_c
        scale = c_s / d_c
        mi = density[i] * volume[i]
        pw = wp.float64(0.0)
        f = wp.vec3d(wp.float64(0.0), wp.float64(0.0), wp.float64(0.0))
        for c in range(dim):
            f[c] = force[i, c]
        k = pair_offsets[i]
        end = pair_offsets[i + 1]
        while k < end:
            j = pair_j[k]
            k += wp.int64(1)
            r2 = _dist_sq(x, u, i, j)
            if r2 >= dc_sq or r2 == wp.float64(0.0):
                continue
            if _excluded(k - wp.int64(1), bond_ij, bond_ji, intact):
                continue
            r = wp.sqrt(r2)
            g = scale * (d_c - r) / r * volume[j]
            s = wp.float64(0.0)  # (y_j - y_i) . (v_i - v_j)
            for c in range(dim):
                e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                f[c] = f[c] - g * e
                s += e * (v[i, c] - v[j, c])
            vt2 = wp.float64(0.0)
            for c in range(dim):
                e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                t = (v[i, c] - v[j, c]) - e * (s / r2)
                vt2 += t * t
            if vt2 == wp.float64(0.0):
                continue
            vt = wp.sqrt(vt2)
            fn = scale * (d_c - r)
            mj = density[j] * volume[j]
            m_ij = mi * mj / (mi + mj)
            l_ij = wp.max(load[i], load[j])
            a = mu_k * fn / vt
            if m_ij * vt <= mu_s * l_ij * dt:
                a = fn * m_ij / (dt * l_ij)
            for c in range(dim):
                e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                t = (v[i, c] - v[j, c]) - e * (s / r2)
                f[c] = f[c] - a * t * volume[j]
            pw -= wp.float64(0.5) * a * vt2 * volume[j]
        for c in range(dim):
            force[i, c] = f[c]
        power[i] = volume[i] * pw
