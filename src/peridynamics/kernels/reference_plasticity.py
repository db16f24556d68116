"""NumPy twins of :mod:`peridynamics.kernels.plasticity` and
:mod:`peridynamics.kernels.finite_plasticity` (the test oracles), and the
algorithmic (consistent) tangent of the J2 return map.

Written from the equations (docs/theory_plasticity.md), vectorised over points, sharing
no code with the Numba kernels: the polar decomposition by the SVD, the return maps
with ``np.where``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]
_I = np.eye(3)


def polar(f: F64) -> tuple[F64, F64]:
    """(R, U) of F = R U, shapes (n, 3, 3), by the SVD F = W S V^T: R = W V^T, U = V S V^T."""
    w, sv, vt = np.linalg.svd(f)
    r = w @ vt
    u = np.einsum("nba,nb,nbc->nac", vt, sv, vt)
    return r, u


def _split(e: F64) -> tuple[F64, F64]:
    tr = np.trace(e, axis1=1, axis2=2)
    return tr, e - tr[:, None, None] / 3.0 * _I


def j2_return(e: F64, hist: F64, p: F64) -> tuple[F64, F64]:
    """(stress (n, 3, 3), new history (n, 19)) of the J2 radial return at strains e."""
    lam, mu, sy, h_iso, h_kin = p[:5]
    bulk = lam + 2.0 * mu / 3.0
    eps_p = hist[:, :9].reshape(-1, 3, 3)
    beta = hist[:, 9:18].reshape(-1, 3, 3)
    alpha = hist[:, 18]
    tr, dev = _split(e - eps_p)
    s_tr = 2.0 * mu * dev
    xi = s_tr - beta
    nrm = np.sqrt(np.einsum("nab,nab->n", xi, xi))
    f = nrm - np.sqrt(2.0 / 3.0) * (sy + h_iso * alpha)
    gamma = np.where(f > 0, f / (2.0 * mu + 2.0 / 3.0 * (h_iso + h_kin)), 0.0)
    n = xi / np.where(nrm > 0, nrm, 1.0)[:, None, None]
    g = gamma[:, None, None]
    stress = s_tr - 2.0 * mu * g * n + (bulk * tr)[:, None, None] * _I
    new = np.concatenate(
        [
            (eps_p + g * n).reshape(-1, 9),
            (beta + 2.0 / 3.0 * h_kin * g * n).reshape(-1, 9),
            (alpha + np.sqrt(2.0 / 3.0) * gamma)[:, None],
        ],
        axis=1,
    )
    return stress, new


def j2_tangent(e: F64, hist: F64, p: F64) -> F64:
    """The algorithmic tangent d sigma / d e (n, 3, 3, 3, 3) of :func:`j2_return`
    (Simo & Hughes 1998, box 3.2, with kinematic hardening): ``K 1 x 1 + 2 mu theta
    I_dev - 2 mu theta_bar n x n``."""
    lam, mu, sy, h_iso, h_kin = p[:5]
    bulk = lam + 2.0 * mu / 3.0
    eps_p = hist[:, :9].reshape(-1, 3, 3)
    beta = hist[:, 9:18].reshape(-1, 3, 3)
    _, dev = _split(e - eps_p)
    xi = 2.0 * mu * dev - beta
    nrm = np.sqrt(np.einsum("nab,nab->n", xi, xi))
    f = nrm - np.sqrt(2.0 / 3.0) * (sy + h_iso * hist[:, 18])
    plastic = f > 0
    gamma = np.where(plastic, f / (2.0 * mu + 2.0 / 3.0 * (h_iso + h_kin)), 0.0)
    theta = 1.0 - 2.0 * mu * gamma / np.where(nrm > 0, nrm, 1.0)
    theta_bar = np.where(plastic, 1.0 / (1.0 + (h_iso + h_kin) / (3.0 * mu)) - (1.0 - theta), 0.0)
    n = xi / np.where(nrm > 0, nrm, 1.0)[:, None, None]
    sym = 0.5 * (np.einsum("ac,bd->abcd", _I, _I) + np.einsum("ad,bc->abcd", _I, _I))
    one = np.einsum("ab,cd->abcd", _I, _I)
    dev4 = sym - one / 3.0
    return np.asarray(
        bulk * one[None]
        + 2.0 * mu * theta[:, None, None, None, None] * dev4[None]
        - 2.0 * mu * theta_bar[:, None, None, None, None] * np.einsum("nab,ncd->nabcd", n, n)
    )


def dp_return(e: F64, hist: F64, p: F64) -> tuple[F64, F64]:
    """(stress (n, 3, 3), new history (n, 10)) of the Drucker-Prager return with the
    tension cut-off at strains e."""
    lam, mu, eta, eta_bar, xic, cut = p[:6]
    bulk = lam + 2.0 * mu / 3.0
    eps_p = hist[:, :9].reshape(-1, 3, 3)
    tr, dev = _split(e - eps_p)
    s_tr = 2.0 * mu * dev
    sj2 = np.sqrt(0.5 * np.einsum("nab,nab->n", s_tr, s_tr))
    p_tr = bulk * tr
    f = sj2 + eta * p_tr - xic
    gamma = np.where(f > 0, f / (mu + bulk * eta * eta_bar), 0.0)
    cone = sj2 - mu * gamma >= 0
    safe = np.where(sj2 > 0, sj2, 1.0)
    scale = np.where(cone, (sj2 - mu * gamma) / safe, 0.0)
    pm = np.where(cone, p_tr - bulk * eta_bar * gamma, xic / eta if eta > 0 else 0.0)
    over = pm > cut
    corner = over & (sj2 + eta * cut - xic > 0)
    scale = np.where(over, np.where(corner, (xic - eta * cut) / safe, 1.0), scale)
    pm = np.where(over, cut, pm)
    s = scale[:, None, None] * s_tr
    stress = s + pm[:, None, None] * _I
    eps_new = e - s / (2.0 * mu) - (pm / (3.0 * bulk))[:, None, None] * _I
    de = (eps_new - eps_p).reshape(-1, 9)
    alpha = hist[:, 9] + np.sqrt(2.0 / 3.0 * np.einsum("nk,nk->n", de, de))
    return stress, np.concatenate([eps_new.reshape(-1, 9), alpha[:, None]], axis=1)


def corotated_update(
    fgrad: F64, active: F64, law: int, params: F64, hist: F64
) -> tuple[F64, F64, F64]:
    """(P (n, d, d), s (n, 3, 3), trial history) of :func:`.plasticity.corotated_update`."""
    n, d, _ = fgrad.shape
    f = np.tile(_I, (n, 1, 1))
    f[:, :d, :d] = fgrad
    r, u = polar(f)
    ret = j2_return if law == 0 else dp_return
    s, new = ret(u - _I, hist, params)
    jac = np.linalg.det(f)
    piola = jac[:, None, None] * r @ s @ np.linalg.inv(u)
    on = active > 0
    piola = np.where(on[:, None, None], piola, 0.0)[:, :d, :d]
    s = np.where(on[:, None, None], s, 0.0)
    new = np.where(on[:, None], new, hist)
    return piola, s, new


def log_stretch(f: F64) -> tuple[F64, F64, F64]:
    """(R, ln U, U^-1) of F = R U, shapes (n, 3, 3), from the SVD F = W S V^T: R = W V^T,
    ln U = V diag(ln S) V^T, U^-1 = V diag(1/S) V^T."""
    w, sv, vt = np.linalg.svd(f)
    log_u = np.einsum("nba,nb,nbc->nac", vt, np.log(sv), vt)
    u_inv = np.einsum("nba,nb,nbc->nac", vt, 1.0 / sv, vt)
    return w @ vt, log_u, u_inv


def hencky_update(
    fgrad: F64, active: F64, law: int, params: F64, hist: F64
) -> tuple[F64, F64, F64]:
    """(P (n, d, d), T (n, 3, 3), trial history) of
    :func:`.finite_plasticity.hencky_update`: the return map at e = ln U to the rotated
    Kirchhoff stress T, P = R T U^-1."""
    n, d, _ = fgrad.shape
    f = np.tile(_I, (n, 1, 1))
    f[:, :d, :d] = fgrad
    r, log_u, u_inv = log_stretch(f)
    ret = j2_return if law == 0 else dp_return
    t, new = ret(log_u, hist, params)
    piola = r @ t @ u_inv
    on = active > 0
    piola = np.where(on[:, None, None], piola, 0.0)[:, :d, :d]
    t = np.where(on[:, None, None], t, 0.0)
    new = np.where(on[:, None], new, hist)
    return piola, t, new
