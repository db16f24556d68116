"""Point stress and strain kernels: the peridynamic (virial) stress of a pairwise force
and the nonlocal deformation gradient of a family, any family, 1-D to 3-D.

Every Numba kernel here has a NumPy twin in :mod:`peridynamics.kernels.reference_stress`
that the tests compare against. The kernels gather over each point's family in the
directed CSR bond list (both (i, j) and (j, i) stored) and write only the rows of the
points that own a family, ``n = offsets.shape[0] - 1``: no atomics. They are
diagnostics (frames, probes), not hot loops: no fast-math, reproducible bits.

Notation (per directed bond k = (i, j)): ``xi_k = x_j - x_i``, ``y_k = xi_k + u_j - u_i``.

* Peridynamic stress: the force-flux stress of Lehoucq & Silling (2008), an integral
  over the bonds that pass through a point, reduces for a homogeneous deformation to
  the virial form below (its integral over the length of each bond gives the factor
  ``|xi|``; Li (2021) shows the general tensor is a weighted virial stress):
  ``sigma_i = 1/2 sum_k g_k y_k (x) xi_k`` with ``g_k y_k`` the pairwise force density
  of bond k times the partial volume of its far point (N/m^3): the family's own force,
  so that ``sum_k g_k y_k`` is the force density of point i.
* Nonlocal deformation gradient (the shape tensor and F of the correspondence model of
  Silling et al. (2007), with unit influence and the partial volumes as weights):
  ``K_i = sum_k mu_k w_k xi_k (x) xi_k``, ``N_i = sum_k mu_k w_k y_k (x) xi_k``,
  ``F_i = N_i K_i^-1``; the identity where K_i is singular (``DEGENERATE``: a family
  with fewer than ``dim`` independent intact bonds).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

#: diagnostics: no fast-math, the same bits compiled or loaded from the cache
_exact = njit(parallel=True, fastmath=False, cache=True)


@_exact
def virial_stress(x, u, offsets, bond_j, g, out):
    """Peridynamic stress ``sigma_i = 1/2 sum_k g_k y_k (x) xi_k`` (Pa).

    Parameters
    ----------
    x, u : (n_all, d) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j : (n_bonds,) far points.
    g : (n_bonds,) pair-force coefficient: the bond's force density on point i is
        ``g_k y_k`` (N/m^4; zero for a broken bond).
    out : (n, d, d) output stress; rows ``0..n-1`` are written.
    """
    n = offsets.shape[0] - 1
    d = x.shape[1]
    for i in prange(n):
        for a in range(d):
            for b in range(d):
                out[i, a, b] = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            gk = g[k]
            if gk == 0.0:
                continue
            j = bond_j[k]
            for a in range(d):
                ya = (x[j, a] - x[i, a]) + (u[j, a] - u[i, a])
                for b in range(d):
                    out[i, a, b] += 0.5 * gk * ya * (x[j, b] - x[i, b])


#: a shape tensor K with det K <= DEGENERATE (tr K / d)^d is taken as singular: its
#: family has fewer than ``dim`` independent intact bonds, up to round-off
DEGENERATE = 1e-8


@njit
def _solve_right(nmat, kmat, d, fout, i):
    """fout[i] = nmat K^-1 for a symmetric positive (d, d) K (d <= 3); the identity
    when K is singular (:data:`DEGENERATE`). Returns det K."""
    tr = 0.0
    for a in range(d):
        tr += kmat[a, a]
    floor = DEGENERATE * (tr / d) ** d
    if d == 1:
        det = kmat[0, 0]
        fout[i, 0, 0] = nmat[0, 0] / det if det > floor else 1.0
        return det
    if d == 2:
        a, b, c, e = kmat[0, 0], kmat[0, 1], kmat[1, 0], kmat[1, 1]
        det = a * e - b * c
        inv = np.empty((2, 2))
        if det > floor:
            inv[0, 0], inv[0, 1], inv[1, 0], inv[1, 1] = e / det, -b / det, -c / det, a / det
    else:
        c00 = kmat[1, 1] * kmat[2, 2] - kmat[1, 2] * kmat[2, 1]
        c01 = kmat[1, 2] * kmat[2, 0] - kmat[1, 0] * kmat[2, 2]
        c02 = kmat[1, 0] * kmat[2, 1] - kmat[1, 1] * kmat[2, 0]
        det = kmat[0, 0] * c00 + kmat[0, 1] * c01 + kmat[0, 2] * c02
        inv = np.empty((3, 3))
        if det > floor:
            inv[0, 0], inv[1, 0], inv[2, 0] = c00 / det, c01 / det, c02 / det
            inv[0, 1] = (kmat[0, 2] * kmat[2, 1] - kmat[0, 1] * kmat[2, 2]) / det
            inv[1, 1] = (kmat[0, 0] * kmat[2, 2] - kmat[0, 2] * kmat[2, 0]) / det
            inv[2, 1] = (kmat[0, 1] * kmat[2, 0] - kmat[0, 0] * kmat[2, 1]) / det
            inv[0, 2] = (kmat[0, 1] * kmat[1, 2] - kmat[0, 2] * kmat[1, 1]) / det
            inv[1, 2] = (kmat[0, 2] * kmat[1, 0] - kmat[0, 0] * kmat[1, 2]) / det
            inv[2, 2] = (kmat[0, 0] * kmat[1, 1] - kmat[0, 1] * kmat[1, 0]) / det
    for a in range(d):
        for b in range(d):
            if det > floor:
                acc = 0.0
                for c in range(d):
                    acc += nmat[a, c] * inv[c, b]
                fout[i, a, b] = acc
            else:
                fout[i, a, b] = 1.0 if a == b else 0.0
    return det


@_exact
def deformation_gradient(x, u, offsets, bond_j, w, intact, out):
    """Nonlocal deformation gradient ``F_i = N_i K_i^-1`` (dimensionless).

    Parameters
    ----------
    x, u : (n_all, d) reference positions and displacements (m).
    offsets : (n + 1,) CSR offsets; bond_j : (n_bonds,) far points.
    w : (n_bonds,) bond weights (the partial volumes, m^3).
    intact : (n_bonds,) uint8, 1 for an intact bond.
    out : (n, d, d) output F; the identity where K_i is singular (:data:`DEGENERATE`).
    """
    n = offsets.shape[0] - 1
    d = x.shape[1]
    for i in prange(n):
        kmat = np.zeros((d, d))
        nmat = np.zeros((d, d))
        for k in range(offsets[i], offsets[i + 1]):
            if intact[k] == 0:
                continue
            j = bond_j[k]
            wk = w[k]
            for a in range(d):
                xa = x[j, a] - x[i, a]
                ya = xa + (u[j, a] - u[i, a])
                for b in range(d):
                    xb = x[j, b] - x[i, b]
                    kmat[a, b] += wk * xa * xb
                    nmat[a, b] += wk * ya * xb
        _solve_right(nmat, kmat, d, out, i)
