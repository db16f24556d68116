"""Per-point return mapping of the correspondence laws in the logarithmic (Hencky)
strain (Numba): ``material.plasticity.strain: logarithmic``.

Every owned point with a regular family: the polar decomposition F = R U (embedded in
3 x 3; plane strain F_33 = 1) of :func:`peridynamics.kernels.plasticity.polar`, the
spectral decomposition U = V diag(lambda) V^T (cyclic Jacobi), the log strain
``e = ln U = V diag(ln lambda) V^T`` (= ln C / 2), the return map of the law
(:func:`~peridynamics.kernels.plasticity.j2_return`,
:func:`~peridynamics.kernels.plasticity.dp_return`: the additive split of the log
strain, Eterovic & Bathe (1990); de Souza Neto et al. (2008), ch. 14) to the rotated
Kirchhoff stress T, and the first Piola-Kirchhoff stress ``P = R T U^-1`` (the
Kirchhoff stress is tau = R T R^T and P = tau F^-T). T is work-conjugate to ln U when
it is coaxial with U (always for isotropic elasticity without plastic strain; the
usual approximation under small elastic strains otherwise). Equations:
docs/theory_plasticity.md. NumPy twin:
:func:`peridynamics.kernels.reference_plasticity.hencky_update`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from peridynamics.kernels.plasticity import (
    embedded,
    law_return,
    polar,
    rotated_piola,
    skip_point,
)

_exact = njit(parallel=True, fastmath=False, cache=True)
_JACOBI_SWEEPS = 50


@njit(cache=True)
def sym_eig3(a, vals, vecs, m):
    """Eigenvalues ``vals`` (3,) and orthonormal eigenvectors (the columns of ``vecs``
    (3, 3)) of the symmetric 3 x 3 ``a`` by cyclic Jacobi rotations (Golub & Van Loan,
    section 8.5); ``m`` (3, 3) scratch. ``a = vecs diag(vals) vecs^T``."""
    for p in range(3):
        for q in range(3):
            m[p, q] = 0.5 * (a[p, q] + a[q, p])
            vecs[p, q] = 1.0 if p == q else 0.0
    for _ in range(_JACOBI_SWEEPS):
        off = m[0, 1] * m[0, 1] + m[0, 2] * m[0, 2] + m[1, 2] * m[1, 2]
        diag = m[0, 0] * m[0, 0] + m[1, 1] * m[1, 1] + m[2, 2] * m[2, 2]
        if off <= 1e-34 * diag or off == 0.0:
            break
        for pair in range(3):
            p = 0 if pair < 2 else 1
            q = 2 if pair > 0 else 1
            apq = m[p, q]
            if apq == 0.0:
                continue
            theta = (m[q, q] - m[p, p]) / (2.0 * apq)
            t = 1.0 / (abs(theta) + math.sqrt(theta * theta + 1.0))
            if theta < 0.0:
                t = -t
            c = 1.0 / math.sqrt(t * t + 1.0)
            s = t * c
            for k in range(3):  # m <- m J
                mkp = m[k, p]
                mkq = m[k, q]
                m[k, p] = c * mkp - s * mkq
                m[k, q] = s * mkp + c * mkq
            for k in range(3):  # m <- J^T m
                mpk = m[p, k]
                mqk = m[q, k]
                m[p, k] = c * mpk - s * mqk
                m[q, k] = s * mpk + c * mqk
            m[p, q] = 0.0
            m[q, p] = 0.0
            for k in range(3):  # vecs <- vecs J
                vkp = vecs[k, p]
                vkq = vecs[k, q]
                vecs[k, p] = c * vkp - s * vkq
                vecs[k, q] = s * vkp + c * vkq
    for p in range(3):
        vals[p] = m[p, p]


@njit(cache=True)
def _spectral(vecs, vals, out):
    """out = vecs diag(vals) vecs^T (3 x 3)."""
    for a in range(3):
        for b in range(3):
            v = 0.0
            for c in range(3):
                v += vecs[a, c] * vals[c] * vecs[b, c]
            out[a, b] = v


@_exact
def hencky_update(fgrad, active, law, params, hist_in, hist_out, piola, stress):
    """The built-in laws in the log strain at every point: P (n, d, d) into ``piola``,
    the rotated Kirchhoff stress T (n, 3, 3) into ``stress``, the trial history into
    ``hist_out``; arguments as :func:`peridynamics.kernels.plasticity.corotated_update`
    (the history holds log strains)."""
    n = fgrad.shape[0]
    for i in prange(n):
        if active[i] == 0.0:
            skip_point(hist_in[i], hist_out[i], piola[i], stress[i])
            continue
        f = embedded(fgrad[i])
        r = np.empty((3, 3))
        u = np.empty((3, 3))
        w = np.empty((2, 3, 3))
        polar(f, r, u, w)
        vals = np.empty(3)
        vecs = np.empty((3, 3))
        sym_eig3(u, vals, vecs, w[0])
        for c in range(3):
            vals[c] = math.log(vals[c])
        e = np.empty((3, 3))
        _spectral(vecs, vals, e)  # ln U
        law_return(law, e, hist_in[i], hist_out[i], params, stress[i])
        for c in range(3):
            vals[c] = math.exp(-vals[c])
        _spectral(vecs, vals, w[0])  # U^-1
        rotated_piola(r, stress[i], w, 1.0, piola[i])  # P = R T U^-1
