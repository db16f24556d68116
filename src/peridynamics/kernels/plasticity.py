"""Per-point return mapping of the history-dependent correspondence laws (Numba).

Every owned point with a regular family: the polar decomposition F = R U (embedded in
3 x 3; a 2-D plane-strain F has F_33 = 1), the corotated small strain e = U - I, the
return map of the law from the committed history to the stress s and the trial
history, and the first Piola-Kirchhoff stress ``P = J R s U^-1`` (s is the Cauchy
stress in the unrotated frame, so the Cauchy stress is ``R s R^T``: objective under a
superposed rigid rotation). Equations: docs/theory_plasticity.md. NumPy twins:
:mod:`peridynamics.kernels.reference_plasticity`.

History layout (row of ``hist``): J2 ``[eps_p (9), beta (9), alpha]`` (plastic strain,
back stress in Pa, equivalent plastic strain); Drucker-Prager ``[eps_p (9), alpha]``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

#: not fast-math: the return map compares a yield function with 0
_exact = njit(parallel=True, fastmath=False, cache=True)

LAW_J2 = 0
LAW_DRUCKER_PRAGER = 1
#: history components of the built-in laws
J2_HISTORY = 19
DP_HISTORY = 10
_POLAR_TOL = 1e-15
_POLAR_ITERATIONS = 40


@njit(cache=True)
def _inverse3(a, out):
    """out = a^-1 (3 x 3); returns det a."""
    c00 = a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1]
    c01 = a[1, 2] * a[2, 0] - a[1, 0] * a[2, 2]
    c02 = a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]
    det = a[0, 0] * c00 + a[0, 1] * c01 + a[0, 2] * c02
    s = 1.0 / det
    out[0, 0] = c00 * s
    out[1, 0] = c01 * s
    out[2, 0] = c02 * s
    out[0, 1] = (a[0, 2] * a[2, 1] - a[0, 1] * a[2, 2]) * s
    out[1, 1] = (a[0, 0] * a[2, 2] - a[0, 2] * a[2, 0]) * s
    out[2, 1] = (a[0, 1] * a[2, 0] - a[0, 0] * a[2, 1]) * s
    out[0, 2] = (a[0, 1] * a[1, 2] - a[0, 2] * a[1, 1]) * s
    out[1, 2] = (a[0, 2] * a[1, 0] - a[0, 0] * a[1, 2]) * s
    out[2, 2] = (a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]) * s
    return det


@njit(cache=True)
def polar(f, r, u, w):
    """F = R U (3 x 3, det F > 0) by Newton's iteration R <- (R + R^-T) / 2 (Higham
    1986), U = sym(R^T F); ``w`` (2, 3, 3) scratch. Returns det F."""
    for a in range(3):
        for b in range(3):
            r[a, b] = f[a, b]
    for _ in range(_POLAR_ITERATIONS):
        _inverse3(r, w[0])
        change = 0.0
        for a in range(3):
            for b in range(3):
                v = 0.5 * (r[a, b] + w[0, b, a])
                change = max(change, abs(v - r[a, b]))
                r[a, b] = v
        if change <= _POLAR_TOL:
            break
    for a in range(3):
        for b in range(3):
            v = 0.0
            for c in range(3):
                v += r[c, a] * f[c, b]
            w[1, a, b] = v
    for a in range(3):
        for b in range(3):
            u[a, b] = 0.5 * (w[1, a, b] + w[1, b, a])
    return _inverse3(f, w[0])


@njit(cache=True)
def j2_return(e, hist_in, hist_out, p, s):
    """J2 radial return (Simo & Hughes 1998, box 3.2) with linear isotropic and
    kinematic hardening. e (3, 3) strain, p = [lambda, mu, sigma_y, H_iso, H_kin],
    s (3, 3) the stress on return; hist_out the updated history."""
    lam, mu, sy, h_iso, h_kin = p[0], p[1], p[2], p[3], p[4]
    bulk = lam + 2.0 * mu / 3.0
    tr = 0.0
    for a in range(3):
        tr += e[a, a] - hist_in[4 * a]
    nrm2 = 0.0
    for a in range(3):
        for b in range(3):
            k = 3 * a + b
            dev = e[a, b] - hist_in[k] - (tr / 3.0 if a == b else 0.0)
            s[a, b] = 2.0 * mu * dev
            xi = s[a, b] - hist_in[9 + k]
            nrm2 += xi * xi
    nrm = math.sqrt(nrm2)
    alpha = hist_in[18]
    f = nrm - math.sqrt(2.0 / 3.0) * (sy + h_iso * alpha)
    for k in range(J2_HISTORY):
        hist_out[k] = hist_in[k]
    if f > 0.0:
        gamma = f / (2.0 * mu + 2.0 / 3.0 * (h_iso + h_kin))
        for a in range(3):
            for b in range(3):
                k = 3 * a + b
                n = (s[a, b] - hist_in[9 + k]) / nrm
                s[a, b] -= 2.0 * mu * gamma * n
                hist_out[k] += gamma * n
                hist_out[9 + k] += 2.0 / 3.0 * h_kin * gamma * n
        hist_out[18] = alpha + math.sqrt(2.0 / 3.0) * gamma
    for a in range(3):
        s[a, a] += bulk * tr


@njit(cache=True)
def dp_return(e, hist_in, hist_out, p, s):
    """Drucker-Prager return (perfectly plastic cone, non-associated flow) with a
    tension cut-off on the mean stress. p = [lambda, mu, eta, eta_bar, xi c, T]."""
    lam, mu, eta, eta_bar, xic, cut = p[0], p[1], p[2], p[3], p[4], p[5]
    bulk = lam + 2.0 * mu / 3.0
    tr = 0.0
    for a in range(3):
        tr += e[a, a] - hist_in[4 * a]
    nrm2 = 0.0
    for a in range(3):
        for b in range(3):
            s[a, b] = 2.0 * mu * (e[a, b] - hist_in[3 * a + b] - (tr / 3.0 if a == b else 0.0))
            nrm2 += s[a, b] * s[a, b]
    sj2 = math.sqrt(0.5 * nrm2)  # sqrt(J2)
    p_tr = bulk * tr
    f = sj2 + eta * p_tr - xic
    scale = 1.0
    pm = p_tr
    if f > 0.0:  # the cone (or its apex)
        gamma = f / (mu + bulk * eta * eta_bar)
        if sj2 - mu * gamma >= 0.0:
            scale = (sj2 - mu * gamma) / sj2
            pm = p_tr - bulk * eta_bar * gamma
        else:
            scale = 0.0
            pm = xic / eta
    if pm > cut:  # the tension cut-off, alone or at its corner with the cone
        pm = cut
        scale = 1.0
        if sj2 + eta * cut - xic > 0.0:
            scale = (xic - eta * cut) / sj2
    for a in range(3):
        for b in range(3):
            s[a, b] *= scale
    # the plastic strain: e - C^-1 sigma
    dsum = 0.0
    for a in range(3):
        for b in range(3):
            k = 3 * a + b
            el = s[a, b] / (2.0 * mu) + (pm / (3.0 * bulk) if a == b else 0.0)
            hist_out[k] = e[a, b] - el
            de = hist_out[k] - hist_in[k]
            dsum += de * de
        s[a, a] += pm
    hist_out[9] = hist_in[9] + math.sqrt(2.0 / 3.0 * dsum)


@njit(cache=True)
def law_return(law, e, hist_in, hist_out, p, s):
    """The return map of the built-in law ``law`` (``LAW_J2`` or
    ``LAW_DRUCKER_PRAGER``) at the strain ``e`` (3, 3): :func:`j2_return` or
    :func:`dp_return` (arguments as theirs)."""
    if law == LAW_J2:
        j2_return(e, hist_in, hist_out, p, s)
    else:
        dp_return(e, hist_in, hist_out, p, s)


@njit(cache=True)
def skip_point(hist_in, hist_out, piola, stress):
    """A degenerate point of the per-point laws: its history kept, P (d, d) and the stress
    (3, 3) zero."""
    for k in range(hist_in.shape[0]):
        hist_out[k] = hist_in[k]
    d = piola.shape[0]
    for a in range(d):
        for b in range(d):
            piola[a, b] = 0.0
    for a in range(3):
        for b in range(3):
            stress[a, b] = 0.0


@njit(cache=True)
def embedded(fgrad):
    """The deformation gradient ``fgrad`` (d, d) embedded in 3 x 3 (plane strain: F_33 = 1)."""
    f = np.eye(3)
    d = fgrad.shape[0]
    for a in range(d):
        for b in range(d):
            f[a, b] = fgrad[a, b]
    return f


@njit(cache=True)
def rotated_piola(r, stress, w, scale, piola):
    """``piola`` (d, d) = scale R (stress U^-1), U^-1 given in ``w[0]``; ``w[1]`` scratch
    (the first Piola-Kirchhoff stress of a stress in the unrotated frame: scale = J for
    the Cauchy stress s, 1 for the Kirchhoff stress T)."""
    for a in range(3):  # w[1] = stress U^-1
        for b in range(3):
            v = 0.0
            for c in range(3):
                v += stress[a, c] * w[0, c, b]
            w[1, a, b] = v
    d = piola.shape[0]
    for a in range(d):
        for b in range(d):
            v = 0.0
            for c in range(3):
                v += r[a, c] * w[1, c, b]
            piola[a, b] = scale * v


@_exact
def corotated_update(fgrad, active, law, params, hist_in, hist_out, piola, stress):
    """The built-in laws at every point: P (n, d, d) into ``piola`` and the unrotated
    stress s (n, 3, 3) into ``stress``, the trial history into ``hist_out``.

    Parameters
    ----------
    fgrad : (n, d, d) deformation gradients (d = 2: plane strain).
    active : (n,) 1.0 regular, 0.0 degenerate (P = 0, history kept).
    law : int, LAW_J2 or LAW_DRUCKER_PRAGER.
    params : (m,) float64 parameters of the law (Pa, dimensionless).
    hist_in, hist_out : (n, h) committed history, trial history.
    piola : (n, d, d) output (Pa).
    stress : (n, 3, 3) output (Pa).
    """
    n = fgrad.shape[0]
    for i in prange(n):
        if active[i] == 0.0:
            skip_point(hist_in[i], hist_out[i], piola[i], stress[i])
            continue
        f = embedded(fgrad[i])
        r = np.empty((3, 3))
        u = np.empty((3, 3))
        w = np.empty((2, 3, 3))
        jac = polar(f, r, u, w)
        for a in range(3):
            u[a, a] -= 1.0
        law_return(law, u, hist_in[i], hist_out[i], params, stress[i])
        for a in range(3):
            u[a, a] += 1.0
        _inverse3(u, w[0])  # U^-1
        rotated_piola(r, stress[i], w, jac, piola[i])
