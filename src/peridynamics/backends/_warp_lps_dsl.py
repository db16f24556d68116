# mypy: ignore-errors
"""Warp kernels of the LPS (ordinary state-based linear peridynamic solid) passes of the
Warp backend: the dilatation pre-pass and the force pass of
:mod:`peridynamics.kernels.lps`, same notation and equations, one thread per point
gathering over its CSR family (each thread writes only its own rows: no atomics). The
dimension (2 or 3) is read from ``x.shape[1]``."""

from __future__ import annotations

from peridynamics.backends._warp_dsl import wp

if wp is not None:
    # no FMA contraction: the CUDA device then gives the CPU device's bits (and the
    # Numba kernels' decisions); see docs/gpu.md
    wp.set_module_options({"fuse_fp": False})

    @wp.func
    def lps_bond(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        i: wp.int32,
        j: wp.int32,
        length: wp.float64,
    ):
        """Deformed bond y (components past the dimension 0), its length r and the
        extension e = r - L evaluated as eta . (2 xi + eta) / (r + L)."""
        y0 = wp.float64(0.0)
        y1 = wp.float64(0.0)
        y2 = wp.float64(0.0)
        r2 = wp.float64(0.0)
        num = wp.float64(0.0)
        for c in range(x.shape[1]):
            xi = x[j, c] - x[i, c]
            eta = u[j, c] - u[i, c]
            y = xi + eta
            r2 += y * y
            num += eta * (xi + xi + eta)
            if c == 0:
                y0 = y
            elif c == 1:
                y1 = y
            else:
                y2 = y
        r = wp.sqrt(r2)
        return y0, y1, y2, r, num / (r + length)

    @wp.kernel
    def lps_dilatation(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        length: wp.array(dtype=wp.float64),
        wv: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        theta_scale: wp.array(dtype=wp.float64),
        theta: wp.array(dtype=wp.float64),
    ) -> None:
        """theta_i = ts_i sum_k mu_k wv_k L_k e_k."""
        i = wp.tid()
        acc = wp.float64(0.0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:  # int64 bond indices (range() takes int32)
            if intact[k] != wp.uint8(0):
                y0, y1, y2, r, e = lps_bond(x, u, i, bond_j[k], length[k])
                acc += wv[k] * length[k] * e
            k += wp.int64(1)
        theta[i] = theta_scale[i] * acc

    @wp.kernel
    def lps_force(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        length: wp.array(dtype=wp.float64),
        wv: wp.array(dtype=wp.float64),
        wvf: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        theta: wp.array(dtype=wp.float64),
        cd: wp.array(dtype=wp.float64),
        a: wp.array(dtype=wp.float64),
        force: wp.array2d(dtype=wp.float64),
    ) -> None:
        """f_i = sum_k mu_k ((wv_k cd_i theta_i + wvf_k cd_j theta_j) L_k
        + (wv_k a_i + wvf_k a_j) e_k) y_k / r_k (N/m^3), overwriting row i."""
        i = wp.tid()
        dim = x.shape[1]
        ci = cd[i] * theta[i]
        ai = a[i]
        f0 = wp.float64(0.0)
        f1 = wp.float64(0.0)
        f2 = wp.float64(0.0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            if intact[k] != wp.uint8(0):
                j = bond_j[k]
                y0, y1, y2, r, e = lps_bond(x, u, i, j, length[k])
                w_i = wv[k]
                w_j = wvf[k]
                t = (w_i * ci + w_j * cd[j] * theta[j]) * length[k] + (w_i * ai + w_j * a[j]) * e
                g = t / r
                f0 += g * y0
                f1 += g * y1
                f2 += g * y2
            k += wp.int64(1)
        force[i, 0] = f0
        if dim > 1:
            force[i, 1] = f1
        if dim > 2:
            force[i, 2] = f2
