"""Strain-energy-density softening kernel (SED-PD (2021), eqs 18-24). NumPy twin:
:func:`peridynamics.kernels.reference.sed_update`.

A hot kernel (called before every force evaluation): fast-math lets LLVM vectorise the
family sum, like the bond-force kernels; the thresholds are compared with the energy
it computes, so a level can differ from the NumPy twin only for energies within
round-off of a threshold.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

#: fast-math without "no infs / no NaNs": thresholds of no-fail points are huge, and a
#: comparison must stay a comparison
_FAST = {"nsz", "arcp", "contract", "afn", "reassoc"}


@njit(inline="always")
def _raise_level(i, w, w_a, w_c, n_levels, level, raised):
    """Level of energy ``w`` (0 below w_a, 1 + floor(N (w - w_a)/(w_c - w_a)) up to N,
    N + 1 from w_c on); raise ``level[i]`` to it if higher (irreversible), flag it in
    ``raised``. Returns 1 if the level rose, else 0."""
    if w < w_a[i]:
        new = 0
    elif w < w_c[i]:
        new = min(1 + int(np.floor(n_levels * (w - w_a[i]) / (w_c[i] - w_a[i]))), n_levels)
    else:
        new = n_levels + 1
    if new > level[i]:
        level[i] = new
        raised[i] = 1
        return 1
    raised[i] = 0
    return 0


@njit(parallel=True, fastmath=_FAST, error_model="numpy", cache=True)
def sed_update(
    x, u, offsets, bond_j, length, stiffness0, intact, w_a, w_c, n_levels, level, energy,
    tensile_only, raised,
):  # pragma: no cover - compiled  # fmt: skip
    """Update the softening level of every point from its strain energy density.

    energy[i] = 1/4 sum_k stiffness0_k mu_k s_k^2 |xi_k| (J/m^3, eq. 22, initial moduli),
    over the stretched bonds only (s_k > 0) when ``tensile_only``;
    new level 0 below w_a[i], 1 + floor(N (W - w_a) / (w_c - w_a)) (at most N) in
    [w_a, w_c), N + 1 at or above w_c; level[i] = max(old, new) (irreversible).
    ``raised`` (n,) uint8 flags the points whose level rose.
    Returns the number of points whose level rose; the caller then rebuilds the bond
    stiffness with :func:`sed_stiffness_raised`.
    """
    n, d = offsets.shape[0] - 1, x.shape[1]
    changed = 0
    for i in prange(n):
        w = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k] == 0:
                continue
            j = bond_j[k]
            r2 = 0.0
            for c in range(d):
                e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                r2 += e * e
            s = np.sqrt(r2) / length[k] - 1.0
            if tensile_only and s <= 0.0:
                continue
            w += stiffness0[k] * s * s * length[k]
        w *= 0.25
        energy[i] = w
        changed += _raise_level(i, w, w_a, w_c, n_levels, level, raised)
    return changed


@njit(parallel=True, fastmath=False, cache=True)
def sed_levels(energy, w_a, w_c, n_levels, level, raised):  # pragma: no cover - compiled
    """The level update of :func:`sed_update` from energies computed elsewhere (the
    fused 2-D force kernel). Returns the number of points whose level rose."""
    n = energy.shape[0]
    changed = 0
    for i in prange(n):
        changed += _raise_level(i, energy[i], w_a, w_c, n_levels, level, raised)
    return changed


@njit(inline="always")
def _factor(lv, n_levels, residual):
    if lv == 0:
        return 1.0
    if lv == n_levels + 1:
        return residual
    return (n_levels + 1 - lv) / n_levels


@njit(parallel=True, fastmath=False, cache=True)
def sed_stiffness_raised(
    offsets, bond_j, stiffness0, level, n_levels, residual, factor, stiffness, raised
):  # pragma: no cover - compiled
    """:func:`sed_stiffness` for the bonds that touch a point flagged in ``raised``: the
    same bits as a full rebuild. Each point rewrites only its own bonds (bond k of point
    i is rebuilt when i or its partner j rose), so no kernel writes another point's
    data."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        if raised[i]:
            factor[i] = _factor(level[i], n_levels, residual)
    for i in prange(n):
        own = raised[i]
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            if own or raised[j]:
                stiffness[k] = stiffness0[k] * 0.5 * (factor[i] + factor[j])


@njit(parallel=True, fastmath=False, cache=True)
def sed_stiffness(
    offsets, bond_j, stiffness0, level, n_levels, residual, factor, stiffness
):  # pragma: no cover - compiled
    """factor_i = E_i / E from the levels (1, (N + 1 - n) / N, residual for 0, n = 1..N,
    N + 1) and stiffness_k = stiffness0_k (factor_i + factor_j) / 2 (eq. 24). Exact
    arithmetic (no fast-math): a run resumed from a checkpoint rebuilds the same bits."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        factor[i] = _factor(level[i], n_levels, residual)
    for i in prange(n):
        for k in range(offsets[i], offsets[i + 1]):
            stiffness[k] = stiffness0[k] * 0.5 * (factor[i] + factor[bond_j[k]])
