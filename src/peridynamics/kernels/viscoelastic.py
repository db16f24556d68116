"""Numba kernel of the viscoelastic LPS (Mitchell (2011), SAND2011-8064): the Maxwell
(back-extension) part of the deviatoric force state, added to the elastic LPS force.

Per directed bond k = (i, j), of reference length L_k and extension e_k, the deviatoric
extension is ``ed_k = e_k - theta_i L_k / 3`` (3-D). The back extension ``eb`` of a
Maxwell element of relaxation time tau obeys ``d eb / dt = (ed - eb) / tau``; for ``ed``
linear in time over a step dt its exact update (Mitchell (2011); Rahman & Foster
(2014)) is

    eb_{n+1} = ed_n (1 - d) + eb_n d + beta (ed_{n+1} - ed_n),
    d = exp(-dt / tau),  beta = 1 - tau (1 - d) / dt.

The force state of the model is ``t_k = (elastic LPS) - lambda a_i wv_k eb_k`` (a_i =
15 mu / m_i, lambda the Maxwell fraction): :func:`viscous_force_3d` adds its pair form
``-lambda (wv_k a_i eb_k + wvf_k a_j eb_k') / r_k`` along the deformed bond (k' the
reverse bond, its trial back extension from theta_j) and writes the trial ``eb`` and
``ed`` of every owned bond. NumPy twin:
:func:`peridynamics.kernels.reference_viscoelastic.viscous_force`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from peridynamics.kernels.lps import _bond_3d

_hot = njit(parallel=True, fastmath=True, error_model="numpy", cache=True)


def decay_and_beta(dt: float, tau: float) -> tuple[float, float]:
    """``d = exp(-dt / tau)`` and ``beta = 1 - tau (1 - d) / dt`` of the exact update
    (Mitchell (2011); Rahman & Foster (2014)) for a step ``dt >= 0`` (s) and a
    relaxation time ``tau > 0`` (s); beta by its series ``x/2 - x^2/6 + x^3/24`` for
    ``x = dt / tau < 1e-4`` (no cancellation; beta = 0 at dt = 0)."""
    x = dt / tau
    decay = math.exp(-x)
    beta = x / 2.0 - x * x / 6.0 + x**3 / 24.0 if x < 1e-4 else 1.0 + math.expm1(-x) / x
    return decay, beta


@_hot
def viscous_force_3d(
    x, u, offsets, bond_j, length, wv, wvf, intact, theta, a, reverse, fraction, decay, beta,
    eb, edn, eb_trial, ed_trial, force,
):  # fmt: skip
    """Add the Maxwell part of the 3-D viscoelastic LPS force density (N/m^3).

    Parameters
    ----------
    x, u : (n, 3) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j, length (m), wv, wvf (m^3), intact :
        (n_bonds,) as in :func:`peridynamics.kernels.lps.force_3d`.
    theta : (n,) dilatation (the LPS pre-pass).
    a : (n,) extension coefficient alpha / m_i (N/m^7).
    reverse : (n_bonds,) index of bond (j, i) for bond (i, j).
    fraction : float, lambda in [0, 1]; decay, beta : floats of the exact update.
    eb, edn : (n_bonds,) committed back extension and deviatoric extension (m).
    eb_trial, ed_trial : (n_bonds,) outputs: the trial back and deviatoric extension.
    force : (n, 3) force density, added to (rows ``0..n-1``).
    """
    n = offsets.shape[0] - 1
    third = 1.0 / 3.0
    keep = 1.0 - decay
    for i in prange(n):
        ai = a[i]
        ti = theta[i] * third
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            rk = reverse[k]
            lk = length[k]
            y0, y1, y2, r, e = _bond_3d(x, u, i, j, lk)
            ed_i = e - ti * lk
            ed_j = e - theta[j] * third * lk
            eb_i = edn[k] * keep + eb[k] * decay + beta * (ed_i - edn[k])
            eb_j = edn[rk] * keep + eb[rk] * decay + beta * (ed_j - edn[rk])
            eb_trial[k] = eb_i
            ed_trial[k] = ed_i
            g = -fraction * np.float64(intact[k]) * (wv[k] * ai * eb_i + wvf[k] * a[j] * eb_j) / r
            f0 += g * y0
            f1 += g * y1
            f2 += g * y2
        force[i, 0] += f0
        force[i, 1] += f1
        force[i, 2] += f2
