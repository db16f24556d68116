"""Per-point correspondence kernels: the shape-tensor determinant, the in-place 2 x 2 /
3 x 3 inverse and the force tensor A = (P - sigma^s) K^-1 of the built-in stress laws.
The bond kernels are :mod:`peridynamics.kernels.correspondence` (which re-exports
these); NumPy twins in :mod:`peridynamics.kernels.reference_correspondence` and the
laws' NumPy interface (:mod:`peridynamics.families.correspondence.material`).
"""

from __future__ import annotations

from numba import njit, prange

#: hot loops: fast-math lets LLVM vectorise
_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
#: reference quantities: no fast-math, reproducible bits
_exact = njit(parallel=True, fastmath=False, cache=True)


@njit
def invert_in_place(m, i, d):
    """Invert the (d, d) block m[i] in place (d = 2 or 3); returns its determinant.

    A plain ``njit`` function (LLVM inlines it): Numba-level inlining made the cold
    compile of the pre-pass about 0.8 s (10 %) longer."""
    if d == 2:
        a, b, c, e = m[i, 0, 0], m[i, 0, 1], m[i, 1, 0], m[i, 1, 1]
        det = a * e - b * c
        if det > 0.0:
            s = 1.0 / det
            m[i, 0, 0] = e * s
            m[i, 0, 1] = -b * s
            m[i, 1, 0] = -c * s
            m[i, 1, 1] = a * s
        return det
    a00, a01, a02 = m[i, 0, 0], m[i, 0, 1], m[i, 0, 2]
    a10, a11, a12 = m[i, 1, 0], m[i, 1, 1], m[i, 1, 2]
    a20, a21, a22 = m[i, 2, 0], m[i, 2, 1], m[i, 2, 2]
    c00 = a11 * a22 - a12 * a21
    c01 = a12 * a20 - a10 * a22
    c02 = a10 * a21 - a11 * a20
    det = a00 * c00 + a01 * c01 + a02 * c02
    if det > 0.0:
        s = 1.0 / det
        m[i, 0, 0] = c00 * s
        m[i, 1, 0] = c01 * s
        m[i, 2, 0] = c02 * s
        m[i, 0, 1] = (a02 * a21 - a01 * a22) * s
        m[i, 1, 1] = (a00 * a22 - a02 * a20) * s
        m[i, 2, 1] = (a01 * a20 - a00 * a21) * s
        m[i, 0, 2] = (a01 * a12 - a02 * a11) * s
        m[i, 1, 2] = (a02 * a10 - a00 * a12) * s
        m[i, 2, 2] = (a00 * a11 - a01 * a10) * s
    return det


@_exact
def shape_determinant(bond_xi, offsets, wv, intact, out):
    """det K_i of every family (m^(5 d)), shape (n,): the reference against which a
    damaged family is judged degenerate.

    Parameters
    ----------
    bond_xi : (n_bonds, d) reference bonds (m).
    offsets : (n + 1,) CSR offsets.
    wv : (n_bonds,) partial volume beta_k V_j (m^3).
    intact : (n_bonds,) uint8.
    out : (>= n,) output.
    """
    n = offsets.shape[0] - 1
    d = bond_xi.shape[1]
    for i in prange(n):
        k00 = 0.0
        k01 = 0.0
        k02 = 0.0
        k11 = 0.0
        k12 = 0.0
        k22 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            w = wv[k] * intact[k]
            x0 = bond_xi[k, 0]
            x1 = bond_xi[k, 1]
            x2 = bond_xi[k, 2] if d == 3 else 0.0
            k00 += w * x0 * x0
            k01 += w * x0 * x1
            k02 += w * x0 * x2
            k11 += w * x1 * x1
            k12 += w * x1 * x2
            k22 += w * x2 * x2
        if d == 2:
            out[i] = k00 * k11 - k01 * k01
        else:
            out[i] = (
                k00 * (k11 * k22 - k12 * k12)
                - k01 * (k01 * k22 - k12 * k02)
                + k02 * (k01 * k12 - k11 * k02)
            )


LAW_SVK = 0
LAW_LINEAR = 1


@_hot
def force_tensor(fgrad, kinv, sigma_s, active, lame, shear, law, strain, amat):
    """A_i = (P(F_i) - sigma^s_i) K_i^-1 of the built-in laws, every owned point.

    Parameters
    ----------
    fgrad, kinv, sigma_s : (n_all, d, d) from :func:`peridynamics.kernels.correspondence.prepass`.
    active : (n_all,) 1.0 regular, 0.0 degenerate (A = 0).
    lame, shear : float, lambda' and mu (Pa).
    law : int, LAW_SVK (Green strain, P = F S) or LAW_LINEAR (sym(F - I), P = sigma).
    strain : (n_all, d, d) scratch: the stress S (SVK) or sigma (linear) on return.
    amat : (n_all, d, d) output; rows ``0..n-1`` of ``fgrad.shape[0]`` are written.
    """
    n = fgrad.shape[0]
    d = fgrad.shape[1]
    for i in prange(n):
        if active[i] == 0.0:
            for a in range(d):
                for b in range(d):
                    amat[i, a, b] = 0.0
                    strain[i, a, b] = 0.0
            continue
        tr = 0.0
        for a in range(d):
            for b in range(d):
                if law == 0:
                    e = 0.0
                    for c in range(d):
                        e += fgrad[i, c, a] * fgrad[i, c, b]
                    e *= 0.5
                else:
                    e = 0.5 * (fgrad[i, a, b] + fgrad[i, b, a])
                if a == b:
                    e -= 0.5 if law == 0 else 1.0
                    tr += e
                strain[i, a, b] = e
        for a in range(d):
            for b in range(d):
                strain[i, a, b] *= 2.0 * shear
            strain[i, a, a] += lame * tr
        # P - sigma^s into amat (as a scratch), then times K^-1 row by row
        for a in range(d):
            for b in range(d):
                if law == 0:
                    p = 0.0
                    for c in range(d):
                        p += fgrad[i, a, c] * strain[i, c, b]
                else:
                    p = strain[i, a, b]
                amat[i, a, b] = p - sigma_s[i, a, b]
        for a in range(d):
            r0 = amat[i, a, 0]
            r1 = amat[i, a, 1]
            r2 = amat[i, a, 2] if d == 3 else 0.0
            for b in range(d):
                v = r0 * kinv[i, 0, b] + r1 * kinv[i, 1, b]
                if d == 3:
                    v += r2 * kinv[i, 2, b]
                amat[i, a, b] = v
