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


#: bonds of points whose filter threshold is infinite never break; the filter works with
#: this finite stand-in so that (r / L - threshold) stays finite (fast-math assumes it)
_NEVER = 1.0e300
#: the filter's threshold is lowered by this fraction: it must let through every bond the
#: exact test breaks, whatever the rounding of the vectorised stretch
_FILTER_MARGIN = 1.0e-12


@njit(inline="always")
def _filter(s0_min_i):
    """Per-point filter level on r/L: bonds above it get the exact breaking test."""
    return (1.0 + min(s0_min_i, _NEVER)) * (1.0 - _FILTER_MARGIN)


@njit(inline="always")
def _family_1d(i, x, u, offsets, bond_j, stiffness, intact, level):
    x0, u0 = x[i, 0], u[i, 0]
    f0 = 0.0
    over = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        q = np.uint64(k)  # unsigned: no negative-index wraparound, plain vector loads
        j = np.uint64(bond_j[q])
        d0 = x[j, 0] - x0
        e0 = d0 + (u[j, 0] - u0)
        inv_l = 1.0 / np.abs(d0)
        r = np.abs(e0)
        m = np.float64(intact[q])
        g = stiffness[q] * m * (inv_l - 1.0 / r)  # = c V mu s / r
        f0 += g * e0
        t = (r * inv_l - level) * m
        over += t + np.abs(t)  # > 0 iff some intact bond is above the filter level
    return f0, over


@njit(inline="always")
def _family_2d(i, x, u, offsets, bond_j, stiffness, intact, level):
    x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
    f0 = 0.0
    f1 = 0.0
    over = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        q = np.uint64(k)
        j = np.uint64(bond_j[q])
        d0 = x[j, 0] - x0
        d1 = x[j, 1] - x1
        e0 = d0 + (u[j, 0] - u0)
        e1 = d1 + (u[j, 1] - u1)
        inv_l = 1.0 / np.sqrt(d0 * d0 + d1 * d1)
        r = np.sqrt(e0 * e0 + e1 * e1)
        m = np.float64(intact[q])
        g = stiffness[q] * m * (inv_l - 1.0 / r)
        f0 += g * e0
        f1 += g * e1
        t = (r * inv_l - level) * m
        over += t + np.abs(t)
    return f0, f1, over


@njit(inline="always")
def _family_3d(i, x, u, offsets, bond_j, stiffness, intact, level):
    x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
    u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    over = 0.0
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
        m = np.float64(intact[q])
        g = stiffness[q] * m * (inv_l - 1.0 / r)
        f0 += g * e0
        f1 += g * e1
        f2 += g * e2
        t = (r * inv_l - level) * m
        over += t + np.abs(t)
    return f0, f1, f2, over


@njit(inline="always")
def _lengths(i, j, x, u):
    """(|xi + eta|, |xi|) of bond (i, j) with xi = x_j - x_i, squares summed in component
    order (the bits of the bond list's ``bond_length``). The vectors are sums of
    differences, exactly antisymmetric, so (j, i) gets the same bits."""
    r2 = 0.0
    l2 = 0.0
    for c in range(x.shape[1]):
        d = x[j, c] - x[i, c]
        e = d + (u[j, c] - u[i, c])
        l2 += d * d
        r2 += e * e
    return np.sqrt(r2), np.sqrt(l2)


@njit(inline="always")
def _stretch_of(i, j, x, u):
    """Stretch of bond (i, j): |xi + eta| * (1 / |xi|) - 1, as the breaking tests take it."""
    r, length = _lengths(i, j, x, u)
    return r * (1.0 / length) - 1.0


@njit
def total_count(counts):
    """Sum of an int64 array (bonds broken per point), in a serial loop: a ``.sum()`` in
    a parallel kernel is a parallel reduction, one more gufunc to compile for a sum of
    n integers (exact in any order)."""
    total = 0
    for i in range(counts.shape[0]):
        total += counts[i]
    return total


@njit(fastmath=False)
def _break_family(i, x, u, offsets, bond_j, intact, s0):
    """Break the bonds of point ``i`` whose stretch reaches (s0_i + s0_j) / 2.

    Not inlined and compiled without fast-math: a scalar loop whose every decision has
    the same bits as :func:`peridynamics.kernels.bond_trial.break_trial`'s, so point
    ``i`` and point ``j`` take the same decision for the same bond. Returns the number of
    bonds broken. Called with ``i`` unsigned (the type of prange's index in the parallel
    loop): compiled once.
    """
    broken = 0
    for k in range(offsets[i], offsets[i + 1]):
        j = bond_j[k]
        if intact[k] and _stretch_of(i, j, x, u) >= 0.5 * (s0[i] + s0[j]):
            intact[k] = 0
            broken += 1
    return broken


@_hot
def force_1d(x, u, offsets, bond_j, stiffness, intact, s0, s0_min, force, nbroken):
    """1-D bond force density (N/m^3) with bond breaking; see the module docstring.

    Parameters
    ----------
    x, u : (n, 1) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j (int32), stiffness (float64), intact (uint8):
        (n_bonds,). Bond lengths are recomputed from ``x`` (nothing else is read per bond).
    s0 : (n,) point critical stretch (``inf`` = never fails).
    s0_min : (n,) smallest bond critical stretch in each family (a cheap filter).
    force : (n, 1) output force density; nbroken : (n,) int64 scratch output, bonds
        broken per point by this call.

    Returns
    -------
    int : number of directed bonds broken by this call.

    Notes
    -----
    The family loop vectorises: unsigned indices, no branch, and instead of the largest
    stretch (a max reduction LLVM does not vectorise here) a sum of positive parts that
    is > 0 exactly when some intact bond is above the filter level; only those points
    run the exact breaking pass. :func:`largest_stretch` gives the largest stretch.
    """
    n = offsets.shape[0] - 1  # points that own a family (ghosts, if any, follow)
    for i in prange(n):
        level = _filter(s0_min[i])
        f0, over = _family_1d(i, x, u, offsets, bond_j, stiffness, intact, level)
        nbroken[i] = 0
        if over > 0.0:
            nb = _break_family(np.uint64(i), x, u, offsets, bond_j, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, over = _family_1d(i, x, u, offsets, bond_j, stiffness, intact, level)
        force[i, 0] = f0
    return total_count(nbroken)


@_hot
def force_2d(x, u, offsets, bond_j, stiffness, intact, s0, s0_min, force, nbroken):
    """2-D bond force density (N/m^3) with bond breaking; arguments as :func:`force_1d`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        level = _filter(s0_min[i])
        f0, f1, over = _family_2d(i, x, u, offsets, bond_j, stiffness, intact, level)
        nbroken[i] = 0
        if over > 0.0:
            nb = _break_family(np.uint64(i), x, u, offsets, bond_j, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, f1, over = _family_2d(i, x, u, offsets, bond_j, stiffness, intact, level)
        force[i, 0] = f0
        force[i, 1] = f1
    return total_count(nbroken)


@_hot
def force_3d(x, u, offsets, bond_j, stiffness, intact, s0, s0_min, force, nbroken):
    """3-D bond force density (N/m^3) with bond breaking; arguments as :func:`force_1d`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        level = _filter(s0_min[i])
        f0, f1, f2, over = _family_3d(i, x, u, offsets, bond_j, stiffness, intact, level)
        nbroken[i] = 0
        if over > 0.0:
            nb = _break_family(np.uint64(i), x, u, offsets, bond_j, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, f1, f2, over = _family_3d(i, x, u, offsets, bond_j, stiffness, intact, level)
        force[i, 0] = f0
        force[i, 1] = f1
        force[i, 2] = f2
    return total_count(nbroken)


@njit(inline="always")
def _family_2d_sed(i, x, u, offsets, bond_j, stiffness, intact, level, k0l, tensile):
    """:func:`_family_2d` plus the strain energy density with the initial stiffness,
    W_i = sum_k k0l_k mu_k s_k^2 with k0l = stiffness0 |xi| / 4 (only s > 0 if
    ``tensile``)."""
    x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
    f0 = 0.0
    f1 = 0.0
    over = 0.0
    w = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        q = np.uint64(k)
        j = np.uint64(bond_j[q])
        d0 = x[j, 0] - x0
        d1 = x[j, 1] - x1
        e0 = d0 + (u[j, 0] - u0)
        e1 = d1 + (u[j, 1] - u1)
        inv_l = 1.0 / np.sqrt(d0 * d0 + d1 * d1)
        r = np.sqrt(e0 * e0 + e1 * e1)
        m = np.float64(intact[q])
        g = stiffness[q] * m * (inv_l - 1.0 / r)
        f0 += g * e0
        f1 += g * e1
        s = r * inv_l - 1.0
        t = (r * inv_l - level) * m
        over += t + np.abs(t)
        if tensile and s <= 0.0:
            continue
        w += k0l[q] * m * s * s
    return f0, f1, over, w


@_hot
def force_sed_2d(
    x, u, offsets, bond_j, stiffness, intact, s0, s0_min, force, nbroken, k0l, tensile, energy
):
    """:func:`force_2d` that also fills ``energy`` (n,) with the SED of SED-PD (2021), eq. 22
    from the initial stiffness (``k0l`` = stiffness0 |xi| / 4, (n_bonds,)), in the same
    pass over the bonds: the softening update then needs no bond loop of its own."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        level = _filter(s0_min[i])
        f0, f1, over, w = _family_2d_sed(
            i, x, u, offsets, bond_j, stiffness, intact, level, k0l, tensile
        )
        nbroken[i] = 0
        if over > 0.0:
            nb = _break_family(np.uint64(i), x, u, offsets, bond_j, intact, s0)
            if nb > 0:
                nbroken[i] = nb
                f0, f1, over, w = _family_2d_sed(
                    i, x, u, offsets, bond_j, stiffness, intact, level, k0l, tensile
                )
        force[i, 0] = f0
        force[i, 1] = f1
        energy[i] = w
    return total_count(nbroken)


FORCE_KERNELS = {1: force_1d, 2: force_2d, 3: force_3d}


@_exact
def bond_stretch(x, u, offsets, bond_j, out):
    """Stretch of every directed bond, shape (n_bonds,); |xi| recomputed from ``x``."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        for k in range(offsets[i], offsets[i + 1]):
            r, length = _lengths(i, bond_j[k], x, u)
            out[k] = (r - length) / length


@njit(inline="always")
def _length(i, j, x):
    """|x_j - x_i| (m), the same bits as the bond list's ``bond_length``."""
    l2 = 0.0
    for c in range(x.shape[1]):
        d = x[j, c] - x[i, c]
        l2 += d * d
    return np.sqrt(l2)


@njit(fastmath=False)
def _largest_of_family(i, x, u, offsets, bond_j, intact):
    """Largest stretch of an intact bond of point ``i`` (0 when none is stretched)."""
    smax = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        if intact[k]:
            smax = max(smax, _stretch_of(i, bond_j[k], x, u))
    return smax


@_hot
def largest_stretch(x, u, offsets, bond_j, intact, above, out):
    """Largest stretch of an intact bond per point, (n,), where it exceeds ``above``;
    0 elsewhere (``above`` = 0: everywhere a bond is stretched).

    A vectorised pass over each family (the filter of the force kernels: the positive
    parts of r/|xi| - level, level = 1 + ``above`` lowered by 1e-12) finds the points
    with such a bond; only they run the exact scalar max. The stability check asks
    for stretches above its limit (100 %), so it costs one vectorised pass.
    """
    n = offsets.shape[0] - 1
    level = (1.0 + max(above, 0.0)) * (1.0 - _FILTER_MARGIN)
    d = x.shape[1]
    for i in prange(n):
        # the force kernels' family loops with the flags standing in for the stiffness:
        # only the filter sum is used (the force sums are dead code after inlining)
        if d == 1:
            over = _family_1d(i, x, u, offsets, bond_j, intact, intact, level)[1]
        elif d == 2:
            over = _family_2d(i, x, u, offsets, bond_j, intact, intact, level)[2]
        else:
            over = _family_3d(i, x, u, offsets, bond_j, intact, intact, level)[3]
        # the helper's index unsigned, as prange's in the parallel loop: one compile
        q = np.uint64(i)
        out[i] = _largest_of_family(q, x, u, offsets, bond_j, intact) if over > 0.0 else 0.0


@_exact
def strain_energy_density(x, u, offsets, bond_j, stiffness, intact, out):
    """Point strain-energy density W_i = 1/4 sum_k stiffness_k mu_k s_k^2 |xi_k| (J/m^3)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        w = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            r, length = _lengths(i, bond_j[k], x, u)
            s = (r - length) / length
            w += stiffness[k] * intact[k] * s * s * length
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


#: partial-volume rules by number, for :func:`damage_derived`
PARTIAL_VOLUME_CODES = {"none": 0, "truncated": 1, "extended": 2}


@njit(inline="always")
def _partial_volume(length, horizon, dx, rule):
    """beta(|xi|) of :func:`peridynamics.bonds.partial_volume.partial_volume_factor`,
    the same operations in the same order (the same bits)."""
    h = horizon * (1.0 + 1e-9)
    if rule == 0:
        return 1.0 if length <= h else 0.0
    if rule == 1:
        beta = min(max((horizon - length) / dx + 0.5, 0.0), 1.0)
        return beta if length <= h else 0.0
    beta = min(max((horizon + 0.5 * dx - length) / dx, 0.0), 1.0)
    return beta if length < (horizon + 0.5 * dx) * (1 - 1e-9) else 0.0


@_exact
def damage_derived(x, offsets, bond_j, point_volume, horizon, dx, rule, intact, out):
    """:func:`damage` with the partial volumes beta(|xi|) V_j recomputed from ``x`` and
    the point volumes (``rule``: :data:`PARTIAL_VOLUME_CODES`), so the bond list need not
    hold them; the same bits as :func:`damage` on the derived ``bond_volume``."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        tot = 0.0
        lost = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            vol = _partial_volume(_length(i, j, x), horizon, dx, rule) * point_volume[j]
            tot += vol
            if not intact[k]:
                lost += vol
        out[i] = lost / tot if tot > 0 else 0.0


@_exact
def stiffness_bound_per_point(x, offsets, bond_j, stiffness, out):
    """K_i = sum_k stiffness_k / |xi_k| (N/m^4), the Silling & Askari (2005) bound."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            acc += stiffness[k] / _length(i, bond_j[k], x)
        out[i] = acc


@_exact
def stable_time_step_per_point(x, offsets, bond_j, stiffness, density, out):
    """Silling & Askari (2005) bound dt_i = sqrt(2 rho_i / sum_k stiffness_k / |xi_k|) (s)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        acc = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            acc += stiffness[k] / _length(i, bond_j[k], x)
        out[i] = np.sqrt(2.0 * density[i] / acc) if acc > 0 else np.inf
