"""Ordinary state-based linear peridynamic solid (LPS), 2-D and 3-D.

Silling et al. (2007) (3-D) and Le, Silling & Bobaru (2014) (plane stress / plane
strain); the coefficients are derived in :mod:`peridynamics.materials.lps` and the
kernels are :mod:`peridynamics.kernels.lps` (NumPy twins in
:mod:`peridynamics.kernels.reference_lps`).

Conventions
-----------
* The weighted volume ``m_i`` is computed once from the reference bond list
  (pre-cracked bonds, ``bonds.bond_intact == 0``, are left out, as Peridigm leaves
  filtered bonds out of the neighbourhood) and stays fixed when bonds break later; the
  dilatation, the force and the energy sum over the intact bonds of the State only.
  This is the standard practice (Peridigm's ``elastic`` material).
* The pre-pass (:meth:`LPSForceModel.prepass`) writes the dilatation of every point to
  ``state["dilatation"]``; :meth:`LPSForceModel.force` reads it at both ends of each
  bond, so a parallel run exchanges it (and :attr:`LPSForceModel.weighted_volume`) for
  ghost points between the two passes.
* Surface correction: the normalisation by m_i already adapts the moduli to a truncated
  family in part. With ``surface_correction=True`` the bond factors ``bond_correction``
  stored in the bond list (symmetric, computed by whoever built the bonds) multiply the
  influence function, ``omega_k -> omega_k lambda_k``, in m, theta, the force and the
  energy alike: the model stays an LPS (energy-consistent, symmetric tangent) with a
  modified influence function. A factor that is uniform over a family cancels. The
  default (False) uses no factor.
"""

from __future__ import annotations

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
        Multiply the influence function by ``bonds.bond_correction`` (module docstring).

    Attributes
    ----------
    omega_volume : (n_bonds,) omega_k beta_k V_j (lambda_k) (m^3): influence function
        times partial volume, what the kernels read.
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
        wv = omega * bonds.bond_volume
        if self.surface_correction:
            wv = wv * bonds.bond_correction
        self.omega_volume = np.ascontiguousarray(wv, dtype=np.float64)
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
            state.intact, state["dilatation"], self.dilatation_coef, self.extension_coef,
            state.force, state.max_stretch,
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
        ``u.K_b.u = sum_pairs V_i wv_k (a_i + a_j) (n_k . du_k)^2`` (du_k = u_j - u_i)
        and ``u.K_theta.u = k_theta sum_i V_i theta_i(u)^2``. By Cauchy-Schwarz
        ``theta_i^2 <= (tf^2 / m_i) sum_k wv_k (n_k . du_k)^2`` (m_i >= the intact part
        of the weighted volume), so ``K <= K'`` in the Loewner order with K' the
        bond-based operator of pair stiffness per unit volume

            s_k = wv_k ((a_i + a_j) + max(k_theta, 0) tf^2 (1 / m_i + 1 / m_j))

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
        s = (
            self.omega_volume
            * b.bond_intact
            * ((a[bi] + a[bj]) + max(self.k_theta, 0.0) * tf * tf * (inv_m[bi] + inv_m[bj]))
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
        scalar ``T_k = wv_k ((cd_i theta_i + cd_j theta_j) L_k + (a_i + a_j) e_k)`` and
        ``f_i = sum_k T_k n_k``:

        * bond part: ``H_k = wv_k (a_i + a_j) n n^T + T_k (I - n n^T) / r_k``, added
          as ``-V_i H_k`` to block (i, j) and ``+V_i H_k`` to block (i, i);
        * dilatation part: ``k_theta B^T diag(V) B`` with B = d theta / du (n, n dim),
          ``B[i, j] = ts_i wv_k L_k n_k^T``, ``B[i, i] = -sum_k ts_i wv_k L_k n_k^T``
          (symmetric: ``V_i wv_(i,j) = V_j wv_(j,i)``).

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
        big_t = wv * ((cd[bi] * theta[bi] + cd[bj] * theta[bj]) * length + (a[bi] + a[bj]) * e)
        nn = nv[:, :, None] * nv[:, None, :]
        eye = np.eye(d)[None, :, :]
        h = (wv * (a[bi] + a[bj]))[:, None, None] * nn + (big_t / r)[:, None, None] * (eye - nn)
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
