# mypy: ignore-errors
"""Warp kernels of :mod:`peridynamics.backends.warp_energy`: the point strain-energy
density W_i (J/m^3) of the force models on the device, so that an energy history copies
n floats back instead of the displacement and the bond flags.

One thread per point gathering over its CSR family (int64 bond indices), float64
throughout; a thread writes only its own row (no atomics). Each kernel follows the
arithmetic order of the host's exact (no fast-math) Numba kernel, broken bonds
included through the factor ``mu_k`` (0 or 1) as on the host:

* PMB: :func:`peridynamics.kernels.bond_based.strain_energy_density`;
* LPS: :func:`peridynamics.kernels.lps.energy_density_2d` / ``_3d`` (the dilatation
  recomputed from ``u``);
* correspondence: ``active_i W(F_i)`` of the law's NumPy ``energy_density`` plus
  :func:`peridynamics.kernels.correspondence.stabilization_energy`, F and the
  stabilisation coefficient from the device pre-pass
  (:data:`peridynamics.backends._warp_correspondence_prepass_dsl.corr_prepass`).
"""

from __future__ import annotations

from peridynamics.backends._warp_dsl import wp

if wp is not None:
    # no FMA contraction: the CUDA device then gives the CPU device's bits (and the
    # Numba kernels' decisions); see docs/gpu.md
    wp.set_module_options({"fuse_fp": False})
    from peridynamics.backends._warp_lps_dsl import lps_bond

    wp.set_module_options({"enable_backward": False})

    @wp.kernel
    def pmb_energy_density(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        stiffness: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        out: wp.array(dtype=wp.float64),
    ) -> None:
        """W_i = 1/4 sum_k stiffness_k mu_k s_k^2 |xi_k|, s = (r - L) / L, with r and L
        from the squares summed in component order (``_lengths`` of the host)."""
        i = wp.tid()
        dim = x.shape[1]
        w = wp.float64(0.0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:  # int64 bond indices (range() takes int32)
            j = wp.int32(bond_j[k])
            r2 = wp.float64(0.0)
            l2 = wp.float64(0.0)
            for c in range(dim):
                d = x[j, c] - x[i, c]
                e = d + (u[j, c] - u[i, c])
                l2 += d * d
                r2 += e * e
            r = wp.sqrt(r2)
            length = wp.sqrt(l2)
            s = (r - length) / length
            w += stiffness[k] * wp.float64(intact[k]) * s * s * length
            k += wp.int64(1)
        out[i] = wp.float64(0.25) * w

    @wp.kernel
    def lps_energy_density(  # pragma: no cover - compiled by Warp
        x: wp.array2d(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        length: wp.array(dtype=wp.float64),
        wv: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        theta_scale: wp.array(dtype=wp.float64),
        k_theta: wp.float64,
        a: wp.array(dtype=wp.float64),
        out: wp.array(dtype=wp.float64),
    ) -> None:
        """W_i = k_theta theta_i^2 / 2 + (a_i / 2) sum_k mu_k wv_k e_k^2 with
        theta_i = ts_i sum_k mu_k wv_k L_k e_k recomputed from ``u``."""
        i = wp.tid()
        th = wp.float64(0.0)
        w = wp.float64(0.0)
        k = offsets[i]
        end = offsets[i + 1]
        while k < end:
            y0, y1, y2, r, e = lps_bond(x, u, i, bond_j[k], length[k])
            q = wp.float64(intact[k]) * wv[k]
            th += q * length[k] * e
            w += q * e * e
            k += wp.int64(1)
        th *= theta_scale[i]
        out[i] = wp.float64(0.5) * (k_theta * th * th + a[i] * w)

    @wp.kernel
    def corr_energy_density(  # pragma: no cover - compiled by Warp
        bond_xi: wp.array2d(dtype=wp.float64),
        length: wp.array(dtype=wp.float64),
        u: wp.array2d(dtype=wp.float64),
        offsets: wp.array(dtype=wp.int64),
        bond_j: wp.array(dtype=wp.int32),
        wv: wp.array(dtype=wp.float64),
        intact: wp.array(dtype=wp.uint8),
        fgrad: wp.array2d(dtype=wp.float64),
        stab: wp.array(dtype=wp.float64),
        active: wp.array(dtype=wp.float64),
        mode: wp.int32,
        lame: wp.float64,
        shear: wp.float64,
        law: wp.int32,
        out: wp.array(dtype=wp.float64),
    ) -> None:
        """W_i = active_i (lambda' tr(E)^2 / 2 + mu E:E) + stabilisation energy, with E the
        Green strain (F^T F - I) / 2 (``law`` 0, St Venant-Kirchhoff) or sym(F - I)
        (``law`` 1, linear elastic); F (n, d*d) row-major, 1 on a degenerate point's
        diagonal. Stabilisation: Silling ``stab_i / 2 sum_k w_k |z_ik|^2``, LBSCMM
        ``stab_i / 2 sum_k w_k (xi . z_ik)^2 / L^3``, z_ik = y_k - F_i xi_k."""
        i = wp.tid()
        d = u.shape[1]
        zero = wp.float64(0.0)
        half = wp.float64(0.5)
        one = wp.float64(1.0)
        tr = zero
        ee = zero
        for a in range(d):
            for b in range(d):
                e = zero
                if law == 0:
                    for c in range(d):
                        e += fgrad[i, c * d + a] * fgrad[i, c * d + b]
                    if a == b:
                        e -= one
                    e = half * e
                else:
                    hab = fgrad[i, a * d + b]
                    hba = fgrad[i, b * d + a]
                    if a == b:
                        hab -= one
                        hba -= one
                    e = half * (hab + hba)
                if a == b:
                    tr += e
                ee += e * e
        w_law = active[i] * (half * lame * tr * tr + shear * ee)
        acc = zero
        if mode != 0:
            k = offsets[i]
            end = offsets[i + 1]
            while k < end:
                w = wv[k] * wp.float64(intact[k])
                if w != zero:
                    j = bond_j[k]
                    zz = zero
                    xz = zero
                    for a in range(d):
                        za = bond_xi[k, a] + u[j, a] - u[i, a]
                        for b in range(d):
                            za -= fgrad[i, a * d + b] * bond_xi[k, b]
                        zz += za * za
                        xz += bond_xi[k, a] * za
                    if mode == 1:
                        acc += w * zz
                    else:
                        lk = length[k]
                        acc += w * xz * xz / (lk * lk * lk)
                k += wp.int64(1)
        out[i] = w_law + half * stab[i] * acc
