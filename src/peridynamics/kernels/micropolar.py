"""Micropolar bond-based force and energy kernels (2-D, small deformation).

Every kernel has a NumPy twin in :mod:`peridynamics.kernels.reference_micropolar`.
Bond k = (i, j) with unit vectors n = xi/|xi|, n_perp = (-n_y, n_x), weight
``w_k = G_k beta_k V_j`` (surface correction times partial volume, m^3) and the springs
k_n, k_t, k_phi (N/m^6) of :mod:`peridynamics.families.micropolar.material`:

    l = (u_j - u_i).n / xi,   gamma = (u_j - u_i).n_perp / xi - (theta_i + theta_j)/2,
    phi = theta_j - theta_i,
    f_i = sum_k w_k (k_n l n + k_t gamma n_perp)                     (N/m^3)
    m_i = sum_k w_k xi (k_t gamma / 2 + k_phi phi)                   (N m/m^3)
    W_i = 1/4 sum_k w_k xi (k_n l^2 + k_t gamma^2 + k_phi phi^2)     (J/m^3)

so that V_i f_i = -dE/du_i and V_i m_i = -dE/dtheta_i for E = sum_i W_i V_i when
V_i w_ij = V_j w_ji (Zhou, Zhu & Li (n.d.), eqs 7-12; Diana & Casolo 2019).
"""

from __future__ import annotations

from numba import njit, prange

_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
_exact = njit(parallel=True, fastmath=False, cache=True)


@_hot
def force_2d(
    x, u, theta, offsets, bond_j, inv_length, weight, intact, kn, kt, kphi, force, moment,
    max_stretch,
):  # fmt: skip
    """Force density (N/m^3) into ``force`` (n, 2), moment density (N m/m^3) into
    ``moment`` (n, 1) and the largest axial stretch of an intact bond into
    ``max_stretch`` (n,); ``theta`` is (n, 1) (rad)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        xi0, xi1, ui0, ui1, ti = x[i, 0], x[i, 1], u[i, 0], u[i, 1], theta[i, 0]
        f0 = 0.0
        f1 = 0.0
        m = 0.0
        smax = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k] == 0:
                continue
            j = bond_j[k]
            il = inv_length[k]
            n0 = (x[j, 0] - xi0) * il
            n1 = (x[j, 1] - xi1) * il
            d0 = u[j, 0] - ui0
            d1 = u[j, 1] - ui1
            tj = theta[j, 0]
            stretch = (d0 * n0 + d1 * n1) * il
            gamma = (d1 * n0 - d0 * n1) * il - 0.5 * (ti + tj)
            w = weight[k]
            fn = w * kn * stretch
            ft = w * kt * gamma
            f0 += fn * n0 - ft * n1
            f1 += fn * n1 + ft * n0
            m += w * (0.5 * kt * gamma + kphi * (tj - ti)) / il
            smax = max(smax, stretch)
        force[i, 0] = f0
        force[i, 1] = f1
        moment[i, 0] = m
        max_stretch[i] = smax


@_exact
def energy_density_2d(x, u, theta, offsets, bond_j, inv_length, weight, intact, kn, kt, kphi, out):
    """W_i (J/m^3) into ``out`` (n,)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k] == 0:
                continue
            j = bond_j[k]
            il = inv_length[k]
            n0 = (x[j, 0] - x[i, 0]) * il
            n1 = (x[j, 1] - x[i, 1]) * il
            d0 = u[j, 0] - u[i, 0]
            d1 = u[j, 1] - u[i, 1]
            stretch = (d0 * n0 + d1 * n1) * il
            gamma = (d1 * n0 - d0 * n1) * il - 0.5 * (theta[i, 0] + theta[j, 0])
            phi = theta[j, 0] - theta[i, 0]
            acc += weight[k] * (kn * stretch**2 + kt * gamma**2 + kphi * phi**2) / il
        out[i] = 0.25 * acc


@_exact
def axial_stretch_2d(x, u, offsets, bond_j, inv_length, out):
    """Linearised axial stretch l of every directed bond into ``out`` (n_bonds,)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            il = inv_length[k]
            out[k] = (
                (u[j, 0] - u[i, 0]) * (x[j, 0] - x[i, 0])
                + (u[j, 1] - u[i, 1]) * (x[j, 1] - x[i, 1])
            ) * (il * il)
