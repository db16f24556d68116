"""Kernels of the thermal-expansion variants of the bond-based (PMB) and LPS families.

Every Numba kernel here has a NumPy twin in
:mod:`peridynamics.kernels.reference_thermal` that the tests compare against. They are
separate from :mod:`peridynamics.kernels.bond_based` and :mod:`peridynamics.kernels.lps`
so that a run without thermal expansion keeps its kernels and its bits. One kernel
serves 2-D and 3-D where it is not hot (energy, stretch: a loop over the components);
the force passes have a 2-D and a 3-D form (the dicts at the end); each point writes its
own rows only.

Notation as in those modules, plus the thermal strain ``eps`` (n_all,) of every point
(dimensionless, ``alpha (T - T_ref)``; docs/theory_thermal.md) and the thermal strain of
a bond, ``a_k = (eps_i + eps_j) / 2`` (the same for both directions of a bond):

* mechanical stretch      s_k - a_k                  (Kilic & Madenci (2010b))
* PMB force density       f_i = sum_k stiffness_k mu_k (s_k - a_k) y_k / r_k
* PMB energy density      W_i = 1/4 sum_k stiffness_k mu_k (s_k - a_k)^2 L_k
* LPS extension           e_k - a_k L_k  (the thermal extension of a bond: Oterkus,
  Madenci & Agwai (2014b)),
  in the dilatation, the force state and the energy of :mod:`peridynamics.kernels.lps`.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
_exact = njit(parallel=True, fastmath=False, cache=True)


@njit(inline="always")
def _rl(x, u, i, j):
    """(|xi + eta|, |xi|) of bond (i, j), summed in component order."""
    r2 = 0.0
    l2 = 0.0
    for c in range(x.shape[1]):
        d = x[j, c] - x[i, c]
        e = d + (u[j, c] - u[i, c])
        l2 += d * d
        r2 += e * e
    return np.sqrt(r2), np.sqrt(l2)


@_hot
def pmb_force_2d(x, u, offsets, bond_j, stiffness, intact, eps, force):
    """2-D PMB force density with thermal strain (N/m^3); pure (never breaks).

    Parameters
    ----------
    x, u : (n_all, 2) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j, stiffness (N/m^6 m^3), intact : (n_bonds,).
    eps : (n_all,) thermal strain of every point (ghosts included).
    force : (n_all, 2) output; rows ``0..n-1`` are written.

    Notes
    -----
    The pair force ``stiffness mu (1/L - (1 + a)/r) y`` is ``stiffness mu (s - a) y / r``;
    the family loop has the form of :mod:`peridynamics.kernels.bond_based`'s (unsigned
    indices, no max reduction), so LLVM vectorises it.
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
        ei = eps[i]
        f0 = 0.0
        f1 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            d0 = x[j, 0] - x0
            d1 = x[j, 1] - x1
            e0 = d0 + (u[j, 0] - u0)
            e1 = d1 + (u[j, 1] - u1)
            inv_l = 1.0 / np.sqrt(d0 * d0 + d1 * d1)
            r = np.sqrt(e0 * e0 + e1 * e1)
            g = stiffness[q] * np.float64(intact[q]) * (inv_l - (1.0 + 0.5 * (ei + eps[j])) / r)
            f0 += g * e0
            f1 += g * e1
        force[i, 0] = f0
        force[i, 1] = f1


@_hot
def pmb_force_3d(x, u, offsets, bond_j, stiffness, intact, eps, force):
    """3-D PMB force density with thermal strain; arguments as :func:`pmb_force_2d`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
        u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
        ei = eps[i]
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            d0 = x[j, 0] - x0
            d1 = x[j, 1] - x1
            d2 = x[j, 2] - x2
            e0 = d0 + (u[j, 0] - u0)
            e1 = d1 + (u[j, 1] - u1)
            e2 = d2 + (u[j, 2] - u2)
            inv_l = 1.0 / np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            g = stiffness[q] * np.float64(intact[q]) * (inv_l - (1.0 + 0.5 * (ei + eps[j])) / r)
            f0 += g * e0
            f1 += g * e1
            f2 += g * e2
        force[i, 0] = f0
        force[i, 1] = f1
        force[i, 2] = f2


@_exact
def pmb_energy(x, u, offsets, bond_j, stiffness, intact, eps, out):
    """PMB energy density W_i = 1/4 sum_k stiffness_k mu_k (s_k - a_k)^2 L_k (J/m^3)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        w = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            r, length = _rl(x, u, i, j)
            s = r / length - 1.0 - 0.5 * (eps[i] + eps[j])
            w += stiffness[k] * intact[k] * s * s * length
        out[i] = 0.25 * w


@_exact
def mechanical_stretch(x, u, offsets, bond_j, eps, out):
    """Mechanical stretch s_k - a_k of every directed bond (n_bonds,)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            r, length = _rl(x, u, i, j)
            out[k] = r / length - 1.0 - 0.5 * (eps[i] + eps[j])


@_exact
def largest_mechanical_stretch(x, u, offsets, bond_j, intact, eps, out):
    """Largest mechanical stretch of an intact bond of every point (n,), 0 if none."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        m = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k]:
                j = bond_j[k]
                r, length = _rl(x, u, i, j)
                m = max(m, r / length - 1.0 - 0.5 * (eps[i] + eps[j]))
        out[i] = m


@njit(inline="always")
def _extension(x, u, i, j, length, a):
    """Deformed length r and mechanical extension e - a L of bond (i, j), e evaluated
    as eta.(2 xi + eta)/(r + L) (:mod:`peridynamics.kernels.lps`)."""
    r2 = 0.0
    num = 0.0
    for c in range(x.shape[1]):
        xi = x[j, c] - x[i, c]
        eta = u[j, c] - u[i, c]
        y = xi + eta
        r2 += y * y
        num += eta * (xi + xi + eta)
    r = np.sqrt(r2)
    return r, num / (r + length) - a * length


@njit(inline="always")
def _mech_2d(x, u, i, j, length, a):
    """(y0, y1, r, e - a L) of bond (i, j) in 2-D."""
    xi0 = x[j, 0] - x[i, 0]
    xi1 = x[j, 1] - x[i, 1]
    eta0 = u[j, 0] - u[i, 0]
    eta1 = u[j, 1] - u[i, 1]
    y0 = xi0 + eta0
    y1 = xi1 + eta1
    r = np.sqrt(y0 * y0 + y1 * y1)
    e = (eta0 * (xi0 + xi0 + eta0) + eta1 * (xi1 + xi1 + eta1)) / (r + length)
    return y0, y1, r, e - a * length


@njit(inline="always")
def _mech_3d(x, u, i, j, length, a):
    """(y0, y1, y2, r, e - a L) of bond (i, j) in 3-D."""
    xi0 = x[j, 0] - x[i, 0]
    xi1 = x[j, 1] - x[i, 1]
    xi2 = x[j, 2] - x[i, 2]
    eta0 = u[j, 0] - u[i, 0]
    eta1 = u[j, 1] - u[i, 1]
    eta2 = u[j, 2] - u[i, 2]
    y0 = xi0 + eta0
    y1 = xi1 + eta1
    y2 = xi2 + eta2
    r = np.sqrt(y0 * y0 + y1 * y1 + y2 * y2)
    e = (eta0 * (xi0 + xi0 + eta0) + eta1 * (xi1 + xi1 + eta1) + eta2 * (xi2 + xi2 + eta2)) / (
        r + length
    )
    return y0, y1, y2, r, e - a * length


@_hot
def lps_dilatation_2d(x, u, offsets, bond_j, length, wv, intact, theta_scale, eps, theta):
    """2-D mechanical dilatation theta_i = ts_i sum_k mu_k wv_k L_k (e_k - a_k L_k);
    arguments as :func:`peridynamics.kernels.lps.dilatation_2d` plus ``eps`` (n_all,)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        ei = eps[i]
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            lk = length[q]
            _, _, _, e = _mech_2d(x, u, i, j, lk, 0.5 * (ei + eps[j]))
            acc += np.float64(intact[q]) * wv[q] * lk * e
        theta[i] = theta_scale[i] * acc


@_hot
def lps_dilatation_3d(x, u, offsets, bond_j, length, wv, intact, theta_scale, eps, theta):
    """3-D mechanical dilatation; arguments as :func:`lps_dilatation_2d`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        ei = eps[i]
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            lk = length[q]
            _, _, _, _, e = _mech_3d(x, u, i, j, lk, 0.5 * (ei + eps[j]))
            acc += np.float64(intact[q]) * wv[q] * lk * e
        theta[i] = theta_scale[i] * acc


@_hot
def lps_force_2d(x, u, offsets, bond_j, length, wv, wvf, intact, theta, cd, a, eps, force):
    """2-D LPS force density with thermal strain (N/m^3); arguments as
    :func:`peridynamics.kernels.lps.force_2d` plus ``eps`` (n_all,); ``theta`` the
    mechanical dilatation of :func:`lps_dilatation_2d`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        ci = cd[i] * theta[i]
        ai = a[i]
        ei = eps[i]
        f0 = 0.0
        f1 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            lk = length[q]
            y0, y1, r, e = _mech_2d(x, u, i, j, lk, 0.5 * (ei + eps[j]))
            w_i = wv[q]
            w_j = wvf[q]
            g = (
                np.float64(intact[q])
                * ((w_i * ci + w_j * cd[j] * theta[j]) * lk + (w_i * ai + w_j * a[j]) * e)
                / r
            )
            f0 += g * y0
            f1 += g * y1
        force[i, 0] = f0
        force[i, 1] = f1


@_hot
def lps_force_3d(x, u, offsets, bond_j, length, wv, wvf, intact, theta, cd, a, eps, force):
    """3-D LPS force density with thermal strain; arguments as :func:`lps_force_2d`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        ci = cd[i] * theta[i]
        ai = a[i]
        ei = eps[i]
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            lk = length[q]
            y0, y1, y2, r, e = _mech_3d(x, u, i, j, lk, 0.5 * (ei + eps[j]))
            w_i = wv[q]
            w_j = wvf[q]
            g = (
                np.float64(intact[q])
                * ((w_i * ci + w_j * cd[j] * theta[j]) * lk + (w_i * ai + w_j * a[j]) * e)
                / r
            )
            f0 += g * y0
            f1 += g * y1
            f2 += g * y2
        force[i, 0] = f0
        force[i, 1] = f1
        force[i, 2] = f2


@_exact
def lps_energy(x, u, offsets, bond_j, length, wv, intact, theta_scale, k_theta, a, eps, out):
    """LPS energy density W_i = k_theta theta_i^2 / 2 + (a_i / 2) sum_k mu_k wv_k
    (e_k - a_k L_k)^2 (J/m^3), the mechanical dilatation recomputed from ``u``."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        th = 0.0
        w = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            _, e = _extension(x, u, i, j, length[k], 0.5 * (eps[i] + eps[j]))
            q = intact[k] * wv[k]
            th += q * length[k] * e
            w += q * e * e
        th *= theta_scale[i]
        out[i] = 0.5 * (k_theta * th * th + a[i] * w)


PMB_FORCE = {2: pmb_force_2d, 3: pmb_force_3d}
LPS_DILATATION = {2: lps_dilatation_2d, 3: lps_dilatation_3d}
LPS_FORCE = {2: lps_force_2d, 3: lps_force_3d}
