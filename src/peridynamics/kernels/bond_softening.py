"""Tension-softening bond kernels (bilinear / trilinear envelope) for bond-based PMB.

Every kernel has a NumPy twin in :mod:`peridynamics.kernels.reference_softening`. As in
:mod:`peridynamics.kernels.bond_based` the kernels gather over each point's family of a
directed CSR bond list, write only the owning point's entries (its force row and the
history of its own bonds), never allocate inside the parallel loop, and compute the
bond vector as (x_j - x_i) + (u_j - u_i) so that (i, j) and (j, i) see the same stretch
bit for bit (and therefore soften and break together).

Bond law (docs/theory_bond_based.md, "Tension softening"; the shape is Petersson 1981):

* envelope g(s) (stretch units, force = stiffness g): s up to s0, then linear to
  beta s0 at s1 = s0 + r (s_f - s0), then linear to 0 at s_f (bilinear: r = beta = 1/2,
  the knee lies on the straight line);
* history kappa_k = the largest tensile stretch bond k has reached; the trial value of
  an evaluation is kappa' = max(kappa, s);
* secant factor h(kappa') = g(kappa') / kappa' (1 up to s0): a stretched bond carries
  stiffness h s, a compressed one stiffness s, a bond with kappa' >= s_f nothing;
* per bond s0 = (s0_i + s0_j)/2 and s_f = (sf_i + sf_j)/2 from per-point arrays, so
  no-fail points (inf) give bonds that never soften.

The kernels are compiled without fast-math: the trial (:func:`trial`), the commit
inside :func:`force_1d` ... and the force pass must agree on the stretch to the bit.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from peridynamics.kernels.bond_based import total_count

_kernel = njit(parallel=True, fastmath=False, error_model="numpy", cache=True)


@njit(inline="always")
def _secant(kap, s0, sf, r, beta):
    """h = g(kap)/kap for s0 < kap < sf (the callers handle kap <= s0 and kap >= sf)."""
    s1 = s0 + r * (sf - s0)
    if kap <= s1:
        g = s0 + (beta * s0 - s0) * ((kap - s0) / (s1 - s0))
    else:
        g = beta * s0 * ((sf - kap) / (sf - s1))
    return g / kap


@njit(inline="always")
def _factor(k, i, j, s, kappa, intact, s0, sf, r, beta):
    """(h, kap', alive) of bond k: the stiffness factor of its force at stretch s, its
    trial history kap' = max(kappa_k, s) and whether it still carries load."""
    kap = max(kappa[k], s)
    s0b = 0.5 * (s0[i] + s0[j])
    sfb = 0.5 * (sf[i] + sf[j])
    if intact[k] == 0 or kap >= sfb:
        return 0.0, kap, False
    if s <= 0.0 or kap <= s0b:
        return 1.0, kap, True
    return _secant(kap, s0b, sfb, r, beta), kap, True


@njit(inline="always")
def _family_1d(i, x, u, offsets, bond_j, inv_length, stiffness, intact, kappa, s0, sf, r, beta):
    f0 = 0.0
    smax = 0.0
    grow = False
    for k in range(offsets[i], offsets[i + 1]):
        j = bond_j[k]
        e0 = (x[j, 0] - x[i, 0]) + (u[j, 0] - u[i, 0])
        rr = np.sqrt(e0 * e0)
        s = rr * inv_length[k] - 1.0
        h, kap, alive = _factor(k, i, j, s, kappa, intact, s0, sf, r, beta)
        g = stiffness[k] * h * (inv_length[k] - 1.0 / rr)  # = stiffness h s / |xi + eta|
        f0 += g * e0
        if alive:
            smax = max(smax, s)
        grow = grow or (intact[k] != 0 and (kap > kappa[k] or not alive))
    return f0, smax, grow


@njit(inline="always")
def _family_2d(i, x, u, offsets, bond_j, inv_length, stiffness, intact, kappa, s0, sf, r, beta):
    x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
    f0 = 0.0
    f1 = 0.0
    smax = 0.0
    grow = False
    for k in range(offsets[i], offsets[i + 1]):
        j = bond_j[k]
        e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
        e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
        rr = np.sqrt(e0 * e0 + e1 * e1)
        s = rr * inv_length[k] - 1.0
        h, kap, alive = _factor(k, i, j, s, kappa, intact, s0, sf, r, beta)
        g = stiffness[k] * h * (inv_length[k] - 1.0 / rr)
        f0 += g * e0
        f1 += g * e1
        if alive:
            smax = max(smax, s)
        grow = grow or (intact[k] != 0 and (kap > kappa[k] or not alive))
    return f0, f1, smax, grow


@njit(inline="always")
def _family_3d(i, x, u, offsets, bond_j, inv_length, stiffness, intact, kappa, s0, sf, r, beta):
    x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
    u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    smax = 0.0
    grow = False
    for k in range(offsets[i], offsets[i + 1]):
        j = bond_j[k]
        e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
        e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
        e2 = (x[j, 2] - x2) + (u[j, 2] - u2)
        rr = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        s = rr * inv_length[k] - 1.0
        h, kap, alive = _factor(k, i, j, s, kappa, intact, s0, sf, r, beta)
        g = stiffness[k] * h * (inv_length[k] - 1.0 / rr)
        f0 += g * e0
        f1 += g * e1
        f2 += g * e2
        if alive:
            smax = max(smax, s)
        grow = grow or (intact[k] != 0 and (kap > kappa[k] or not alive))
    return f0, f1, f2, smax, grow


@njit(inline="always")
def _stretch(i, k, x, u, bond_j, inv_length):
    """Stretch of bond k of point i, the same bits as the family passes."""
    j = bond_j[k]
    r2 = 0.0
    for c in range(x.shape[1]):
        e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
        r2 += e * e
    return np.sqrt(r2) * inv_length[k] - 1.0


@njit(inline="always")
def _trial_bond(i, k, x, u, bond_j, inv_length, intact, kappa, s0, sf):
    """(kap', breaks) of bond k: its trial history and whether it fails (kap' >= s_f)."""
    if intact[k] == 0:
        return kappa[k], False
    j = bond_j[k]
    kap = max(kappa[k], _stretch(i, k, x, u, bond_j, inv_length))
    return kap, kap >= 0.5 * (sf[i] + sf[j])


@njit(inline="always")
def _commit_family(i, x, u, offsets, bond_j, inv_length, intact, kappa, s0, sf):
    """Commit the trial of point i's bonds in place (kappa, intact); returns the number
    of bonds broken. Scalar, so both copies of a bond take the same decision."""
    broken = 0
    for k in range(offsets[i], offsets[i + 1]):
        kap, brk = _trial_bond(i, k, x, u, bond_j, inv_length, intact, kappa, s0, sf)
        kappa[k] = kap
        if brk:
            intact[k] = 0
            broken += 1
    return broken


@_kernel
def force_1d(
    x, u, offsets, bond_j, inv_length, stiffness, intact, kappa, s0, sf, r, beta,
    force, smax_out, commit, nbroken,
):  # fmt: skip
    """1-D softening bond force density (N/m^3); see the module docstring.

    Parameters
    ----------
    x, u : (n, 1) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j, inv_length (1/|xi|, 1/m), stiffness
        (c beta V_j lambda, N/m^6 m^3), intact (uint8), kappa (history, largest tensile
        stretch reached) : (n_bonds,).
    s0, sf : (n,) per-point peak and failure stretch (``inf``: never softens).
    r, beta : float
        Knee of the envelope: s1 = s0 + r (s_f - s0), g(s1) = beta s0.
    force : (n, 1) output force density; smax_out : (n,) output largest tensile stretch
        of a bond that still carries load.
    commit : bool
        False: pure force with the trial history max(kappa, s). True: also commit it
        (kappa and intact of the family, in place), the same bits as :func:`trial`, its
        commit and the pure force in turn.
    nbroken : (n,) int64 scratch output, bonds broken per point.

    Returns
    -------
    int : number of directed bonds broken by this call (0 when ``commit`` is False).
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        f0, smax, grow = _family_1d(
            i, x, u, offsets, bond_j, inv_length, stiffness, intact, kappa, s0, sf, r, beta
        )
        nbroken[i] = 0
        if commit and grow:
            nbroken[i] = _commit_family(i, x, u, offsets, bond_j, inv_length, intact, kappa, s0, sf)
        force[i, 0] = f0
        smax_out[i] = smax
    return total_count(nbroken)


@_kernel
def force_2d(
    x, u, offsets, bond_j, inv_length, stiffness, intact, kappa, s0, sf, r, beta,
    force, smax_out, commit, nbroken,
):  # fmt: skip
    """2-D softening bond force density (N/m^3); arguments as :func:`force_1d`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        f0, f1, smax, grow = _family_2d(
            i, x, u, offsets, bond_j, inv_length, stiffness, intact, kappa, s0, sf, r, beta
        )
        nbroken[i] = 0
        if commit and grow:
            nbroken[i] = _commit_family(i, x, u, offsets, bond_j, inv_length, intact, kappa, s0, sf)
        force[i, 0] = f0
        force[i, 1] = f1
        smax_out[i] = smax
    return total_count(nbroken)


@_kernel
def force_3d(
    x, u, offsets, bond_j, inv_length, stiffness, intact, kappa, s0, sf, r, beta,
    force, smax_out, commit, nbroken,
):  # fmt: skip
    """3-D softening bond force density (N/m^3); arguments as :func:`force_1d`."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        f0, f1, f2, smax, grow = _family_3d(
            i, x, u, offsets, bond_j, inv_length, stiffness, intact, kappa, s0, sf, r, beta
        )
        nbroken[i] = 0
        if commit and grow:
            nbroken[i] = _commit_family(i, x, u, offsets, bond_j, inv_length, intact, kappa, s0, sf)
        force[i, 0] = f0
        force[i, 1] = f1
        force[i, 2] = f2
        smax_out[i] = smax
    return total_count(nbroken)


FORCE_KERNELS = {1: force_1d, 2: force_2d, 3: force_3d}


@_kernel
def trial(x, u, offsets, bond_j, inv_length, intact, kappa, s0, sf, kappa_out, proposed):
    """Softening trial: ``kappa_out[k] = max(kappa_k, s_k)`` for every intact bond
    (``kappa_k`` otherwise) and ``proposed[k] = 1`` where that reaches the bond's
    s_f = (sf_i + sf_j)/2 (else 0). Nothing of the State changes. Returns the number of
    directed bonds proposed to break."""
    n = offsets.shape[0] - 1
    count = 0
    for i in prange(n):
        for k in range(offsets[i], offsets[i + 1]):
            kap, brk = _trial_bond(i, k, x, u, bond_j, inv_length, intact, kappa, s0, sf)
            kappa_out[k] = kap
            proposed[k] = 1 if brk else 0
            if brk:
                count += 1
    return count


@_kernel
def energy_density(
    x, u, offsets, bond_j, inv_length, length, stiffness, intact, kappa, s0, sf, r, beta, out
):
    """Recoverable strain energy density W_i = 1/4 sum_k stiffness_k h_k s_k^2 |xi_k|
    (J/m^3), shape (n,), with h_k the force factor of the trial history (1 for a
    compressed bond, 0 for a failed one). On the unloading/reloading branch
    (s <= kappa) the force is exactly -grad of the total sum_i W_i V_i."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        w = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            s = _stretch(i, k, x, u, bond_j, inv_length)
            h = _factor(k, i, bond_j[k], s, kappa, intact, s0, sf, r, beta)[0]
            w += stiffness[k] * h * s * s * length[k]
        out[i] = 0.25 * w
