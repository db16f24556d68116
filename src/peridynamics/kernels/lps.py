"""Linear peridynamic solid (LPS, ordinary state-based) kernels, 2-D and 3-D.

Every Numba kernel here has a NumPy twin in :mod:`peridynamics.kernels.reference_lps`
that the tests compare against. The kernels gather over each point's family in the
directed CSR bond list (both (i, j) and (j, i) stored) and each point writes only its
own rows: no atomics. The hot family loops (dilatation, force) index with unsigned
integers and keep no max reduction, so LLVM vectorises them. They loop over the
points that own a family, ``n = offsets.shape[0] - 1``; per-point inputs (``theta``,
``cd``, ``a``) are read at the far end of a bond too and so must be valid for every
row of ``x`` (ghosts included).

Notation (per directed bond k = (i, j), all bonds of the family of i):

* ``xi = x_j - x_i``, ``eta = u_j - u_i``, deformed bond ``y = xi + eta``, ``r = |y|``,
  ``L = |xi|`` (``length``);
* extension ``e = r - L``, evaluated as ``eta . (2 xi + eta) / (r + L)`` (the same value
  without the cancellation of ``r - L`` at small strain);
* ``wv_k = omega_ik beta_k V_j`` (influence function of point i times partial volume,
  m^3); ``wvf_k = omega_jk beta_k V_j`` the same bond weighted by the influence
  function of the far point j. Without the surface correction omega depends on |xi|
  only and ``wvf = wv``; the correction of :mod:`peridynamics.families.lps.force` makes omega
  a per-point function of the bond direction, so the two differ;
* ``mu_k`` (``intact``) is 1 for an intact bond, 0 for a broken one.

Equations (Silling et al. 2007, eqs. 82-92 for 3-D; Le, Chan & Schwartz 2014 for 2-D;
the coefficients are documented in :mod:`peridynamics.families.lps.material`):

* weighted volume   m_i = sum_k mu_k wv_k L_k^2                        (m^5)
* dilatation        theta_i = ts_i sum_k mu_k wv_k L_k e_k,  ts_i = tf / m_i
* scalar force state t_ik = omega_ik (cd_i theta_i L_k + a_i e_k),
  cd_i = k_theta tf / m_i,  a_i = alpha / m_i                         (N/m^6)
* force density     f_i = sum_k mu_k beta_k V_j (t_ik + t_jk) y_k / r_k  (N/m^3)
  (t_jk: the force state of point j on the same bond, read with theta_j, m_j and
  omega_jk), i.e. ``f_i = sum_k mu_k ((wv_k cd_i theta_i + wvf_k cd_j theta_j) L_k +
  (wv_k a_i + wvf_k a_j) e_k) y_k / r_k``
* energy density    W_i = k_theta theta_i^2 / 2 + (a_i / 2) sum_k mu_k wv_k e_k^2 (J/m^3)

With every bond of the family intact, W_i equals the classical LPS energy
``k_d theta_d^2 / 2 + (a / 2) sum_k wv_k (e_k - theta_d L_k / d)^2`` written with the
deviatoric extension (``theta_d`` the d-dimensional dilatation, ``k_d`` the
d-dimensional bulk modulus; the two agree because
``sum_k wv_k L_k (e_k - theta_d L_k / d) = 0`` when m_i sums over the same bonds), see
:mod:`peridynamics.families.lps.material`. With broken bonds it is still the exact potential of
the force above (the force state is the standard one, as in Peridigm), so
``V_i f_i = -d(sum_j V_j W_j)/du_i`` holds in every state.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

#: hot loops (dilatation, force): fast-math lets LLVM vectorise the family sums
_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
#: reference quantities and diagnostics: no fast-math, reproducible bits
_exact = njit(parallel=True, fastmath=False, cache=True)


@njit(inline="always")
def _bond_2d(x, u, i, j, length):
    """Deformed bond (y0, y1), its length r and the extension e = r - L."""
    xi0 = x[j, 0] - x[i, 0]
    xi1 = x[j, 1] - x[i, 1]
    eta0 = u[j, 0] - u[i, 0]
    eta1 = u[j, 1] - u[i, 1]
    y0 = xi0 + eta0
    y1 = xi1 + eta1
    r = np.sqrt(y0 * y0 + y1 * y1)
    e = (eta0 * (xi0 + xi0 + eta0) + eta1 * (xi1 + xi1 + eta1)) / (r + length)
    return y0, y1, r, e


@njit(inline="always")
def _bond_3d(x, u, i, j, length):
    """Deformed bond (y0, y1, y2), its length r and the extension e = r - L."""
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
    return y0, y1, y2, r, e


# -- reference quantities ---------------------------------------------------------------
@_exact
def weighted_volume(offsets, length, wv, intact, out):
    """Weighted volume m_i = sum_k mu_k wv_k L_k^2 (m^5) (Silling et al. 2007, eq. 85).

    Parameters
    ----------
    offsets : (n + 1,) int64 CSR offsets.
    length : (n_bonds,) reference bond length L (m).
    wv : (n_bonds,) influence function times partial volume (m^3).
    intact : (n_bonds,) uint8 bond status (the reference one: pre-cracks excluded).
    out : (>= n,) output; rows ``0..n-1`` are written.
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            acc += intact[k] * wv[k] * length[k] * length[k]
        out[i] = acc


# -- dilatation (the pre-pass) ----------------------------------------------------------
@_hot
def dilatation_2d(x, u, offsets, bond_j, length, wv, intact, theta_scale, theta):
    """2-D dilatation theta_i = ts_i sum_k mu_k wv_k L_k e_k (dimensionless).

    Parameters
    ----------
    x, u : (n_all, 2) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j, length (m), wv (m^3), intact : (n_bonds,).
    theta_scale : (n_all,) ts_i = tf / m_i (1/m^5; 0 for a point without bonds).
    theta : (n_all,) output; rows ``0..n-1`` are written.
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            lk = length[q]
            _, _, _, e = _bond_2d(x, u, i, np.uint64(bond_j[q]), lk)
            acc += np.float64(intact[q]) * wv[q] * lk * e
        theta[i] = theta_scale[i] * acc


@_hot
def dilatation_3d(x, u, offsets, bond_j, length, wv, intact, theta_scale, theta):
    """3-D dilatation; arguments as :func:`dilatation_2d` with (n_all, 3) ``x``, ``u``."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            lk = length[q]
            _, _, _, _, e = _bond_3d(x, u, i, np.uint64(bond_j[q]), lk)
            acc += np.float64(intact[q]) * wv[q] * lk * e
        theta[i] = theta_scale[i] * acc


# -- force ------------------------------------------------------------------------------
@_hot
def force_2d(x, u, offsets, bond_j, length, wv, wvf, intact, theta, cd, a, force):
    """2-D LPS force density (N/m^3); pure (never breaks).

    Parameters
    ----------
    x, u : (n_all, 2) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j, length (m), wv (m^3), intact : (n_bonds,).
    wvf : (n_bonds,) the far end's weight of the same bond, ``wvf_k = wv_k' V_j / V_i``
        with k' = (j, i) (m^3); ``wv`` itself when the weights are symmetric
        (``V_i wv_k = V_j wv_k'``), i.e. without the surface correction.
    theta : (n_all,) dilatation of every point (the pre-pass, ghosts included).
    cd : (n_all,) dilatation coefficient k_theta tf / m_i (N/m^7).
    a : (n_all,) extension coefficient alpha / m_i (N/m^7).
    force : (n_all, 2) output force density; rows ``0..n-1`` are written.

    Notes
    -----
    The family loop vectorises: unsigned indices (plain loads of the per-bond streams)
    and no max reduction in it; the largest stretch is a pass of its own
    (:func:`peridynamics.kernels.bond_based.largest_stretch`), run when a solver asks.
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        ci = cd[i] * theta[i]
        ai = a[i]
        f0 = 0.0
        f1 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            lk = length[q]
            y0, y1, r, e = _bond_2d(x, u, i, j, lk)
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
def force_3d(x, u, offsets, bond_j, length, wv, wvf, intact, theta, cd, a, force):
    """3-D LPS force density (N/m^3); arguments as :func:`force_2d` with dim 3."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        ci = cd[i] * theta[i]
        ai = a[i]
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            lk = length[q]
            y0, y1, y2, r, e = _bond_3d(x, u, i, j, lk)
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


# -- energy -----------------------------------------------------------------------------
@_exact
def energy_density_2d(x, u, offsets, bond_j, length, wv, intact, theta_scale, k_theta, a, out):
    """2-D strain energy density W_i (J/m^3), the dilatation recomputed from ``u``.

    Parameters
    ----------
    x, u : (n_all, 2) reference positions and displacements (m).
    offsets, bond_j, length, wv, intact : the bond arrays as in :func:`force_2d`.
    theta_scale : (n_all,) tf / m_i (1/m^5).
    k_theta : float, dilatation modulus (Pa).
    a : (n_all,) alpha / m_i (N/m^7).
    out : (>= n,) output; rows ``0..n-1`` are written.
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        th = 0.0
        w = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            _, _, _, e = _bond_2d(x, u, i, bond_j[k], length[k])
            q = intact[k] * wv[k]
            th += q * length[k] * e
            w += q * e * e
        th *= theta_scale[i]
        out[i] = 0.5 * (k_theta * th * th + a[i] * w)


@_exact
def energy_density_3d(x, u, offsets, bond_j, length, wv, intact, theta_scale, k_theta, a, out):
    """3-D strain energy density W_i (J/m^3); arguments as :func:`energy_density_2d`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        th = 0.0
        w = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            _, _, _, _, e = _bond_3d(x, u, i, bond_j[k], length[k])
            q = intact[k] * wv[k]
            th += q * length[k] * e
            w += q * e * e
        th *= theta_scale[i]
        out[i] = 0.5 * (k_theta * th * th + a[i] * w)


DILATATION_KERNELS = {2: dilatation_2d, 3: dilatation_3d}
FORCE_KERNELS = {2: force_2d, 3: force_3d}
ENERGY_KERNELS = {2: energy_density_2d, 3: energy_density_3d}
