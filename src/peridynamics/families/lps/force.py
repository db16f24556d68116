"""Ordinary state-based linear peridynamic solid (LPS), 2-D and 3-D.

Silling et al. (2007) (3-D) and Le, Chan & Schwartz (2014) (plane stress / plane
strain); the coefficients are derived in :mod:`peridynamics.families.lps.material` and the
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
  calibration of the influence function,
  :func:`~peridynamics.families.calibration.calibrate_influence`. Under a homogeneous
  small strain eps the energy of point i is
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
  :data:`~peridynamics.families.calibration.CALIBRATION_BOUNDS`, the bounded least
  change by alternating projections).
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

from typing import TYPE_CHECKING, Any, ClassVar, Protocol

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import FieldSpec, ForceModel, LargestStretchPass
from peridynamics.families.calibration import calibrate_influence
from peridynamics.families.lps.tangent import lps_tangent
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import lps as kernels

if TYPE_CHECKING:
    from peridynamics.state import State


class LPSConstants(Protocol):
    """What the force model reads of its material
    (:class:`~peridynamics.families.lps.material.LPSMaterial`)."""

    @property
    def influence(self) -> str: ...

    def coefficients(self, dim: int, plane: str | None) -> Any: ...


class LPSForceModel(LargestStretchPass, ForceModel):
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
        :func:`~peridynamics.families.calibration.calibrate_influence`).

    Attributes
    ----------
    omega_volume : (n_bonds,) wv_k = omega_ik beta_k V_j (m^3): influence function of
        the owner times partial volume, what the kernels read.
    omega_volume_far : (n_bonds,) wvf_k = omega_jk beta_k V_j (m^3): the same bond with
        the far point's influence function; ``omega_volume`` itself (the same array)
        without the correction.
    calibration_factor : (n_bonds,) or None
        The factor g_k of
        :func:`~peridynamics.families.calibration.calibrate_influence`
        (``omega_ik = omega(|xi|) g_k``); None without the correction.
    calibration_residual : (n_points,) or None
        Relative moment residual of every point after the calibration (0: the point
        reproduces the continuum moduli for every homogeneous strain); None without
        the correction.
    weighted_volume : (n_points,) m_i (m^5).
    theta_scale : (n_points,) tf / m_i (1/m^5), 0 for a point without an intact bond.
    dilatation_coef : (n_points,) k_theta tf / m_i (N/m^7).
    extension_coef : (n_points,) alpha / m_i (N/m^7).
    k_theta : float
        Dilatation modulus (Pa), see :class:`~peridynamics.families.lps.material.LPSCoefficients`.
    reach : int
        The force of a point depends on the displacements up to ``reach`` bonds away
        (2: the dilatation of its neighbours), used by the finite-difference tangent.
    """

    name: ClassVar[str] = "lps"
    spectral_bound: ClassVar[bool] = True  # the evaluator tightens the bound
    reach: ClassVar[int] = 2

    def __init__(
        self,
        cloud: PointCloud,
        bonds: Bonds,
        material: LPSConstants,
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
        """LPS force density (N/m^3) into ``state.force``; reads ``state["dilatation"]``
        of the last :meth:`prepass`. Pure: never breaks a bond. The largest stretch is
        not tracked here (the family loop vectorises without that max):
        ``update_max_stretch`` (:class:`~peridynamics.families.base.LargestStretchPass`)."""
        if "dilatation" not in state:
            raise KeyError(
                "state has no 'dilatation' field: call LPSForceModel.prepass(state) before "
                "force(state)"
            )
        b = self.bonds
        self._force(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            self.omega_volume_far, state.intact, state["dilatation"], self.dilatation_coef,
            self.extension_coef, state.force,
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

    def pair_force_coefficients(self, state: State) -> NDArray[np.float64]:
        """g_k = mu_k ((wv_k cd_i theta_i + wvf_k cd_j theta_j) L_k + (wv_k a_i +
        wvf_k a_j) e_k) / r_k (n_bonds,) (N/m^4): the net pair force of the force pass,
        both ends' force states (:mod:`peridynamics.kernels.lps`), with the dilatation
        recomputed from ``state.u`` (the State is not changed)."""
        b = self.bonds
        theta = np.zeros(state.u.shape[0])
        self._dilatation(
            self.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.omega_volume,
            state.intact, self.theta_scale, theta,
        )  # fmt: skip
        bi, bj, length = b.bond_i, b.bond_j, b.bond_length
        xi = b.bond_xi
        eta = state.u[bj] - state.u[bi]
        y = xi + eta
        r = np.sqrt(np.einsum("ij,ij->i", y, y))
        e = np.einsum("ij,ij->i", eta, 2.0 * xi + eta) / (r + length)
        cd, a = self.dilatation_coef, self.extension_coef
        wv, wvf = self.omega_volume, self.omega_volume_far
        t = (wv * cd[bi] * theta[bi] + wvf * cd[bj] * theta[bj]) * length + (
            wv * a[bi] + wvf * a[bj]
        ) * e
        return np.asarray(state.intact * t / r)

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
        """Analytic tangent K = -d(V f)/du at ``state`` (N/m), shape (n dim, n dim), CSR
        (:func:`peridynamics.families.lps.tangent.lps_tangent`). Serial models only:
        every point must own its family (no ghost rows)."""
        return lps_tangent(self, state)
