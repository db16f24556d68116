"""Influence-function calibration of a bond family to the continuum moments.

Shared by the LPS surface correction (:mod:`peridynamics.families.lps.force`, which
multiplies the influence function of every directed bond by the factor found here) and
the moment method of the bond-based surface correction
(:func:`peridynamics.bonds.surface.moment_correction_factors`, to which the PMB family
passes :func:`calibrate_influence`). The construction, its bounds and what is left at
edges and corners are described in the module docstring of
:mod:`peridynamics.families.lps.force` and in docs/theory_lps.md.
"""

from __future__ import annotations

import itertools

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds

#: bounds of the calibration factor g of :func:`calibrate_influence`: wide enough for
#: every face point of a grid at delta = 3.015 dx to reach the continuum moments (a
#: linear-programming check, docs/theory_lps.md), narrow enough to keep the stiffness
#: bound, and so the stable step, within a factor of the uncorrected one
CALIBRATION_BOUNDS: tuple[float, float] = (0.25, 4.0)
#: alternating projections: at most this many sweeps, stop below this residual
_CALIBRATION_SWEEPS = 400
_CALIBRATION_TOL = 1e-9
#: bonds per block of the calibration (bounds its memory: ~ 2 kB per bond in 3-D)
_CALIBRATION_BLOCK = 1 << 14


def quartic_monomials(dim: int) -> tuple[tuple[int, ...], ...]:
    """Index tuples (a, b, c, e), a <= b <= c <= e < dim, of the quartic monomials
    ``n_a n_b n_c n_e`` (15 in 3-D, 5 in 2-D). On the unit sphere they span every even
    polynomial of degree <= 4 (``1 = (n . n)^2``)."""
    return tuple(itertools.combinations_with_replacement(range(dim), 4))


def quartic_values(
    n_hat: NDArray[np.float64], monos: tuple[tuple[int, ...], ...] | None = None
) -> NDArray[np.float64]:
    """The quartic monomials ``monos`` (default :func:`quartic_monomials` of the
    dimension) of unit vectors ``n_hat`` (n, dim), shape (n, P)."""
    if monos is None:
        monos = quartic_monomials(n_hat.shape[1])
    phi = np.ones((len(n_hat), len(monos)))
    for p, mono in enumerate(monos):
        for c in mono:
            phi[:, p] *= n_hat[:, c]
    return phi


def isotropic_fourth_moment(dim: int) -> NDArray[np.float64]:
    """The monomial moments of :func:`quartic_monomials` of the continuous ball,
    normalised by the second moment: ``<n_a n_b n_c n_e> = (d_ab d_ce + d_ac d_be +
    d_ae d_bc) / (d (d + 2))`` (weight |xi|^2 omega, any radial omega), shape (P,)."""
    out = []
    for a, b, c, e in quartic_monomials(dim):
        out.append(
            ((a == b) * (c == e) + (a == c) * (b == e) + (a == e) * (b == c)) / (dim * (dim + 2))
        )
    return np.asarray(out, dtype=np.float64)


def calibrate_influence(
    bonds: Bonds,
    weight: NDArray[np.float64],
    bounds: tuple[float, float] = CALIBRATION_BOUNDS,
    sweeps: int = _CALIBRATION_SWEEPS,
    tol: float = _CALIBRATION_TOL,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per-point influence-function factors that give every family the continuum moments.

    For point i with reference bonds k (direction n_k, length L_k, weight wv_k, intact)
    the factors g_k of its own bonds solve ``sum_k g_k w_k phi(n_k) = m_i T`` with
    ``w_k = wv_k L_k^2``, ``m_i = sum_k w_k``, phi the quartic monomials
    (:func:`quartic_monomials`) and T their moments on the ball
    (:func:`isotropic_fourth_moment`); the second moments follow (``sum_c n_c^2 = 1``),
    and so does ``sum_k g_k w_k = m_i``. Chosen among the solutions:

    1. the minimum-norm change ``g = 1 + phi(n) . lam_i`` (``min sum_k w_k (g_k - 1)^2``),
       kept where it lies within ``bounds``: every interior point and most surface
       points;
    2. elsewhere the bounded least change, by Dykstra's alternating projections between
       the moment constraints and the box ``bounds`` (``sweeps`` sweeps at most), kept
       where it meets the moments to ``tol``;
    3. where no factor within ``bounds`` meets them (edges of a 3-D body, corners of a
       2-D one), the change of step 1 scaled down until it fits the bounds.

    Parameters
    ----------
    bonds : Bonds
        Directed CSR bond list (its ``bond_correction`` is not used).
    weight : (n_bonds,) float
        wv_k = omega beta V_j (m^3) of the uncorrected model.
    bounds : (float, float)
        Lowest and highest factor, 0 < g_lo <= 1 <= g_hi.
    sweeps : int
        Most sweeps of step 2.
    tol : float
        Accepted relative moment residual ``max_p |M_p / m_i - T_p| / max_p T_p``.

    Returns
    -------
    factor : (n_bonds,) float
        g_k of the owner of every directed bond (1 for pre-cracked bonds).
    residual : (n_points,) float
        Relative moment residual of every point after the calibration (0 for a point
        without an intact bond).
    """
    g_lo, g_hi = float(bounds[0]), float(bounds[1])
    if not (0.0 < g_lo <= 1.0 <= g_hi):
        raise ValueError(f"calibration bounds must satisfy 0 < lo <= 1 <= hi, got {bounds}")
    dim = bonds.bond_xi.shape[1]
    target = isotropic_fourth_moment(dim)
    t_scale = float(target.max())
    monos = quartic_monomials(dim)
    n_pts = bonds.n_points
    offsets = bonds.offsets
    factor = np.ones(bonds.n_bonds)
    residual = np.zeros(n_pts)
    p0 = 0
    while p0 < n_pts:  # blocks of whole families, about _CALIBRATION_BLOCK bonds each
        stop = np.searchsorted(offsets, offsets[p0] + _CALIBRATION_BLOCK, side="right") - 1
        p1 = int(min(max(stop, p0 + 1), n_pts))
        b0, b1 = int(offsets[p0]), int(offsets[p1])
        g, res = _calibrate_block(
            bonds.bond_xi[b0:b1], bonds.bond_length[b0:b1],
            weight[b0:b1] * bonds.bond_intact[b0:b1], offsets[p0 : p1 + 1] - b0,
            monos, target, t_scale, g_lo, g_hi, sweeps, tol,
        )  # fmt: skip
        factor[b0:b1] = g
        residual[p0:p1] = res
        p0 = p1
    return factor, residual


def _calibrate_block(
    xi: NDArray[np.float64],
    length: NDArray[np.float64],
    w0: NDArray[np.float64],
    offsets: NDArray[np.int64],
    monos: tuple[tuple[int, ...], ...],
    target: NDArray[np.float64],
    t_scale: float,
    g_lo: float,
    g_hi: float,
    sweeps: int,
    tol: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`calibrate_influence` on the families of consecutive points (offsets local
    to the block); returns the factors of the block's bonds and the points' residuals."""
    npt = len(offsets) - 1
    phi = quartic_values(xi / length[:, None], monos)
    w = w0 * length * length
    fam = _Families(phi, w, offsets, target)
    # 1. minimum-norm change, scaled into the bounds where it leaves them
    h = fam.project(np.ones(fam.n_bonds)) - 1.0
    h_min = np.minimum(fam.segment_min(h), 0.0)
    h_max = np.maximum(fam.segment_max(h), 0.0)
    scale = np.ones(npt)
    low = h_min < g_lo - 1.0
    scale[low] = (g_lo - 1.0) / h_min[low]
    high = h_max > g_hi - 1.0
    scale[high] = np.minimum(scale[high], (g_hi - 1.0) / h_max[high])
    g = 1.0 + scale[fam.owner] * h
    # 2. Dykstra between the moment constraints and the box, on the clipped points only;
    # converged points leave the active set every few sweeps
    active = np.flatnonzero(fam.alive & (scale < 1.0))
    state: tuple[NDArray[np.float64], ...] | None = None
    done = 0
    while active.size and done < sweeps:
        sub, bond_idx = fam.subset(active)
        if state is None:
            x = np.ones(sub.n_bonds)
            p_inc = np.zeros(sub.n_bonds)
            q_inc = np.zeros(sub.n_bonds)
        else:
            x, p_inc, q_inc = state
        for _ in range(min(25, sweeps - done)):
            y = x + p_inc
            z = sub.project(y)
            p_inc = y - z
            y = z + q_inc
            x = np.clip(y, g_lo, g_hi)
            q_inc = y - x
            done += 1
        ok = sub.residual(x, t_scale) < tol
        g[bond_idx[ok[sub.owner]]] = x[ok[sub.owner]]
        still = ~ok[sub.owner]
        state = (x[still], p_inc[still], q_inc[still])
        active = active[~ok]
    g[w0 == 0] = 1.0  # broken at the reference state: no weight either way
    return g, np.where(fam.alive, fam.residual(g, t_scale), 0.0)


class _Families:
    """Moment algebra of a set of families (directed bonds grouped by owner, CSR)."""

    def __init__(
        self,
        phi: NDArray[np.float64],
        w: NDArray[np.float64],
        offsets: NDArray[np.int64],
        target: NDArray[np.float64],
    ) -> None:
        npt = len(offsets) - 1
        nb, n_p = phi.shape
        self.phi, self.offsets, self.target = phi, offsets, target
        self.n_bonds = nb
        self.owner = np.repeat(np.arange(npt), np.diff(offsets))
        m = np.bincount(self.owner, w, minlength=npt)
        self.alive = m > 0
        self.wn = w / np.where(self.alive, m, 1.0)[self.owner]  # per unit weighted volume
        self.sum = sp.csr_matrix((np.ones(nb), np.arange(nb), offsets), shape=(npt, nb))
        outer = (self.wn[:, None, None] * phi[:, :, None] * phi[:, None, :]).reshape(nb, -1)
        gram = np.asarray(self.sum @ outer).reshape(npt, n_p, n_p)
        self.gram_inv = np.linalg.pinv(gram, rcond=1e-12, hermitian=True)

    def moments(self, g: NDArray[np.float64]) -> NDArray[np.float64]:
        """sum_k g_k w_k phi(n_k) / m_i, shape (n_points, P)."""
        return np.asarray(self.sum @ ((self.wn * g)[:, None] * self.phi))

    def project(self, g: NDArray[np.float64]) -> NDArray[np.float64]:
        """The w-weighted projection of g onto the moment constraints."""
        lam = np.einsum("ipq,iq->ip", self.gram_inv, self.target[None, :] - self.moments(g))
        return np.asarray(g + np.einsum("kp,kp->k", self.phi, lam[self.owner]))

    def residual(self, g: NDArray[np.float64], t_scale: float) -> NDArray[np.float64]:
        """Relative moment residual per point."""
        return np.asarray(np.abs(self.moments(g) - self.target[None, :]).max(axis=1) / t_scale)

    def segment_min(self, v: NDArray[np.float64]) -> NDArray[np.float64]:
        out = np.full(len(self.offsets) - 1, np.inf)
        np.minimum.at(out, self.owner, v)
        return out

    def segment_max(self, v: NDArray[np.float64]) -> NDArray[np.float64]:
        out = np.full(len(self.offsets) - 1, -np.inf)
        np.maximum.at(out, self.owner, v)
        return out

    def subset(self, points: NDArray[np.intp]) -> tuple[_Families, NDArray[np.intp]]:
        """The families of ``points`` (sorted) and the indices of their bonds here."""
        counts = np.diff(self.offsets)[points]
        starts = self.offsets[points]
        idx = np.repeat(starts - np.cumsum(counts) + counts, counts) + np.arange(counts.sum())
        sub = _Families.__new__(_Families)
        sub.phi, sub.target = self.phi[idx], self.target
        sub.offsets = np.concatenate([[0], np.cumsum(counts)])
        sub.n_bonds = len(idx)
        sub.owner = np.repeat(np.arange(len(points)), counts)
        sub.alive = self.alive[points]
        sub.wn = self.wn[idx]
        sub.sum = sp.csr_matrix(
            (np.ones(len(idx)), np.arange(len(idx)), sub.offsets), shape=(len(points), len(idx))
        )
        sub.gram_inv = self.gram_inv[points]
        return sub, idx
