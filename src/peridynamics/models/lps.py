"""Ordinary state-based linear peridynamic solid (LPS), 2-D and 3-D.

Silling et al. (2007) (3-D) and Le, Chan & Schwartz (2014) (plane stress / plane
strain); the coefficients are derived in :mod:`peridynamics.materials.lps` and the
kernels are :mod:`peridynamics.kernels.lps` (NumPy twins in
:mod:`peridynamics.kernels.reference_lps`). Equations, the correction and the measured
accuracy: docs/theory_lps.md.

Conventions
-----------
* The weighted volume ``m_i`` is computed once from the reference bond list
  (pre-cracked bonds, ``bonds.bond_intact == 0``, are left out, as Peridigm leaves
  filtered bonds out of the neighbourhood) and stays fixed when bonds break later; the
  dilatation, the force and the energy sum over the intact bonds of the State only.
  This is the standard practice (Peridigm's ``elastic`` material).
* The pre-pass (:meth:`LPSForceModel.prepass`) writes the dilatation of every point to
  ``state["dilatation"]``; :meth:`LPSForceModel.force` reads it at both ends of each
  bond, so a parallel run exchanges it (and ``LPSForceModel.weighted_volume``) for
  ghost points between the two passes.
* Surface correction (``surface_correction=True``, the deck default): a per-point
  calibration of the influence function, :func:`calibrate_influence`. Under a
  homogeneous small strain eps the energy of point i is
  ``W_i = k_theta theta_i^2 / 2 + (alpha / 2 m_i) sum_k wv_k L_k^2 (n_k . eps . n_k)^2``
  with ``theta_i = (tf / m_i) sum_k wv_k L_k^2 n_k . eps . n_k``: it depends on the
  family only through its second and fourth moments ``sum_k wv_k L_k^2 n_k^(x2)`` and
  ``sum_k wv_k L_k^2 n_k^(x4)``, and it is the continuum energy of the isotropic solid
  for every eps exactly when these equal the moments of the continuous ball,
  ``m_i I / d`` and ``m_i (delta delta + delta delta + delta delta) / (d (d + 2))``. A
  grid family misses them twice: in the interior its fourth moment has the cubic
  anisotropy of the lattice (truncated partial volumes, delta = 3.015 dx, 3-D: the
  normal-deviatoric modulus 12.7 % low and the shear modulus 8.5 % high, hence
  E -11 %, nu +11 %), and near a surface the cut family is neither isotropic nor
  centred. The calibration multiplies the influence function of every directed bond
  (i, j) by a factor ``g_ik > 0`` of its owner i, chosen so that the moments of every
  point are the continuum ones (the minimum-norm correction ``g = 1 + P_i(n)``, P_i a
  homogeneous quartic in the bond direction, then, where that leaves the bounds
  :data:`CALIBRATION_BOUNDS`, the bounded least change by alternating projections).
  The influence function thus becomes a per-point function of the bond direction
  (omega_ik differs from omega_jk): the point energies are those of an ordinary LPS
  with these influence functions, the force is their exact gradient
  (:mod:`peridynamics.kernels.lps` reads both weights of a bond), the tangent stays
  symmetric and linear and angular momentum are conserved (pairwise forces along the
  bond). Points whose family cannot reach the continuum moments with any positive
  weights keep the bounded minimum-norm correction: on an edge of a 3-D body or in a
  corner of a 2-D one every bond has ``n_a n_b >= 0`` for the two cut directions a, b,
  so the odd moment ``sum w g n_a^3 n_b`` (0 on the ball) vanishes only if the bonds
  with ``n_a n_b > 0`` get no weight, and without them ``n_a^2 n_b^2`` cannot be
  reached. ``LPSForceModel.calibration_residual`` reports what is left. The
  factors are computed once from the reference bond list (pre-cracked bonds left out)
  and stay fixed when bonds break. ``False`` is the plain model (omega depends on |xi|
  only); ``bonds.bond_correction`` is not used by LPS.
"""

from __future__ import annotations

import itertools
from typing import TYPE_CHECKING, ClassVar

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import lps as kernels
from peridynamics.models.base import FieldSpec, ForceModel

if TYPE_CHECKING:
    from peridynamics.materials.lps import LPSMaterial
    from peridynamics.state import State


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
    n_hat = xi / length[:, None]
    phi = np.ones((len(length), len(monos)))
    for p, mono in enumerate(monos):
        for c in mono:
            phi[:, p] *= n_hat[:, c]
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


class LPSForceModel(ForceModel):
    """Linear peridynamic solid over a directed CSR bond list.

    Parameters
    ----------
    cloud : PointCloud
        2-D (plane stress or plane strain) or 3-D cloud.
    bonds : Bonds
        Bond list of ``cloud``.
    material : LPSMaterial
    surface_correction : bool
        Calibrate the influence function of every point (module docstring,
        :func:`calibrate_influence`).

    Attributes
    ----------
    omega_volume : (n_bonds,) wv_k = omega_ik beta_k V_j (m^3): influence function of
        the owner times partial volume, what the kernels read.
    omega_volume_far : (n_bonds,) wvf_k = omega_jk beta_k V_j (m^3): the same bond with
        the far point's influence function; ``omega_volume`` itself (the same array)
        without the correction.
    calibration_factor : (n_bonds,) or None
        The factor g_k of :func:`calibrate_influence` (``omega_ik = omega(|xi|) g_k``);
        None without the correction.
    calibration_residual : (n_points,) or None
        Relative moment residual of every point after the calibration (0: the point
        reproduces the continuum moduli for every homogeneous strain); None without
        the correction.
    weighted_volume : (n_points,) m_i (m^5).
    theta_scale : (n_points,) tf / m_i (1/m^5), 0 for a point without an intact bond.
    dilatation_coef : (n_points,) k_theta tf / m_i (N/m^7).
    extension_coef : (n_points,) alpha / m_i (N/m^7).
    k_theta : float
        Dilatation modulus (Pa), see :class:`~peridynamics.materials.lps.LPSCoefficients`.
    reach : int
        The force of a point depends on the displacements up to ``reach`` bonds away
        (2: the dilatation of its neighbours), used by the finite-difference tangent.
    """

    name: ClassVar[str] = "lps"
    reach: ClassVar[int] = 2

    def __init__(
        self,
        cloud: PointCloud,
        bonds: Bonds,
        material: LPSMaterial,
        surface_correction: bool = False,
    ) -> None:
        dim = cloud.dim
        coef = material.coefficients(dim, cloud.plane)  # validates dim and plane
        self.cloud = cloud
        self.bonds = bonds
        self.material = material
        self.surface_correction = bool(surface_correction)
        self.coefficients = coef
        self.k_theta = float(coef.k_theta)
        length = bonds.bond_length
        if material.influence == "inverse":
            omega = bonds.horizon / length
        else:
            omega = np.ones_like(length)
        wv = np.ascontiguousarray(omega * bonds.bond_volume, dtype=np.float64)
        self.calibration_factor: NDArray[np.float64] | None = None
        self.calibration_residual: NDArray[np.float64] | None = None
        if self.surface_correction:
            factor, residual = calibrate_influence(bonds, wv)
            self.calibration_factor = factor
            self.calibration_residual = residual
            self.omega_volume = np.ascontiguousarray(wv * factor)
            self.omega_volume_far = np.ascontiguousarray(wv * factor[bonds.reverse_index()])
        else:
            self.omega_volume = wv
            self.omega_volume_far = wv
        n = cloud.n_points
        m = np.zeros(n)
        kernels.weighted_volume(bonds.offsets, length, self.omega_volume, bonds.bond_intact, m)
        self.weighted_volume = m
        inv_m = np.divide(1.0, m, out=np.zeros(n), where=m > 0)
        self.theta_scale = coef.theta_factor * inv_m
        self.dilatation_coef = coef.k_theta * coef.theta_factor * inv_m
        self.extension_coef = coef.alpha * inv_m
        self._dilatation = kernels.DILATATION_KERNELS[dim]
        self._force = kernels.FORCE_KERNELS[dim]
        self._energy = kernels.ENERGY_KERNELS[dim]
        self._bound: NDArray[np.float64] | None = None

    # -- fields and passes ----------------------------------------------------------------
    def state_fields(self) -> tuple[FieldSpec, ...]:
        """The dilatation theta (n,), written by :meth:`prepass`."""
        return (FieldSpec("dilatation"),)

    def prepass(self, state: State) -> None:
        """Dilatation of every owned point into ``state["dilatation"]`` (allocated, zero,
        when missing)."""
        if "dilatation" not in state:
            state["dilatation"] = np.zeros(state.u.shape[0])
        b = self.bonds
        self._dilatation(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            state.intact, self.theta_scale, state["dilatation"],
        )  # fmt: skip

    def force(self, state: State) -> None:
        """LPS force density (N/m^3) into ``state.force`` and the largest tensile stretch
        of an intact bond into ``state.max_stretch``; reads ``state["dilatation"]`` of
        the last :meth:`prepass`. Pure: never breaks a bond."""
        if "dilatation" not in state:
            raise KeyError(
                "state has no 'dilatation' field: call LPSForceModel.prepass(state) before "
                "force(state)"
            )
        b = self.bonds
        self._force(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            self.omega_volume_far, state.intact, state["dilatation"], self.dilatation_coef,
            self.extension_coef, state.force, state.max_stretch,
        )  # fmt: skip

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """W_i = k_theta theta_i^2 / 2 + (alpha / 2 m_i) sum_k mu_k wv_k e_k^2 (J/m^3),
        shape (n,), the dilatation recomputed from ``state.u`` (the State is not
        changed)."""
        b = self.bonds
        out = np.empty(len(b.offsets) - 1)
        self._energy(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            state.intact, self.theta_scale, self.k_theta, self.extension_coef, out,
        )  # fmt: skip
        return out

    # -- stiffness bound ------------------------------------------------------------------
    def stiffness_bound(self) -> NDArray[np.float64]:
        """Per-point bound K_i (N/m^4 = Pa/m^2), shape (n,), such that
        ``dt = min_i sqrt(2 rho_i / K_i)`` is a stable explicit (central-difference /
        velocity-Verlet) step of the linearised model, also after bonds break.

        Derivation. At the reference state the tangent is ``K = K_b + K_theta`` with
        ``u.K_b.u = sum_pairs V_i (wv_k a_i + wvf_k a_j) (n_k . du_k)^2``
        (du_k = u_j - u_i) and ``u.K_theta.u = k_theta sum_i V_i theta_i(u)^2``. By
        Cauchy-Schwarz ``theta_i^2 <= (tf^2 / m_i) sum_k wv_k (n_k . du_k)^2`` (m_i >=
        the intact part of the weighted volume), so ``K <= K'`` in the Loewner order with
        K' the bond-based operator of pair stiffness per unit volume

            s_k = wv_k (a_i + kp tf^2 / m_i) + wvf_k (a_j + kp tf^2 / m_j),
            kp = max(k_theta, 0)

        (``V_i s_k = V_j s_k'``: symmetric; ``wvf = wv`` without the correction)

        (k_theta < 0, i.e. nu < 1/4 in 3-D, makes K_theta negative semi-definite and is
        dropped). Then ``u.K'.u <= 2 sum_i u_i.D_i.u_i V_i`` with
        ``D_i = sum_k s_k n_k n_k^T`` (``(a - b)^2 <= 2 a^2 + 2 b^2``), so
        ``omega_max^2 <= max_i 2 lambda_max(D_i) / rho_i`` and the central-difference
        limit ``dt < 2 / omega_max`` holds for ``dt <= sqrt(2 rho_i / K_i)`` with
        ``K_i = lambda_max(D_i)``. (Silling & Askari 2005's bond-based bound is the same
        construction with the trace of D_i in place of its largest eigenvalue.) Broken
        bonds only remove non-negative terms from K', so the bound of the reference
        state covers every later state (geometric stiffness of large stretches aside).
        """
        if self._bound is None:
            self._bound = self._eigen_bound()
        return self._bound.copy()

    def _eigen_bound(self) -> NDArray[np.float64]:
        b = self.bonds
        n_own = len(b.offsets) - 1
        m = self.weighted_volume
        inv_m = np.divide(1.0, m, out=np.zeros_like(m), where=m > 0)
        bi = b.bond_i.astype(np.intp)
        bj = b.bond_j.astype(np.intp)
        a = self.extension_coef
        tf = self.coefficients.theta_factor
        kp = max(self.k_theta, 0.0) * tf * tf
        s = b.bond_intact * (
            self.omega_volume * (a[bi] + kp * inv_m[bi])
            + self.omega_volume_far * (a[bj] + kp * inv_m[bj])
        )
        n_hat = b.bond_xi / b.bond_length[:, None]
        d = self.dim
        blocks = np.empty((n_own, d, d))
        for c in range(d):  # loop over the (<= 3 x 3) components only
            for c2 in range(c, d):
                col = np.bincount(bi, s * n_hat[:, c] * n_hat[:, c2], minlength=n_own)[:n_own]
                blocks[:, c, c2] = col
                blocks[:, c2, c] = col
        return np.asarray(np.linalg.eigvalsh(blocks)[:, -1], dtype=np.float64)

    # -- tangent --------------------------------------------------------------------------
    def tangent(self, state: State) -> sp.csr_matrix:
        """Analytic tangent K = -d(V f)/du at ``state`` (N/m), shape (n dim, n dim), CSR.

        With per intact bond k = (i, j) the deformed direction n_k = y_k / r_k, the
        scalar ``T_k = (wv_k cd_i theta_i + wvf_k cd_j theta_j) L_k + (wv_k a_i +
        wvf_k a_j) e_k`` and ``f_i = sum_k T_k n_k``:

        * bond part: ``H_k = (wv_k a_i + wvf_k a_j) n n^T + T_k (I - n n^T) / r_k``,
          added as ``-V_i H_k`` to block (i, j) and ``+V_i H_k`` to block (i, i);
        * dilatation part: ``k_theta B^T diag(V) B`` with B = d theta / du (n, n dim),
          ``B[i, j] = ts_i wv_k L_k n_k^T``, ``B[i, i] = -sum_k ts_i wv_k L_k n_k^T``
          (the bond part is symmetric because ``V_i wvf_(i,j) = V_j wv_(j,i)``).

        Reads ``state.u`` and ``state.intact``; the dilatation is recomputed from u.
        Serial models only: every point must own its family (no ghost rows).
        """
        b = self.bonds
        d = self.dim
        n_all = self.cloud.n_points
        if len(b.offsets) - 1 != n_all:
            raise NotImplementedError("the analytic LPS tangent needs every family (no ghosts)")
        x, u = self.cloud.x, state.u
        keep = np.flatnonzero(state.intact)
        bi = b.bond_i[keep].astype(np.intp)
        bj = b.bond_j[keep].astype(np.intp)
        length = b.bond_length[keep]
        wv = self.omega_volume[keep]
        wvf = self.omega_volume_far[keep]
        xi = x[bj] - x[bi]
        eta = u[bj] - u[bi]
        y = xi + eta
        r = np.sqrt(np.einsum("ij,ij->i", y, y))
        e = np.einsum("ij,ij->i", eta, 2.0 * xi + eta) / (r + length)
        nv = y / r[:, None]
        ts = self.theta_scale
        theta = ts * np.bincount(bi, wv * length * e, minlength=n_all)
        cd, a = self.dilatation_coef, self.extension_coef
        vol = self.cloud.volume
        k_ext = wv * a[bi] + wvf * a[bj]
        big_t = (wv * cd[bi] * theta[bi] + wvf * cd[bj] * theta[bj]) * length + k_ext * e
        nn = nv[:, :, None] * nv[:, None, :]
        eye = np.eye(d)[None, :, :]
        h = k_ext[:, None, None] * nn + (big_t / r)[:, None, None] * (eye - nn)
        h *= vol[bi][:, None, None]
        comp = np.arange(d)
        rr = (bi[:, None, None] * d + comp[None, :, None]) * np.ones((1, 1, d), dtype=np.intp)
        cc_j = (bj[:, None, None] * d + comp[None, None, :]) * np.ones((1, d, 1), dtype=np.intp)
        cc_i = (bi[:, None, None] * d + comp[None, None, :]) * np.ones((1, d, 1), dtype=np.intp)
        size = n_all * d
        k_bond = sp.coo_matrix(
            (
                np.concatenate([-h.ravel(), h.ravel()]),
                (
                    np.concatenate([rr.ravel(), rr.ravel()]),
                    np.concatenate([cc_j.ravel(), cc_i.ravel()]),
                ),
            ),
            shape=(size, size),
        ).tocsr()
        # B = d theta / du, rows: points, columns: dofs
        g = (ts[bi] * wv * length)[:, None] * nv  # (nb, d)
        b_rows = np.repeat(bi, d)
        b_cols_j = (bj[:, None] * d + comp[None, :]).ravel()
        b_cols_i = (bi[:, None] * d + comp[None, :]).ravel()
        b_mat = sp.coo_matrix(
            (
                np.concatenate([g.ravel(), -g.ravel()]),
                (np.concatenate([b_rows, b_rows]), np.concatenate([b_cols_j, b_cols_i])),
            ),
            shape=(n_all, size),
        ).tocsr()
        k_dil = (b_mat.T @ sp.diags(self.k_theta * vol) @ b_mat).tocsr()
        k = sp.csr_matrix(k_bond + k_dil)
        k.sum_duplicates()
        return k
