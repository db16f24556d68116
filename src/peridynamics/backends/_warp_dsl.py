# mypy: ignore-errors
"""The Warp kernel sources of :mod:`peridynamics.backends.warp_kernels` (Warp's
kernel language: its type annotations are calls, which static checkers do not read)."""

from __future__ import annotations

try:  # optional: pip install ".[gpu]"
    import warp as wp
except ImportError:  # pragma: no cover - exercised where warp-lang is absent
    wp = None


if wp is not None:
    # no FMA contraction: the CUDA device then gives the CPU device's bits (and the
    # Numba kernels' decisions); see docs/gpu.md
    wp.set_module_options({"fuse_fp": False})
    wp.config.quiet = True  # Warp < 1.19
    if hasattr(wp, "LOG_WARNING"):  # Warp >= 1.19: no banner, no module-load lines
        wp.config.log_level = wp.LOG_ERROR

    @wp.kernel
    def _pmb_force_break(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        stiffness: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        s0: wp.array(dtype=wp.float64),
        force: wp.array2d(dtype=wp.float64),
        nbroken: wp.array(dtype=wp.int64),
    ) -> None:
        i = wp.tid()
        dim = x.shape[1]
        nb = wp.int64(0)
        f0 = wp.float64(0.0)
        f1 = wp.float64(0.0)
        f2 = wp.float64(0.0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:  # int64 bond indices (range() takes int32)
            j = wp.int32(bond_j[k])
            l2 = wp.float64(0.0)
            r2 = wp.float64(0.0)
            e0 = wp.float64(0.0)
            e1 = wp.float64(0.0)
            e2 = wp.float64(0.0)
            for c in range(dim):
                d = x[j, c] - x[i, c]
                e = d + (u[j, c] - u[i, c])
                l2 += d * d
                r2 += e * e
                if c == 0:
                    e0 = e
                elif c == 1:
                    e1 = e
                else:
                    e2 = e
            r = wp.sqrt(r2)
            inv_l = wp.float64(1.0) / wp.sqrt(l2)
            if intact[k] != wp.uint8(0):
                if r * inv_l - wp.float64(1.0) >= wp.float64(0.5) * (s0[i] + s0[j]):
                    intact[k] = wp.uint8(0)
                    nb += wp.int64(1)
                else:
                    g = stiffness[k] * (inv_l - wp.float64(1.0) / r)
                    f0 += g * e0
                    f1 += g * e1
                    f2 += g * e2
            k += wp.int64(1)
        force[i, 0] = f0
        if dim > 1:
            force[i, 1] = f1
        if dim > 2:
            force[i, 2] = f2
        nbroken[i] = nb

    @wp.kernel
    def _damage(  # pragma: no cover - compiled by Warp
        offsets: wp.array(dtype=wp.int64),
        bond_volume: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        out: wp.array(dtype=wp.float64),
    ) -> None:
        i = wp.tid()
        total = wp.float64(0.0)
        lost = wp.float64(0.0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:  # (broken partial volume) / (partial volume): the Numba bits
            total += bond_volume[k]
            if intact[k] == wp.uint8(0):
                lost += bond_volume[k]
            k += wp.int64(1)
        out[i] = wp.float64(0.0)
        if total > wp.float64(0.0):
            out[i] = lost / total
