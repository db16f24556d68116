"""Kernel of the isotropy factor of a bond-based family on a regular grid
(:mod:`peridynamics.families.pmb.isotropy`): ``g(n) = 1 + sum_p lam_p phi_p(n)`` of every
bond, ``phi_p`` the quartic monomials of the bond direction n. NumPy twin:
:func:`peridynamics.families.calibration.quartic_values` times ``lam``."""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

_exact = njit(parallel=True, fastmath=False, cache=True)


@_exact
def direction_factors(xi, lam, monos):  # pragma: no cover - compiled
    """``1 + sum_p lam[p] n_a n_b n_c n_e`` for every bond vector.

    Parameters
    ----------
    xi : (n_bonds, dim) float64
        Bond vectors (m).
    lam : (P,) float64
        Coefficients of the monomials.
    monos : (P, 4) int64
        Axes (a, b, c, e) of each monomial.

    Returns
    -------
    (n_bonds,) float64
        The factor of every bond (each bond alone, the same bits in any range).
    """
    nb, dim = xi.shape
    out = np.empty(nb)
    n_p = lam.shape[0]
    for k in prange(nb):
        s = 0.0
        for c in range(dim):
            s += xi[k, c] * xi[k, c]
        inv = 1.0 / math.sqrt(s)
        acc = 1.0
        for p in range(n_p):
            acc += (
                lam[p]
                * (xi[k, monos[p, 0]] * inv)
                * (xi[k, monos[p, 1]] * inv)
                * (xi[k, monos[p, 2]] * inv)
                * (xi[k, monos[p, 3]] * inv)
            )
        out[k] = acc
    return out
