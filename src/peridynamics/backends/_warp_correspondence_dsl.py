# mypy: ignore-errors
"""Warp kernels of the correspondence (non-ordinary state-based) family of the Warp
backend: the force pass, and the trial / commit passes of the principal-stress failure
law. The pre-pass (force tensor, stabilisation, largest principal stress) is
:mod:`peridynamics.backends._warp_correspondence_prepass_dsl`.

Same notation, equations and operation order as the Numba kernels
(:mod:`peridynamics.kernels.correspondence`, :mod:`...correspondence_points`): sums run
over each family in CSR order. One thread per point gathering over its family; a thread
writes only its own rows and its own bonds (no atomics). The dimension (2 or 3) is read
from ``u.shape[1]``; tensors are (n, d*d) row-major arrays.
"""

from __future__ import annotations

from peridynamics.backends._warp_dsl import wp

if wp is not None:
    # no FMA contraction: the CUDA device then gives the CPU device's bits (and the
    # Numba kernels' decisions); see docs/gpu.md
    wp.set_module_options({"fuse_fp": False})
    from peridynamics.backends._warp_damage_dsl import bond_stretch

    wp.set_module_options({"enable_backward": False})

    @wp.kernel
    def corr_force(  # pragma: no cover - compiled by Warp
        bond_xi: wp.array2d(dtype=wp.float64),
        length: wp.array(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        wv: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        amat: wp.array2d(dtype=wp.float64),
        fgrad: wp.array2d(dtype=wp.float64),
        stab: wp.array(dtype=wp.float64),
        mode: wp.int32,
        force: wp.array2d(dtype=wp.float64),
        max_stretch: wp.array(dtype=wp.float64),
    ) -> None:
        """f_i = sum_k w_k ((A_i + A_j) xi + stabilisation pair term) and the largest
        (|y| - L) / L of an intact bond (0 if none is stretched): ``force`` of the
        Numba kernels."""
        i = wp.tid()
        d = u.shape[1]
        zero = wp.float64(0.0)
        f0 = zero
        f1 = zero
        f2 = zero
        smax = zero
        si = stab[i]
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            w = wv[k] * wp.float64(intact[k])
            if w != zero:
                j = bond_j[k]
                sj = stab[j]
                lk = length[k]
                x0 = bond_xi[k, 0]
                x1 = bond_xi[k, 1]
                y0 = x0 + u[j, 0] - u[i, 0]
                y1 = x1 + u[j, 1] - u[i, 1]
                t0 = zero
                t1 = zero
                t2 = zero
                r = zero
                if d == 2:
                    t0 = (amat[i, 0] + amat[j, 0]) * x0 + (amat[i, 1] + amat[j, 1]) * x1
                    t1 = (amat[i, 2] + amat[j, 2]) * x0 + (amat[i, 3] + amat[j, 3]) * x1
                    if mode != 0:
                        zi0 = y0 - fgrad[i, 0] * x0 - fgrad[i, 1] * x1
                        zi1 = y1 - fgrad[i, 2] * x0 - fgrad[i, 3] * x1
                        zj0 = y0 - fgrad[j, 0] * x0 - fgrad[j, 1] * x1
                        zj1 = y1 - fgrad[j, 2] * x0 - fgrad[j, 3] * x1
                        if mode == 1:
                            t0 += si * zi0 + sj * zj0
                            t1 += si * zi1 + sj * zj1
                        else:
                            g = (si * (x0 * zi0 + x1 * zi1) + sj * (x0 * zj0 + x1 * zj1)) / (
                                lk * lk * lk
                            )
                            t0 += g * x0
                            t1 += g * x1
                    r = wp.sqrt(y0 * y0 + y1 * y1)
                else:
                    x2 = bond_xi[k, 2]
                    y2 = x2 + u[j, 2] - u[i, 2]
                    for b in range(3):
                        xb = bond_xi[k, b]
                        t0 += (amat[i, b] + amat[j, b]) * xb
                        t1 += (amat[i, 3 + b] + amat[j, 3 + b]) * xb
                        t2 += (amat[i, 6 + b] + amat[j, 6 + b]) * xb
                    if mode != 0:
                        zi0 = y0
                        zi1 = y1
                        zi2 = y2
                        zj0 = y0
                        zj1 = y1
                        zj2 = y2
                        for b in range(3):
                            xb = bond_xi[k, b]
                            zi0 -= fgrad[i, b] * xb
                            zi1 -= fgrad[i, 3 + b] * xb
                            zi2 -= fgrad[i, 6 + b] * xb
                            zj0 -= fgrad[j, b] * xb
                            zj1 -= fgrad[j, 3 + b] * xb
                            zj2 -= fgrad[j, 6 + b] * xb
                        if mode == 1:
                            t0 += si * zi0 + sj * zj0
                            t1 += si * zi1 + sj * zj1
                            t2 += si * zi2 + sj * zj2
                        else:
                            g = (
                                si * (x0 * zi0 + x1 * zi1 + x2 * zi2)
                                + sj * (x0 * zj0 + x1 * zj1 + x2 * zj2)
                            ) / (lk * lk * lk)
                            t0 += g * x0
                            t1 += g * x1
                            t2 += g * x2
                    r = wp.sqrt(y0 * y0 + y1 * y1 + y2 * y2)
                f0 += w * t0
                f1 += w * t1
                f2 += w * t2
                st = (r - lk) / lk
                if st > smax:
                    smax = st
            k += wp.int64(1)
        force[i, 0] = f0
        force[i, 1] = f1
        if d == 3:
            force[i, 2] = f2
        max_stretch[i] = smax

    @wp.kernel
    def corr_propose(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        intact: wp.array(dtype=wp.uint8),
        s0: wp.array(dtype=wp.float64),
        stretch_on: wp.int32,
        s1: wp.array(dtype=wp.float64),
        tensile_strength: wp.float64,
        stress_on: wp.int32,
        keep: wp.array(dtype=wp.uint8),
        proposed: wp.array(dtype=wp.uint8),
        any_proposed: wp.array(dtype=wp.int32),
    ) -> None:
        """The trial of CorrespondenceFailureLaw before the degenerate rounds: an intact
        bond is proposed when its stretch reaches (s0_i + s0_j)/2 or (unprotected) the
        mean of its ends' largest principal stresses reaches f_t. ``any_proposed[0]``
        is set to 1 when some bond is (every writer writes 1)."""
        i = wp.tid()
        half = wp.float64(0.5)
        hit = wp.int32(0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            p = wp.uint8(0)
            if intact[k] != wp.uint8(0):
                j = bond_j[k]
                if stretch_on != 0:
                    if bond_stretch(x, u, i, j) >= half * (s0[i] + s0[j]):
                        p = wp.uint8(1)
                if stress_on != 0 and keep[k] == wp.uint8(0):
                    if half * (s1[i] + s1[j]) >= tensile_strength:
                        p = wp.uint8(1)
            proposed[k] = p
            if p != wp.uint8(0):
                hit = 1
            k += wp.int64(1)
        if hit != 0:
            any_proposed[0] = 1

    @wp.kernel
    def corr_degenerate(  # pragma: no cover - compiled by Warp
        bond_xi: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        wv: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        proposed: wp.array(dtype=wp.uint8),
        det_ref: wp.array(dtype=wp.float64),
        degenerate_ratio: wp.float64,
        any_proposed: wp.array(dtype=wp.int32),
        bad: wp.array(dtype=wp.uint8),
    ) -> None:
        """bad_i: the family left by the proposal (intact and not proposed) is degenerate,
        ``det K <= ratio det K_ref`` with det K_ref > 0, and still has bonds (the
        determinant of ``shape_determinant``); nothing is bad without a proposal."""
        i = wp.tid()
        bad[i] = wp.uint8(0)
        if any_proposed[0] == 0:
            return
        d = bond_xi.shape[1]
        zero = wp.float64(0.0)
        k00 = zero
        k01 = zero
        k02 = zero
        k11 = zero
        k12 = zero
        k22 = zero
        left = wp.int32(0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            after = wp.uint8(0)
            if intact[k] != wp.uint8(0) and proposed[k] == wp.uint8(0):
                after = wp.uint8(1)
                left += 1
            w = wv[k] * wp.float64(after)
            x0 = bond_xi[k, 0]
            x1 = bond_xi[k, 1]
            x2 = zero
            if d == 3:
                x2 = bond_xi[k, 2]
            k00 += w * x0 * x0
            k01 += w * x0 * x1
            k02 += w * x0 * x2
            k11 += w * x1 * x1
            k12 += w * x1 * x2
            k22 += w * x2 * x2
            k += wp.int64(1)
        det = zero
        if d == 2:
            det = k00 * k11 - k01 * k01
        else:
            det = (
                k00 * (k11 * k22 - k12 * k12)
                - k01 * (k01 * k22 - k12 * k02)
                + k02 * (k01 * k12 - k11 * k02)
            )
        if not (det > degenerate_ratio * det_ref[i]) and det_ref[i] > zero and left > 0:
            bad[i] = wp.uint8(1)

    @wp.kernel
    def corr_spread(  # pragma: no cover - compiled by Warp
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        intact: wp.array(dtype=wp.uint8),
        bad: wp.array(dtype=wp.uint8),
        proposed: wp.array(dtype=wp.uint8),
    ) -> None:
        """Propose every intact bond with a degenerate end."""
        i = wp.tid()
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            if intact[k] != wp.uint8(0):
                if bad[i] != wp.uint8(0) or bad[bond_j[k]] != wp.uint8(0):
                    proposed[k] = wp.uint8(1)
            k += wp.int64(1)

    @wp.kernel
    def corr_commit(  # pragma: no cover - compiled by Warp
        offsets: wp.array(dtype=wp.int64),
        proposed: wp.array(dtype=wp.uint8),
        intact: wp.array(dtype=wp.uint8),
        broken: wp.array(dtype=wp.int64),
    ) -> None:
        """Break the proposed bonds (all intact), their count per point into ``broken``."""
        i = wp.tid()
        nb = wp.int64(0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            if proposed[k] != wp.uint8(0):
                intact[k] = wp.uint8(0)
                nb += wp.int64(1)
            k += wp.int64(1)
        broken[i] = nb
