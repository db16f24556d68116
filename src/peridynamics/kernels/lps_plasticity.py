"""Numba kernels of the elastic-plastic LPS (Mitchell (2011), SAND2011-3166), 3-D.

Per directed bond k = (i, j) of reference length L_k, extension e_k and the dilatation
theta_i of its owner, the deviatoric extension is ``ed_k = e_k - theta_i L_k / 3``; it
is split into an elastic part and a plastic part ``ep_k`` (the committed history). With
``a_i = 15 mu / m_i`` and ``wv_k`` (influence function times partial volume, as in
:mod:`peridynamics.kernels.lps`), the elastic deviatoric energy of point i is

    Wd_i = (a_i / 2) sum_k mu_k wv_k (ed_k - ep_k)^2,

its equivalent stress ``sbar_i = sqrt(6 mu Wd_i)`` (the von Mises stress of a
homogeneous deviatoric strain: ``Wd = s:s / (4 mu)``). Yield and radial return (linear
isotropic hardening H, equivalent plastic strain ``q_i``):

    f = sbar_trial - (sigma_y + H q_n);  f <= 0: elastic (c_i = 1);
    f > 0: dq = f / (3 mu + H),  c_i = 1 - 3 mu dq / sbar_trial,  q = q_n + dq,

and every bond of the point returns radially, ``ep_k <- ep_k + (1 - c_i) (ed_k -
ep_k)`` (the deviatoric force state is scaled by c_i onto the yield surface). The force
state is the elastic LPS one less the plastic part,
``t_ik = omega_ik (cd_i theta_i L_k + a_i e_k - a_i ep_k)`` (cd_i = (3K - 5 mu) / m_i).

:func:`plastic_prepass_3d` computes theta_i and the return of every point (one pass
over the family: ``sum wv (ed - ep)^2`` is expanded into sums of the same pass);
:func:`plastic_force_3d` the force density and the trial ``ep`` of every owned bond.
NumPy twins: :mod:`peridynamics.kernels.reference_lps_plasticity`.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from peridynamics.kernels.lps import _bond_3d

_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)


@_hot
def plastic_prepass_3d(
    x, u, offsets, bond_j, length, wv, intact, theta_scale, a, ep, q, shear, yield_stress,
    hardening, theta, scale, q_trial,
):  # fmt: skip
    """Dilatation and the return map of every owned point.

    Parameters
    ----------
    x, u : (n, 3) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j, length (m), wv (m^3), intact : (n_bonds,).
    theta_scale : (n,) 3 / m_i (1/m^5); a : (n,) 15 mu / m_i (N/m^7).
    ep : (n_bonds,) committed plastic extension (m); q : (n,) committed equivalent
        plastic strain.
    shear, yield_stress, hardening : floats, mu, sigma_y, H (Pa).
    theta, scale, q_trial : (n,) outputs: the dilatation, c_i (1: elastic) and the
        trial equivalent plastic strain.
    """
    n = offsets.shape[0] - 1
    third = 1.0 / 3.0
    three_mu = 3.0 * shear
    for i in prange(n):
        s_le = 0.0
        s_lp = 0.0
        s_dd = 0.0
        s_ll = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            lk = length[k]
            _, _, _, _, e = _bond_3d(x, u, i, bond_j[k], lk)
            w = np.float64(intact[k]) * wv[k]
            d = e - ep[k]
            s_le += w * lk * e
            s_lp += w * lk * ep[k]
            s_dd += w * d * d
            s_ll += w * lk * lk
        th = theta_scale[i] * s_le
        theta[i] = th
        t3 = th * third
        # sum wv (e - ep - t3 L)^2, expanded
        wd = 0.5 * a[i] * (s_dd - 2.0 * t3 * (s_le - s_lp) + t3 * t3 * s_ll)
        sbar = np.sqrt(6.0 * shear * max(wd, 0.0))
        f = sbar - (yield_stress + hardening * q[i])
        if f > 0.0:
            dq = f / (three_mu + hardening)
            scale[i] = 1.0 - three_mu * dq / sbar
            q_trial[i] = q[i] + dq
        else:
            scale[i] = 1.0
            q_trial[i] = q[i]


@_hot
def plastic_force_3d(
    x, u, offsets, bond_j, length, wv, wvf, intact, theta, cd, a, reverse, ep, scale,
    ep_trial, force,
):  # fmt: skip
    """Elastic-plastic LPS force density (N/m^3) and the trial plastic extension.

    Parameters
    ----------
    x, u, offsets, bond_j, length, wv, wvf, intact, theta, cd, a : as
        :func:`peridynamics.kernels.lps.force_3d`.
    reverse : (n_bonds,) index of bond (j, i) for bond (i, j).
    ep : (n_bonds,) committed plastic extension (m).
    scale : (n,) c_i of :func:`plastic_prepass_3d`.
    ep_trial : (n_bonds,) output: the plastic extension after the return.
    force : (n, 3) output force density (rows ``0..n-1`` written).
    """
    n = offsets.shape[0] - 1
    third = 1.0 / 3.0
    for i in prange(n):
        ci = cd[i] * theta[i]
        ai = a[i]
        ti = theta[i] * third
        ri = 1.0 - scale[i]
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            rk = reverse[k]
            lk = length[k]
            y0, y1, y2, r, e = _bond_3d(x, u, i, j, lk)
            on = np.float64(intact[k])
            p_i = ep[k] + on * ri * (e - ti * lk - ep[k])
            p_j = ep[rk] + on * (1.0 - scale[j]) * (e - theta[j] * third * lk - ep[rk])
            ep_trial[k] = p_i
            w_i = wv[k]
            w_j = wvf[k]
            g = (
                on
                * (
                    (w_i * ci + w_j * cd[j] * theta[j]) * lk
                    + (w_i * ai + w_j * a[j]) * e
                    - (w_i * ai * p_i + w_j * a[j] * p_j)
                )
                / r
            )
            f0 += g * y0
            f1 += g * y1
            f2 += g * y2
        force[i, 0] = f0
        force[i, 1] = f1
        force[i, 2] = f2
