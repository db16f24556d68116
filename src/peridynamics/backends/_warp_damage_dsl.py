# mypy: ignore-errors
"""Warp kernels of the bond-level damage passes of the Warp backend (critical-stretch
breaking without a force pass, the largest stretch, the damage reduction)."""

from __future__ import annotations

from peridynamics.backends._warp_dsl import wp

if wp is not None:
    # no FMA contraction: the CUDA device then gives the CPU device's bits (and the
    # Numba kernels' decisions); see docs/gpu.md
    wp.set_module_options({"fuse_fp": False})

    @wp.func
    def bond_stretch(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        i: wp.int32,
        j: wp.int32,
    ) -> wp.float64:
        """|x_j - x_i + u_j - u_i| / |x_j - x_i| - 1, squares summed in component order
        (the Numba kernels' order: both directions of a bond get the same bits)."""
        l2 = wp.float64(0.0)
        r2 = wp.float64(0.0)
        for c in range(x.shape[1]):
            d = x[j, c] - x[i, c]
            e = d + (u[j, c] - u[i, c])
            l2 += d * d
            r2 += e * e
        return wp.sqrt(r2) * (wp.float64(1.0) / wp.sqrt(l2)) - wp.float64(1.0)

    @wp.kernel
    def break_by_stretch(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        intact: wp.array(dtype=wp.uint8),
        s0: wp.array(dtype=wp.float64),
        broken: wp.array(dtype=wp.int64),
    ) -> None:
        i = wp.tid()
        nb = wp.int64(0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            if intact[k] != wp.uint8(0):
                j = bond_j[k]
                if bond_stretch(x, u, i, j) >= wp.float64(0.5) * (s0[i] + s0[j]):
                    intact[k] = wp.uint8(0)
                    nb += wp.int64(1)
            k += wp.int64(1)
        broken[i] = nb

    @wp.kernel
    def largest_stretch(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        intact: wp.array(dtype=wp.uint8),
        out: wp.array(dtype=wp.float64),
    ) -> None:
        i = wp.tid()
        m = wp.float64(0.0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            if intact[k] != wp.uint8(0):
                m = wp.max(m, bond_stretch(x, u, i, bond_j[k]))
            k += wp.int64(1)
        out[i] = m
