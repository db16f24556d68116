# mypy: ignore-errors
"""Warp kernels of the halo exchange of a decomposed run
(:mod:`peridynamics.backends.warp_halo`): the rows other ranks hold as ghosts are
packed into one contiguous buffer, and the received ghost rows scattered back. Pure
copies: no arithmetic, so the exchanged values are the owners' bits."""

from __future__ import annotations

from peridynamics.backends._warp_dsl import wp

if wp is not None:
    wp.set_module_options({"fuse_fp": False})

    @wp.kernel
    def pack_rows(  # pragma: no cover - compiled by Warp
        rows: wp.array(dtype=wp.int32),
        u: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
        out: wp.array2d(dtype=wp.float64),
    ) -> None:
        t = wp.tid()
        i = rows[t]
        d = u.shape[1]
        for c in range(d):
            out[t, c] = u[i, c]
            out[t, d + c] = v[i, c]

    @wp.kernel
    def unpack_rows(  # pragma: no cover - compiled by Warp
        rows: wp.array(dtype=wp.int32),
        buf: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
    ) -> None:
        t = wp.tid()
        i = rows[t]
        d = u.shape[1]
        for c in range(d):
            u[i, c] = buf[t, c]
            v[i, c] = buf[t, d + c]
