# mypy: ignore-errors
"""The Warp kernel sources of :mod:`peridynamics.backends.warp_extras`: viscous bond
forces (twin of :func:`peridynamics.kernels.viscous.add_viscous_force`) and SED
softening of the PMB bond stiffness (twins of :mod:`peridynamics.kernels.sed`).

Thread per point over its CSR family (int64 bond indices), float64 throughout; every
kernel writes only its own point's data, so no atomics."""

from __future__ import annotations

from peridynamics.backends._warp_dsl import wp

if wp is not None:
    # no FMA contraction: the CUDA device then gives the CPU device's bits (and the
    # Numba kernels' decisions); see docs/gpu.md
    wp.set_module_options({"fuse_fp": False})

    @wp.kernel
    def _viscous_add(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        v: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        inv_length: wp.array(dtype=wp.float64),
        weight: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        lin: wp.float64,
        quad: wp.float64,
        force: wp.array2d(dtype=wp.float64),
    ) -> None:
        """force[i] += sum_k weight_k mu_k (lin zeta + quad zeta |zeta|) n_k, with the
        arithmetic order of the Numba kernel."""
        i = wp.tid()
        d = x.shape[1]
        a0 = wp.float64(0.0)
        a1 = wp.float64(0.0)
        a2 = wp.float64(0.0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            q = k
            k += wp.int64(1)
            if intact[q] == wp.uint8(0):
                continue
            j = wp.int32(bond_j[q])
            e0 = (x[j, 0] - x[i, 0]) + (u[j, 0] - u[i, 0])
            e1 = wp.float64(0.0)
            e2 = wp.float64(0.0)
            r2 = e0 * e0
            rate = (v[j, 0] - v[i, 0]) * e0
            if d > 1:
                e1 = (x[j, 1] - x[i, 1]) + (u[j, 1] - u[i, 1])
                r2 += e1 * e1
            if d > 2:
                e2 = (x[j, 2] - x[i, 2]) + (u[j, 2] - u[i, 2])
                r2 += e2 * e2
            if r2 == wp.float64(0.0):
                continue
            inv_r = wp.float64(1.0) / wp.sqrt(r2)
            if d > 1:
                rate += (v[j, 1] - v[i, 1]) * e1
            if d > 2:
                rate += (v[j, 2] - v[i, 2]) * e2
            zeta = rate * inv_r * inv_length[q]
            f = weight[q] * (lin * zeta + quad * zeta * wp.abs(zeta)) * inv_r
            a0 += f * e0
            a1 += f * e1
            a2 += f * e2
        force[i, 0] += a0
        if d > 1:
            force[i, 1] += a1
        if d > 2:
            force[i, 2] += a2

    @wp.func
    def _sed_factor(lv: wp.int64, n_levels: wp.int64, residual: wp.float64) -> wp.float64:
        """E_i / E of level ``lv``: 1 (0), (N + 1 - lv) / N (1..N), residual (N + 1)."""
        if lv == wp.int64(0):
            return wp.float64(1.0)
        if lv == n_levels + wp.int64(1):
            return residual
        return wp.float64(n_levels + wp.int64(1) - lv) / wp.float64(n_levels)

    @wp.kernel
    def _sed_levels(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        stiffness0: wp.array(dtype=wp.float64),
        length: wp.array(dtype=wp.float64),
        k0l: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        w_a: wp.array(dtype=wp.float64),
        w_c: wp.array(dtype=wp.float64),
        n_levels: wp.int64,
        residual: wp.float64,
        tensile: wp.int32,
        fused_form: wp.int32,
        level: wp.array(dtype=wp.int64),
        energy: wp.array(dtype=wp.float64),
        raised: wp.array(dtype=wp.uint8),
        factor: wp.array(dtype=wp.float64),
    ) -> None:
        """energy[i] (SED-PD eq. 22, initial stiffness, intact bonds; stretched ones only
        with ``tensile``), the level raised to that of the energy (irreversible),
        ``raised`` flags and the factor of the raised points. ``fused_form``: the
        arithmetic of the host's 2-D fused pass (sum k0l s^2, s = r / |xi| - 1), else
        that of ``sed_update`` (1/4 sum stiffness0 s^2 |xi|, s = r / |xi| - 1)."""
        i = wp.tid()
        d = x.shape[1]
        w = wp.float64(0.0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            q = k
            k += wp.int64(1)
            if intact[q] == wp.uint8(0):
                continue
            j = wp.int32(bond_j[q])
            r2 = wp.float64(0.0)
            l2 = wp.float64(0.0)
            for c in range(d):
                dd = x[j, c] - x[i, c]
                e = dd + (u[j, c] - u[i, c])
                l2 += dd * dd
                r2 += e * e
            s = wp.float64(0.0)
            if fused_form != 0:
                s = wp.sqrt(r2) * (wp.float64(1.0) / wp.sqrt(l2)) - wp.float64(1.0)
            else:
                s = wp.sqrt(r2) / length[q] - wp.float64(1.0)
            if tensile != 0 and s <= wp.float64(0.0):
                continue
            if fused_form != 0:
                w += k0l[q] * s * s
            else:
                w += stiffness0[q] * s * s * length[q]
        if fused_form == 0:
            w *= wp.float64(0.25)
        energy[i] = w
        new = wp.int64(0)
        if w < w_a[i]:
            new = wp.int64(0)
        elif w < w_c[i]:
            band = wp.int64(wp.floor(wp.float64(n_levels) * (w - w_a[i]) / (w_c[i] - w_a[i])))
            new = wp.min(wp.int64(1) + band, n_levels)
        else:
            new = n_levels + wp.int64(1)
        if new > level[i]:
            level[i] = new
            raised[i] = wp.uint8(1)
            factor[i] = _sed_factor(new, n_levels, residual)
        else:
            raised[i] = wp.uint8(0)

    @wp.kernel
    def _sed_factor_all(  # pragma: no cover - compiled by Warp
        level: wp.array(dtype=wp.int64),
        n_levels: wp.int64,
        residual: wp.float64,
        factor: wp.array(dtype=wp.float64),
    ) -> None:
        """factor[i] from level[i] for every point (restore)."""
        i = wp.tid()
        factor[i] = _sed_factor(level[i], n_levels, residual)

    @wp.kernel
    def _sed_stiffness(  # pragma: no cover - compiled by Warp
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        stiffness0: wp.array(dtype=wp.float64),
        factor: wp.array(dtype=wp.float64),
        raised: wp.array(dtype=wp.uint8),
        every: wp.int32,
        stiffness: wp.array(dtype=wp.float64),
    ) -> None:
        """stiffness_k = stiffness0_k (factor_i + factor_j) / 2 for the bonds of point i
        whose end i or j rose (``every``: all bonds)."""
        i = wp.tid()
        own = every != 0 or raised[i] != wp.uint8(0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            j = wp.int32(bond_j[k])
            if own or raised[j] != wp.uint8(0):
                stiffness[k] = stiffness0[k] * wp.float64(0.5) * (factor[i] + factor[j])
            k += wp.int64(1)
