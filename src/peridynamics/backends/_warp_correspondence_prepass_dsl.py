# mypy: ignore-errors
"""Warp pre-pass kernel of the correspondence (non-ordinary state-based) family of the
Warp backend: shape tensor, deformation gradient, LBSCMM sigma^s, force tensor
A = (P - sigma^s) K^-1, stabilisation coefficient and largest principal Cauchy stress
per point. The force pass and the failure-law passes are
:mod:`peridynamics.backends._warp_correspondence_dsl`.

Same notation, equations and operation order as the Numba kernels
(:mod:`peridynamics.kernels.correspondence`, :mod:`...correspondence_points`): the 2 x 2
and 3 x 3 inverses are the cofactor forms of ``invert_in_place``, sums run over each
family in CSR order. One thread per point gathering over its family; a thread writes
only its own rows (no atomics). The dimension (2 or 3) is read from ``u.shape[1]``;
tensors are (n, d*d) row-major arrays, local 3 x 3 matrices whose unused row and column
stay zero in 2-D.
"""

from __future__ import annotations

from peridynamics.backends._warp_dsl import wp

if wp is not None:
    # no FMA contraction: the CUDA device then gives the CPU device's bits (and the
    # Numba kernels' decisions); see docs/gpu.md
    wp.set_module_options({"fuse_fp": False})
    wp.set_module_options({"enable_backward": False})

    #: the symmetric (6 x 6, upper triangle) moment matrix of the LBSCMM pre-pass
    mat66d = wp.types.matrix(shape=(6, 6), dtype=wp.float64)
    vec6d = wp.types.vector(length=6, dtype=wp.float64)

    @wp.func
    def _products(x0: wp.float64, x1: wp.float64, x2: wp.float64, d: wp.int32):
        """p = (xi_a xi_b)_{a <= b}: 2-D xx, yy, xy; 3-D xx, yy, zz, xy, xz, yz."""
        p = vec6d()
        if d == 2:
            p[0] = x0 * x0
            p[1] = x1 * x1
            p[2] = x0 * x1
        else:
            p[0] = x0 * x0
            p[1] = x1 * x1
            p[2] = x2 * x2
            p[3] = x0 * x1
            p[4] = x0 * x2
            p[5] = x1 * x2
        return p

    @wp.func
    def _sym_h(h: wp.mat33d, d: wp.int32):
        """h = (H_aa, H_ab + H_ba for a < b) in the order of :func:`_products`."""
        v = vec6d()
        if d == 2:
            v[0] = h[0, 0]
            v[1] = h[1, 1]
            v[2] = h[0, 1] + h[1, 0]
        else:
            v[0] = h[0, 0]
            v[1] = h[1, 1]
            v[2] = h[2, 2]
            v[3] = h[0, 1] + h[1, 0]
            v[4] = h[0, 2] + h[2, 0]
            v[5] = h[1, 2] + h[2, 1]
        return v

    @wp.func
    def _largest_eig3(a: wp.mat33d) -> wp.float64:
        """Largest eigenvalue of a symmetric 3 x 3 matrix by cyclic Jacobi rotations
        (backward stable: absolute error ~ eps |a|, as LAPACK's eigvalsh)."""
        zero = wp.float64(0.0)
        one = wp.float64(1.0)
        sweep = wp.int32(0)
        while sweep < 30:
            off = a[0, 1] * a[0, 1] + a[0, 2] * a[0, 2] + a[1, 2] * a[1, 2]
            dia = a[0, 0] * a[0, 0] + a[1, 1] * a[1, 1] + a[2, 2] * a[2, 2]
            if off <= wp.float64(1e-40) * dia or off == zero:
                break
            for pair in range(3):
                p = wp.int32(0)
                q = wp.int32(1)
                if pair == 1:
                    q = 2
                elif pair == 2:
                    p = 1
                    q = 2
                apq = a[p, q]
                if apq != zero:
                    theta = (a[q, q] - a[p, p]) / (apq + apq)
                    t = one / (wp.abs(theta) + wp.sqrt(theta * theta + one))
                    if theta < zero:
                        t = -t
                    c = one / wp.sqrt(t * t + one)
                    s = t * c
                    # a <- J^T a J with the rotation J in the (p, q) plane
                    for r in range(3):
                        arp = a[r, p]
                        arq = a[r, q]
                        a[r, p] = c * arp - s * arq
                        a[r, q] = s * arp + c * arq
                    for r in range(3):
                        apr = a[p, r]
                        aqr = a[q, r]
                        a[p, r] = c * apr - s * aqr
                        a[q, r] = s * apr + c * aqr
                    a[p, q] = zero
                    a[q, p] = zero
            sweep += 1
        return wp.max(a[0, 0], wp.max(a[1, 1], a[2, 2]))

    @wp.kernel
    def corr_prepass(  # pragma: no cover - compiled by Warp
        bond_xi: wp.array2d(dtype=wp.float64),
        length: wp.array(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        wv: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        det_ref: wp.array(dtype=wp.float64),
        degenerate_ratio: wp.float64,
        mode: wp.int32,
        stab_base: wp.array(dtype=wp.float64),
        silling_gc: wp.float64,
        lame: wp.float64,
        shear: wp.float64,
        law: wp.int32,
        want_s1: wp.int32,
        fgrad: wp.array2d(dtype=wp.float64),
        amat: wp.array2d(dtype=wp.float64),
        stab: wp.array(dtype=wp.float64),
        active: wp.array(dtype=wp.float64),
        s1: wp.array(dtype=wp.float64),
    ) -> None:
        """F_i, A_i = (P_i - sigma^s_i) K_i^-1, the stabilisation coefficient, the
        active flag and (``want_s1``) the largest principal Cauchy stress of point i:
        ``prepass`` + ``force_tensor`` + ``_stabilization`` (+ ``max_principal_stress``)
        of the host model. A degenerate family gets F = I, A = 0, stab = 0, active = 0,
        s1 = 0."""
        i = wp.tid()
        d = u.shape[1]
        m = 3
        if d == 3:
            m = 6
        zero = wp.float64(0.0)
        one = wp.float64(1.0)
        half = wp.float64(0.5)
        kmat = wp.mat33d()  # K (symmetric)
        nmat = wp.mat33d()  # N' = sum w eta (x) xi
        tvec = vec6d()  # LBSCMM sum_k (w/L^3) (xi . eta) p_k
        mmat = mat66d()  # LBSCMM sum_k (w/L^3) p_k (x) p_k, upper triangle
        om = zero
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            w = wv[k] * wp.float64(intact[k])
            if w != zero:
                j = bond_j[k]
                om += w
                x0 = bond_xi[k, 0]
                x1 = bond_xi[k, 1]
                x2 = zero
                e0 = u[j, 0] - u[i, 0]
                e1 = u[j, 1] - u[i, 1]
                e2 = zero
                if d == 3:
                    x2 = bond_xi[k, 2]
                    e2 = u[j, 2] - u[i, 2]
                kmat[0, 0] += w * x0 * x0
                kmat[1, 1] += w * x1 * x1
                kmat[0, 1] += w * x0 * x1
                nmat[0, 0] += w * e0 * x0
                nmat[0, 1] += w * e0 * x1
                nmat[1, 0] += w * e1 * x0
                nmat[1, 1] += w * e1 * x1
                if d == 3:
                    kmat[2, 2] += w * x2 * x2
                    kmat[0, 2] += w * x0 * x2
                    kmat[1, 2] += w * x1 * x2
                    nmat[0, 2] += w * e0 * x2
                    nmat[1, 2] += w * e1 * x2
                    nmat[2, 0] += w * e2 * x0
                    nmat[2, 1] += w * e2 * x1
                    nmat[2, 2] += w * e2 * x2
                if mode == 2:
                    lk = length[k]
                    wl = w / (lk * lk * lk)
                    q = zero
                    if d == 2:
                        q = wl * (x0 * e0 + x1 * e1)
                    else:
                        q = wl * (x0 * e0 + x1 * e1 + x2 * e2)
                    p = _products(x0, x1, x2, d)
                    for r in range(m):
                        tvec[r] += q * p[r]
                    for r in range(m):
                        g = wl * p[r]
                        for c in range(r, m):
                            mmat[r, c] += g * p[c]
            k += wp.int64(1)
        # K^-1 as invert_in_place: det > 0 inverts, else the family is degenerate
        kinv = wp.mat33d()
        det = zero
        if d == 2:
            q00 = kmat[0, 0]
            q01 = kmat[0, 1]
            q11 = kmat[1, 1]
            det = q00 * q11 - q01 * q01
            if det > zero:
                s = one / det
                kinv[0, 0] = q11 * s
                kinv[0, 1] = -q01 * s
                kinv[1, 0] = -q01 * s
                kinv[1, 1] = q00 * s
        else:
            a00 = kmat[0, 0]
            a01 = kmat[0, 1]
            a02 = kmat[0, 2]
            a11 = kmat[1, 1]
            a12 = kmat[1, 2]
            a22 = kmat[2, 2]
            # the lower triangle equals the upper one (K symmetric)
            a10 = a01
            a20 = a02
            a21 = a12
            c00 = a11 * a22 - a12 * a21
            c01 = a12 * a20 - a10 * a22
            c02 = a10 * a21 - a11 * a20
            det = a00 * c00 + a01 * c01 + a02 * c02
            if det > zero:
                s = one / det
                kinv[0, 0] = c00 * s
                kinv[1, 0] = c01 * s
                kinv[2, 0] = c02 * s
                kinv[0, 1] = (a02 * a21 - a01 * a22) * s
                kinv[1, 1] = (a00 * a22 - a02 * a20) * s
                kinv[2, 1] = (a01 * a20 - a00 * a21) * s
                kinv[0, 2] = (a01 * a12 - a02 * a11) * s
                kinv[1, 2] = (a02 * a10 - a00 * a12) * s
                kinv[2, 2] = (a00 * a11 - a01 * a10) * s
        if not (det > degenerate_ratio * det_ref[i]) or not (det > zero):
            for a in range(d):
                for b in range(d):
                    fgrad[i, a * d + b] = zero
                    amat[i, a * d + b] = zero
                fgrad[i, a * d + a] = one
            stab[i] = zero
            active[i] = zero
            s1[i] = zero
            return
        # H = N' K^-1 row by row
        hmat = wp.mat33d()
        for a in range(d):
            r0 = nmat[a, 0]
            r1 = nmat[a, 1]
            r2 = nmat[a, 2]
            for b in range(d):
                v = r0 * kinv[0, b] + r1 * kinv[1, b]
                if d == 3:
                    v += r2 * kinv[2, b]
                hmat[a, b] = v
        sig_s = wp.mat33d()
        if mode == 2:
            sb = stab_base[i]
            h = _sym_h(hmat, d)
            for r in range(m):
                t = zero
                if d == 2:
                    acc = zero
                    for c in range(m):
                        mm = mmat[c, r]
                        if c >= r:
                            mm = mmat[r, c]
                        acc += mm * h[c]
                    t = tvec[r] - acc
                else:
                    t = tvec[r]
                    for c in range(m):
                        mm = mmat[c, r]
                        if c >= r:
                            mm = mmat[r, c]
                        t -= mm * h[c]
                v = sb * t
                if d == 2:
                    if r == 0:
                        sig_s[0, 0] = v
                    elif r == 1:
                        sig_s[1, 1] = v
                    else:
                        sig_s[0, 1] = v
                        sig_s[1, 0] = v
                else:
                    if r < 3:
                        sig_s[r, r] = v
                    elif r == 3:
                        sig_s[0, 1] = v
                        sig_s[1, 0] = v
                    elif r == 4:
                        sig_s[0, 2] = v
                        sig_s[2, 0] = v
                    else:
                        sig_s[1, 2] = v
                        sig_s[2, 1] = v
        f = hmat
        for a in range(d):
            f[a, a] += one
        # the stress law of force_tensor: S (SVK, Green strain) or sigma (linear)
        strain = wp.mat33d()
        tr = zero
        for a in range(d):
            for b in range(d):
                e = zero
                if law == 0:
                    for c in range(d):
                        e += f[c, a] * f[c, b]
                    e *= half
                else:
                    e = half * (f[a, b] + f[b, a])
                if a == b:
                    if law == 0:
                        e -= half
                    else:
                        e -= one
                    tr += e
                strain[a, b] = e
        two_mu = wp.float64(2.0) * shear
        for a in range(d):
            for b in range(d):
                strain[a, b] *= two_mu
            strain[a, a] += lame * tr
        piola = wp.mat33d()
        for a in range(d):
            for b in range(d):
                pv = zero
                if law == 0:
                    for c in range(d):
                        pv += f[a, c] * strain[c, b]
                else:
                    pv = strain[a, b]
                piola[a, b] = pv
        for a in range(d):
            r0 = piola[a, 0] - sig_s[a, 0]
            r1 = piola[a, 1] - sig_s[a, 1]
            r2 = piola[a, 2] - sig_s[a, 2]
            for b in range(d):
                v = r0 * kinv[0, b] + r1 * kinv[1, b]
                if d == 3:
                    v += r2 * kinv[2, b]
                amat[i, a * d + b] = v
            for b in range(d):
                fgrad[i, a * d + b] = f[a, b]
        active[i] = one
        if mode == 1:
            stab[i] = zero
            if om > zero:
                stab[i] = silling_gc / om
        elif mode == 2:
            stab[i] = stab_base[i]
        else:
            stab[i] = zero
        if want_s1 != 0:
            # Cauchy sigma = P F^T / det F (det F <= 0: / 1), its symmetric part
            jac = zero
            if d == 2:
                jac = f[0, 0] * f[1, 1] - f[0, 1] * f[1, 0]
            else:
                jac = wp.determinant(f)
            if not (jac > zero):
                jac = one
            sig = wp.mat33d()
            for a in range(d):
                for c in range(d):
                    acc = zero
                    for b in range(d):
                        acc += piola[a, b] * f[c, b]
                    sig[a, c] = acc / jac
            sym = half * (sig + wp.transpose(sig))
            if d == 2:
                sa = sym[0, 0]
                sbb = sym[1, 1]
                sc = sym[0, 1]
                s1[i] = half * (sa + sbb) + wp.sqrt(
                    wp.float64(0.25) * (sa - sbb) * (sa - sbb) + sc * sc
                )
            else:
                s1[i] = _largest_eig3(sym)
