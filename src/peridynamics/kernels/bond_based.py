"""Bond-based (PMB / linear microelastic) force, energy and damage kernels.

Every Numba kernel here has a NumPy twin in :mod:`peridynamics.kernels.reference`
that the tests compare against. The kernels gather over each point's family in a
directed CSR bond list (both (i, j) and (j, i) stored), so each point is written by
one thread only: no atomics.

Equations (Lu & Wang (2016), eqs 1-8; SED-PD (2021), eqs 6-11; docs/theory_bond_based.md):

* stretch            s_k = (|xi_k + eta_k| - |xi_k|) / |xi_k|
* force density      f_i = sum_k stiffness_k * mu_k * s_k * (xi_k + eta_k) / |xi_k + eta_k|
* energy density     W_i = 1/4 sum_k stiffness_k * mu_k * s_k**2 * |xi_k|

where ``stiffness_k = c(|xi_k|) * V_j * beta_k * lambda_k`` (micromodulus times partial
volume times surface correction, N/m^6 * m^3) and ``mu_k`` is 1 for intact bonds.

Bond breaking: a bond breaks for good when ``s_k >= (s0_i + s0_j) / 2`` with ``s0`` the
critical stretch of each point (``inf`` for points that may never fail). Point ``i``
and point ``j`` evaluate the same stretch bit-for-bit (the bond vector is computed as a
sum of differences, which is exactly antisymmetric), so both directions of a bond
break in the same evaluation.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

#: hot loops: fast-math lets LLVM vectorise the family sums
_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
#: diagnostics (energy, stretch, damage, stable step) are not hot: no fast-math, so they
#: give the same bits whether compiled in this process or loaded from the cache
_exact = njit(parallel=True, fastmath=False, cache=True)


@njit(inline="always")
def _family_1d(i, x, u, offsets, bond_j, inv_length, stiffness, intact):
    f0 = 0.0
    smax = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        j = bond_j[k]
        e0 = (x[j, 0] - x[i, 0]) + (u[j, 0] - u[i, 0])
        r = np.abs(e0)
        m = intact[k]
        g = stiffness[k] * m * (inv_length[k] - 1.0 / r)  # = c V mu s / r
        f0 += g * e0
        smax = max(smax, (r * inv_length[k] - 1.0) * m)
    return f0, smax


@njit(inline="always")
def _family_2d(i, x, u, offsets, bond_j, inv_length, stiffness, intact):
    x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
    f0 = 0.0
    f1 = 0.0
    smax = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        j = bond_j[k]
        e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
        e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
        r = np.sqrt(e0 * e0 + e1 * e1)
        m = intact[k]
        g = stiffness[k] * m * (inv_length[k] - 1.0 / r)  # = c V mu s / r
        f0 += g * e0
        f1 += g * e1
        smax = max(smax, (r * inv_length[k] - 1.0) * m)
    return f0, f1, smax


@njit(inline="always")
def _family_3d(i, x, u, offsets, bond_j, inv_length, stiffness, intact):
    x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
    u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    smax = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        j = bond_j[k]
        e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
        e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
        e2 = (x[j, 2] - x2) + (u[j, 2] - u2)
        r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        m = intact[k]
        g = stiffness[k] * m * (inv_length[k] - 1.0 / r)  # = c V mu s / r
        f0 += g * e0
        f1 += g * e1
        f2 += g * e2
        smax = max(smax, (r * inv_length[k] - 1.0) * m)
    return f0, f1, f2, smax


@njit(inline="always")
def _reaches_threshold(i, k, x, u, bond_j, inv_length, s0):
    """True when intact-or-not bond ``k`` of point ``i`` has a stretch of at least
    (s0_i + s0_j) / 2. The bond vector is a sum of differences, exactly antisymmetric,
    so point ``j`` takes the same decision for its copy of the bond."""
    d = x.shape[1]
    j = bond_j[k]
    r2 = 0.0
    for c in range(d):
        e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
        r2 += e * e
    s = np.sqrt(r2) * inv_length[k] - 1.0
    return s >= 0.5 * (s0[i] + s0[j])


@njit(inline="always")
def _break_family(i, x, u, offsets, bond_j, inv_length, intact, s0):
    """Break the bonds of point ``i`` whose stretch reaches (s0_i + s0_j) / 2.

    A scalar loop (never vectorised) so that point ``i`` and point ``j`` take the same
    decision for the same bond. Returns the number of bonds broken.
    """
    broken = 0
    for k in range(offsets[i], offsets[i + 1]):
        if intact[k] and _reaches_threshold(i, k, x, u, bond_j, inv_length, s0):
            intact[k] = 0
            broken += 1
    return broken


@_hot
def force_1d(
    x, u, offsets, bond_j, inv_length, stiffness, intact, s0, s0_min, force, smax_out, nbroken
):
    """1-D bond force density (N/m^3) with bond breaking; see the module docstring.

    Parameters
    ----------
    x, u : (n, 1) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j, inv_length (1/|xi|, 1/m), stiffness,
        intact : (n_bonds,).
    s0 : (n,) point critical stretch (``inf`` = never fails).
    s0_min : (n,) smallest bond critical stretch in each family (a cheap filter).
    force : (n, 1) output force density; smax_out : (n,) output largest tensile stretch
        of an intact bond (0 when none is stretched); nbroken : (n,) int64 scratch output,
        bonds broken per point by this call.

    Returns
    -------
    int : number of directed bonds broken by this call.
    """
    n = offsets.shape[0] - 1  # points that own a family (ghosts, if any, follow)
    for i in prange(n):
        f0, smax = _family_1d(i, x, u, offsets, bond_j, inv_length, stiffness, intact)
        nbroken[i] = 0
        if smax >= s0_min[i]:
            nb = _break_family(i, x, u, offsets, bond_j, inv_length, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, smax = _family_1d(i, x, u, offsets, bond_j, inv_length, stiffness, intact)
        force[i, 0] = f0
        smax_out[i] = smax
    return nbroken.sum()


@_hot
def force_2d(
    x, u, offsets, bond_j, inv_length, stiffness, intact, s0, s0_min, force, smax_out, nbroken
):
    """2-D bond force density (N/m^3) with bond breaking; arguments as :func:`force_1d`."""
    n = offsets.shape[0] - 1  # points that own a family (ghosts, if any, follow)
    for i in prange(n):
        f0, f1, smax = _family_2d(i, x, u, offsets, bond_j, inv_length, stiffness, intact)
        nbroken[i] = 0
        if smax >= s0_min[i]:
            nb = _break_family(i, x, u, offsets, bond_j, inv_length, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, f1, smax = _family_2d(i, x, u, offsets, bond_j, inv_length, stiffness, intact)
        force[i, 0] = f0
        force[i, 1] = f1
        smax_out[i] = smax
    return nbroken.sum()


@_hot
def force_3d(
    x, u, offsets, bond_j, inv_length, stiffness, intact, s0, s0_min, force, smax_out, nbroken
):
    """3-D bond force density (N/m^3) with bond breaking; arguments as :func:`force_1d`."""
    n = offsets.shape[0] - 1  # points that own a family (ghosts, if any, follow)
    for i in prange(n):
        f0, f1, f2, smax = _family_3d(i, x, u, offsets, bond_j, inv_length, stiffness, intact)
        nbroken[i] = 0
        if smax >= s0_min[i]:
            nb = _break_family(i, x, u, offsets, bond_j, inv_length, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, f1, f2, smax = _family_3d(
                    i, x, u, offsets, bond_j, inv_length, stiffness, intact
                )
        force[i, 0] = f0
        force[i, 1] = f1
        force[i, 2] = f2
        smax_out[i] = smax
    return nbroken.sum()


@njit(inline="always")
def _family_2d_sed(i, x, u, offsets, bond_j, inv_length, stiffness, intact, k0l, tensile):
    """:func:`_family_2d` plus the strain energy density with the initial stiffness,
    W_i = sum_k k0l_k mu_k s_k^2 with k0l = stiffness0 |xi| / 4 (only s > 0 if
    ``tensile``)."""
    x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
    f0 = 0.0
    f1 = 0.0
    smax = 0.0
    w = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        j = bond_j[k]
        e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
        e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
        r = np.sqrt(e0 * e0 + e1 * e1)
        m = intact[k]
        g = stiffness[k] * m * (inv_length[k] - 1.0 / r)  # = c V mu s / r
        f0 += g * e0
        f1 += g * e1
        s = r * inv_length[k] - 1.0
        smax = max(smax, s * m)
        if tensile and s <= 0.0:
            continue
        w += k0l[k] * m * s * s
    return f0, f1, smax, w


@_hot
def force_sed_2d(
    x, u, offsets, bond_j, inv_length, stiffness, intact, s0, s0_min, force, smax_out, nbroken,
    k0l, tensile, energy,
):  # fmt: skip
    """:func:`force_2d` that also fills ``energy`` (n,) with the SED of SED-PD (2021), eq. 22
    from the initial stiffness (``k0l`` = stiffness0 |xi| / 4, (n_bonds,)), in the same
    pass over the bonds: the softening update then needs no bond loop of its own."""
    n = offsets.shape[0] - 1  # points that own a family (ghosts, if any, follow)
    for i in prange(n):
        f0, f1, smax, w = _family_2d_sed(
            i, x, u, offsets, bond_j, inv_length, stiffness, intact, k0l, tensile
        )
        nbroken[i] = 0
        if smax >= s0_min[i]:
            nb = _break_family(i, x, u, offsets, bond_j, inv_length, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, f1, smax, w = _family_2d_sed(
                    i, x, u, offsets, bond_j, inv_length, stiffness, intact, k0l, tensile
                )
        force[i, 0] = f0
        force[i, 1] = f1
        smax_out[i] = smax
        energy[i] = w
    return nbroken.sum()


FORCE_KERNELS = {1: force_1d, 2: force_2d, 3: force_3d}


@_exact
def bond_stretch(x, u, offsets, bond_j, length, out):
    """Stretch of every directed bond, shape (n_bonds,)."""
    n, d = offsets.shape[0] - 1, x.shape[1]
    for i in prange(n):
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            r2 = 0.0
            for c in range(d):
                e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                r2 += e * e
            out[k] = (np.sqrt(r2) - length[k]) / length[k]


@_exact
def strain_energy_density(x, u, offsets, bond_j, length, stiffness, intact, out):
    """Point strain-energy density W_i = 1/4 sum_k stiffness_k mu_k s_k^2 |xi_k| (J/m^3)."""
    n, d = offsets.shape[0] - 1, x.shape[1]
    for i in prange(n):
        w = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            r2 = 0.0
            for c in range(d):
                e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                r2 += e * e
            s = (np.sqrt(r2) - length[k]) / length[k]
            w += stiffness[k] * intact[k] * s * s * length[k]
        out[i] = 0.25 * w


@_exact
def first_bad_point(u, v, shift, limit):
    """First point with non-finite u or v or |u_c - shift_c| > limit, else -1."""
    n, d = u.shape
    nbad = 0
    for i in prange(n):
        for c in range(d):
            a = u[i, c] - shift[c]
            if not (np.isfinite(a) and np.isfinite(v[i, c]) and abs(a) <= limit):
                nbad += 1
    if nbad == 0:
        return -1
    for i in range(n):  # rare: find the first offender serially
        for c in range(d):
            a = u[i, c] - shift[c]
            if not (np.isfinite(a) and np.isfinite(v[i, c]) and abs(a) <= limit):
                return i
    return -1


@_exact
def damage(offsets, bond_volume, intact, out):
    """Local damage phi_i = 1 - sum mu_k V_k / sum V_k (Lu & Wang (2016), eq. 7), shape (n,).

    Computed as (sum of broken V) / (sum V) without fast-math, so a family with no
    broken bond has exactly zero damage.
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        tot = 0.0
        lost = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            tot += bond_volume[k]
            if not intact[k]:
                lost += bond_volume[k]
        out[i] = lost / tot if tot > 0 else 0.0


@_exact
def stiffness_bound_per_point(offsets, length, stiffness, out):
    """K_i = sum_k stiffness_k / |xi_k| (N/m^4), the Silling & Askari (2005) bound."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            acc += stiffness[k] / length[k]
        out[i] = acc


@_exact
def break_trial(x, u, offsets, bond_j, inv_length, intact, s0, proposed):
    """Critical-stretch trial: ``proposed[k] = 1`` for every intact bond whose stretch
    reaches (s0_i + s0_j) / 2, else 0; ``intact`` is not changed. Returns the number of
    directed bonds proposed. The stretch is computed as in the force kernels'
    breaking pass, so both directions of a bond get the same decision."""
    n = offsets.shape[0] - 1
    count = 0
    for i in prange(n):
        for k in range(offsets[i], offsets[i + 1]):
            proposed[k] = 0
            if intact[k] and _reaches_threshold(i, k, x, u, bond_j, inv_length, s0):
                proposed[k] = 1
                count += 1
    return count


@_exact
def stable_time_step_per_point(offsets, length, stiffness, density, out):
    """Silling & Askari (2005) bound dt_i = sqrt(2 rho_i / sum_k stiffness_k / |xi_k|) (s)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            acc += stiffness[k] / length[k]
        out[i] = np.sqrt(2.0 * density[i] / acc) if acc > 0 else np.inf
