"""The critical-stretch trial of a damage law that is not fused with its force pass (LPS,
correspondence, several bodies): which intact bonds reach (s0_i + s0_j) / 2.

:func:`break_trial_filtered` gives exactly the proposals of
:func:`break_trial` (the same scalar test, compiled
without fast-math, on the same stretch) but runs it only on the families that can hold
such a bond: a vectorised pass over each family (the filter of the PMB force kernels,
r/|xi| above level = 1 + the family's smallest threshold lowered by 1e-12, tested
squared: the positive parts of r^2 - level^2 |xi|^2, no square root) finds them first.
The exact scalar loop, with a square root per bond, cost as much as a whole LPS step
(2-D 500^2, quiet); the filter pass 2.1-2.5 times less when no family is near breaking,
12 % more when a twentieth of the points are."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from peridynamics.kernels.bond_based import _NEVER, _filter, _stretch_of, total_count

_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
_exact = njit(parallel=True, fastmath=False, cache=True)


@njit(fastmath=False)
def _propose_family(i, x, u, offsets, bond_j, intact, s0, proposed):
    """``proposed[k]`` for the bonds of point ``i``: 1 where an intact bond's stretch
    reaches (s0_i + s0_j) / 2 (the test of ``break_trial``, the same bits), else 0.
    Returns the count. Called with ``i`` unsigned: compiled once."""
    count = 0
    for k in range(offsets[i], offsets[i + 1]):
        proposed[k] = 0
        j = bond_j[k]
        if intact[k] and _stretch_of(i, j, x, u) >= 0.5 * (s0[i] + s0[j]):
            proposed[k] = 1
            count += 1
    return count


@njit(inline="always")
def _over(i, x, u, offsets, bond_j, intact, level2):
    """Sum of the positive parts of (r^2 - level2 L^2) over the intact bonds of point
    ``i``: > 0 exactly when some intact bond has r/L above the filter level (squared,
    so no square root and no division; vectorises)."""
    d = x.shape[1]
    over = 0.0
    for k in range(offsets[i], offsets[i + 1]):
        q = np.uint64(k)  # unsigned: plain vector loads
        j = np.uint64(bond_j[q])
        r2 = 0.0
        l2 = 0.0
        for c in range(d):
            dc = x[j, c] - x[i, c]
            ec = dc + (u[j, c] - u[i, c])
            r2 += ec * ec
            l2 += dc * dc
        t = (r2 - level2 * l2) * np.float64(intact[q])
        over += t + np.abs(t)
    return over


@_exact
def break_trial(x, u, offsets, bond_j, intact, s0, proposed):
    """Critical-stretch trial: ``proposed[k] = 1`` for every intact bond whose stretch
    reaches (s0_i + s0_j) / 2, else 0; ``intact`` is not changed. Returns the number of
    directed bonds proposed. The stretch is computed as in the force kernels' breaking
    pass (:func:`peridynamics.kernels.bond_based._break_family`), so both directions of
    a bond get the same decision. Every family runs the exact test (the interface bonds
    of several bodies, which keep no family minimum)."""
    n = offsets.shape[0] - 1
    count = 0
    for i in prange(n):
        count += _propose_family(np.uint64(i), x, u, offsets, bond_j, intact, s0, proposed)
    return count


@_hot
def break_trial_filtered(x, u, offsets, bond_j, intact, s0, s0_min, proposed, counts):
    """Critical-stretch trial with the vectorised filter; ``intact`` is not changed.

    Parameters
    ----------
    x, u : (n_all, d) reference positions and displacements (m), d = 1, 2 or 3.
    offsets : (n + 1,) CSR offsets; bond_j (int32), intact (uint8): (n_bonds,).
    s0 : (n_all,) point critical stretch (``inf``: never fails).
    s0_min : (n,) smallest bond threshold of each family (the filter level).
    proposed : (n_bonds,) uint8 output: 1 for a bond that breaks, else 0.
    counts : (n,) int64 scratch output, the bonds proposed per point.

    Returns
    -------
    int : the number of directed bonds proposed.
    """
    n = offsets.shape[0] - 1
    for i in prange(n):
        q = np.uint64(i)
        counts[i] = 0
        if s0_min[i] < _NEVER:  # else no bond of the family can break
            level = _filter(s0_min[i])
            if _over(q, x, u, offsets, bond_j, intact, level * level) > 0.0:
                counts[i] = _propose_family(q, x, u, offsets, bond_j, intact, s0, proposed)
                continue
        for k in range(offsets[i], offsets[i + 1]):
            proposed[k] = 0
    return total_count(counts)
