"""Micropolar bond-based force model (2-D): displacements and rotations per point.

Kinematics, springs and calibration: :mod:`peridynamics.families.micropolar.material`;
kernels: :mod:`peridynamics.kernels.micropolar`. The model is linear in (u, theta)
(small deformation, as in Zhou, Zhu & Li (n.d.)), so its tangent does not depend on
the displacement and one Newton iteration solves an elastic load step exactly.

Discretisation (Zhou, Zhu & Li (n.d.), section 2.3):

* volume correction: the partial-volume rule of the bond list ("truncated", r = dx/2,
  Madenci & Oterkus 2014, is the paper's);
* surface correction by the energy method (Madenci & Oterkus 2014, section 4.2), with
  this model's energy: the uniform strains u = (eps x, 0) and u = (0, eps y) with
  theta = 0 give W_x,i and W_y,i from the k_n and k_t terms, the ratios
  g_k,i = (C11 eps^2 / 2) / W_k,i give the bond factors of
  :func:`peridynamics.bonds.surface.bond_factors_from_point_ratios`, which multiply all
  three springs of a bond.

Fracture energy with the correction (``corrected_critical_stretch``): the critical
stretch l_c = sqrt(G_c / (4 kappa beta)) is calibrated with the continuum spring k_n;
a bond whose springs carry the factor g_k stores g_k times that energy at l_c, so the
energy to break the bonds crossing a unit crack area is about g G_c (g ~ 1.16 inside a
body at delta = 3.015 dx, where the discrete family sum of the bond energy is 0.86 of the
continuum integral). With the option, :meth:`bond_stretch` and :meth:`pair_stretch`
report sqrt(g_k) l, so a threshold l_c breaks the bond at l = l_c / sqrt(g_k) and its
rupture energy 1/2 g_k k_n (l_c^2 / g_k) xi is the uncorrected one.

Tangent (dof order per point [u_x, u_y, theta]): bond k = (i, j) contributes

    k_ij = w_k V_i xi (k_n B_l B_l^T + k_t B_g B_g^T + k_phi B_p B_p^T)     (6 x 6, N/m)
    B_l = [-n/xi, 0, n/xi, 0],  B_g = [-n_perp/xi, -1/2, n_perp/xi, -1/2],
    B_p = [0, 0, -1, 0, 0, 1],

once per pair (Zhou, Zhu & Li (n.d.), eq. 18), assembled by
:func:`peridynamics.families.assembly.block_csr`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.bonds.surface import bond_factors_from_point_ratios
from peridynamics.communicator import active_comm
from peridynamics.families.assembly import family_sum
from peridynamics.families.base import Dof, ForceModel
from peridynamics.families.micropolar.springs import SpringConstants
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import micropolar as kern

if TYPE_CHECKING:
    from peridynamics.state import State


class MicropolarConstants(Protocol):
    """What the force model reads of its material
    (:class:`~peridynamics.families.micropolar.material.MicropolarMaterial`)."""

    def springs(
        self, dim: int, horizon: float, thickness: float, plane: str | None
    ) -> SpringConstants: ...

    def c11(self, plane: str | None) -> float: ...


#: the rotation degrees of freedom: theta (rad), its rate omega (rad/s), the moment
#: density (N m/m^3) and an external body moment density (N m/m^3)
ROTATION = Dof("theta", "omega", "moment", "body_moment", 1)

_CALIBRATION_STRAIN = 1e-6


class MicropolarForceModel(ForceModel):
    """Micropolar bond-based PD in 2-D (plane stress or plane strain).

    Parameters
    ----------
    cloud : PointCloud
        2-D, with ``plane`` and ``cross_section`` (the thickness t, m).
    bonds : Bonds
    material : MicropolarMaterial
    surface_correction : bool
        Energy-method surface correction (module docstring).

    Attributes
    ----------
    springs : SpringConstants
        k_n, k_t, k_phi (N/m^6).
    weight : (n_bonds,) G_k beta_k V_j (m^3): correction times partial volume.
    inv_length : (n_bonds,) 1/|xi| (1/m).
    """

    name = "micropolar"
    fused_breaking = False

    def __init__(
        self,
        cloud: PointCloud,
        bonds: Bonds,
        material: MicropolarConstants,
        surface_correction: bool = False,
    ) -> None:
        self.cloud = cloud
        self.material = material
        self.springs = material.springs(cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane)
        if surface_correction:
            bonds = bonds.with_correction(self._correction_factors(bonds))
        self.bonds = bonds
        self.inv_length = bonds.inv_length
        self.weight = np.ascontiguousarray(bonds.bond_volume * bonds.bond_correction)
        #: sqrt(g_k) per bond (n_bonds,) when the critical stretch follows the correction
        self.stretch_scale: NDArray[np.float64] | None = None
        if surface_correction and getattr(material, "corrected_critical_stretch", False):
            self.stretch_scale = np.sqrt(bonds.bond_correction)
        self._bounds: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None

    # -- degrees of freedom ---------------------------------------------------------------
    def dofs(self) -> tuple[Dof, ...]:
        """Displacement (2 components) and rotation (1)."""
        return (Dof("u", "v", "force", "body", 2), ROTATION)

    def dof_inertia(self, k: int) -> NDArray[np.float64]:
        """Inertia per unit mass density of dof group k: 1 for displacements, dx^2 / 6
        (m^2) for rotations (the square cell of side dx about its centre)."""
        n = self.n_points
        if k == 0:
            return np.ones(n)
        return np.full(n, self.cloud.spacing**2 / 6.0)

    # -- forces -------------------------------------------------------------------------
    def force(self, state: State) -> None:
        """Force (N/m^3) into ``state.force``, moment (N m/m^3) into ``state["moment"]``,
        largest axial stretch into ``state.max_stretch``; never breaks a bond."""
        b, k = self.bonds, self.springs
        kern.force_2d(
            self.cloud.x, state.u, state["theta"], b.offsets, b.bond_j, self.inv_length,
            self.weight, state.intact, k.axial, k.shear, k.rotational, state.force,
            state["moment"], state.max_stretch,
        )  # fmt: skip

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """W_i (J/m^3), shape (n,)."""
        b, k = self.bonds, self.springs
        out = np.empty(len(b.offsets) - 1)
        kern.energy_density_2d(
            self.cloud.x, state.u, state["theta"], b.offsets, b.bond_j, self.inv_length,
            self.weight, state.intact, k.axial, k.shear, k.rotational, out,
        )  # fmt: skip
        return out

    def bond_stretch(self, state: State) -> NDArray[np.float64]:
        """Axial stretch l of every directed bond (n_bonds,) (linearised, as the model);
        sqrt(g_k) l with ``corrected_critical_stretch`` (module docstring)."""
        b = self.bonds
        out = np.empty(b.n_bonds)
        kern.axial_stretch_2d(self.cloud.x, state.u, b.offsets, b.bond_j, self.inv_length, out)
        if self.stretch_scale is not None:
            out *= self.stretch_scale
        return out

    def pair_stretch(self, state: State, index: NDArray[np.int64]) -> NDArray[np.float64]:
        """Axial stretch l of the directed bonds ``index`` (m,), shape (m,): the numbers
        of :meth:`bond_stretch` at those bonds, without computing the others."""
        b = self.bonds
        out = np.empty(len(index))
        kern.pair_stretch_2d(
            self.cloud.x, state.u, b.bond_i, b.bond_j, self.inv_length, index, out
        )  # fmt: skip
        if self.stretch_scale is not None:
            out *= self.stretch_scale[index]
        return out

    # -- bounds and tangent -----------------------------------------------------------------
    def _row_sums(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The bounds of both dof groups, computed once (the undamaged model's)."""
        if self._bounds is None:
            self._bounds = self._gershgorin()
        return self._bounds

    def _gershgorin(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Gershgorin row sums of the mass-scaled undamaged stiffness M^-1/2 K M^-1/2,
        per point, in the units of the :meth:`stiffness_bound` contract: translational
        rows (N/m^4) and rotational rows (N/m^2), with the rotation measured by the
        radius of gyration r_g = dx / sqrt 6 (so the coupling of a rotation row to the
        displacements counts k_t (|n_x| + |n_y|) r_g and that of a displacement row to
        the rotations k_t / r_g)."""
        b, k = self.bonds, self.springs
        il = self.inv_length
        n = b.bond_xi * il[:, None]
        a = np.abs(n).sum(axis=1)  # |n_x| + |n_y| (<= sqrt 2)
        r_g = self.cloud.spacing / np.sqrt(6.0)
        trans = self.weight * (2.0 * (k.axial + k.shear) * il * a + k.shear / r_g)
        length = b.bond_length
        rot = self.weight * (
            length * (0.25 * k.shear + k.rotational)
            + length * abs(0.25 * k.shear - k.rotational)
            + k.shear * a * r_g
        )
        return family_sum(b.offsets, trans), family_sum(b.offsets, rot)

    def stiffness_bound(self) -> NDArray[np.float64]:
        """Per-point bound K_i (N/m^4) of the translational rows: the Gershgorin row sum
        of the undamaged stiffness per unit volume, so that dt_i = sqrt(2 rho / K_i) is
        stable (it is sqrt 2 below the Gershgorin limit sqrt(4 rho / K_i))."""
        return self._row_sums()[0]

    def dof_stiffness_bound(self, k: int) -> NDArray[np.float64]:
        """Stiffness bound of dof group k (N/m^4 for displacements, N/m^2 for rotations,
        per unit volume); with :meth:`dof_inertia` the stable step of that group."""
        return self._row_sums()[k]

    #: forces are linear in (u, theta): the tangent changes only when bonds break
    linear = True

    def pair_stiffness(self, index: NDArray[np.int64]) -> NDArray[np.float64]:
        """Pair stiffness k_ij (N/m) of the intact directed bonds ``index``, shape
        (m, 6, 6) in the dof order [u_i, v_i, theta_i, u_j, v_j, theta_j]."""
        return self.bond_blocks(np.ones(len(index), dtype=np.uint8), index)

    def bond_blocks(
        self, intact: NDArray[np.uint8], index: NDArray[np.int64] | None = None
    ) -> NDArray[np.float64]:
        """Pair stiffness k_ij (N/m) of every directed bond (or of the bonds ``index``,
        ``intact`` then of the same length), shape (n_bonds, 6, 6), dof order
        [u_i, v_i, theta_i, u_j, v_j, theta_j]; zero for broken bonds."""
        b, k = self.bonds, self.springs
        sel = slice(None) if index is None else index
        il = self.inv_length[sel]
        n = b.bond_xi[sel] * il[:, None]
        nb = len(il)
        b_l = np.zeros((nb, 6))
        b_l[:, 0:2] = -n * il[:, None]
        b_l[:, 3:5] = n * il[:, None]
        perp = np.stack([-n[:, 1], n[:, 0]], axis=1) * il[:, None]
        b_g = np.zeros((nb, 6))
        b_g[:, 0:2] = -perp
        b_g[:, 3:5] = perp
        b_g[:, 2] = -0.5
        b_g[:, 5] = -0.5
        scale = self.weight[sel] * intact * self.cloud.volume[b.bond_i[sel]] / il  # m^4
        out = (k.axial * scale)[:, None, None] * b_l[:, :, None] * b_l[:, None, :]
        out += (k.shear * scale)[:, None, None] * b_g[:, :, None] * b_g[:, None, :]
        kp = k.rotational * scale
        out[:, 2, 2] += kp
        out[:, 5, 5] += kp
        out[:, 2, 5] -= kp
        out[:, 5, 2] -= kp
        return out

    def tangent(self, state: State) -> sp.csr_matrix:
        """K = d^2 E / dq^2 (N/m, N, N m), shape (3n, 3n), dof order [u_x, u_y, theta]
        per point, sorted indices; constant (the model is linear), changes only with
        ``state.intact``.

        One kernel pass over the bonds writes the CSR arrays
        (:func:`peridynamics.kernels.micropolar.tangent_csr_2d`): the numbers of
        :meth:`bond_blocks`, their family sum and :func:`block_csr`, bit for bit,
        without the per-bond block arrays."""
        b, k = self.bonds, self.springs
        n = self.n_points
        keep = (state.intact != 0) & (self.weight != 0)
        cum = np.concatenate([[0], np.cumsum(keep, dtype=np.int64)])
        per_point = cum[b.offsets[1:]] - cum[b.offsets[:-1]]  # kept bonds of each point
        per_row = np.repeat(3 * (per_point + 1), 3)
        indptr = np.zeros(3 * n + 1, dtype=np.int64)
        np.cumsum(per_row, out=indptr[1:])
        nnz = int(indptr[-1])
        index_type = np.int32 if max(nnz, 3 * n) < 2**31 else np.int64
        indices = np.empty(nnz, dtype=index_type)
        data = np.empty(nnz)
        kern.tangent_csr_2d(
            self.cloud.x, self.cloud.volume, b.offsets, b.bond_j, self.inv_length,
            self.weight, state.intact, k.axial, k.shear, k.rotational, keep, indptr,
            indices, data,
        )  # fmt: skip
        mat = sp.csr_matrix((data, indices, indptr.astype(index_type)), shape=(3 * n, 3 * n))
        mat.has_sorted_indices = True
        return mat

    # -- surface correction ---------------------------------------------------------------
    def _correction_factors(self, bonds: Bonds) -> NDArray[np.float64]:
        """Energy-method factors (module docstring), shape (n_bonds,)."""
        k, x = self.springs, self.cloud.x
        n, dim = x.shape
        il = bonds.inv_length
        nvec = bonds.bond_xi * il[:, None]
        perp = np.stack([-nvec[:, 1], nvec[:, 0]], axis=1)
        eps = _CALIBRATION_STRAIN
        w_inf = 0.5 * self.material.c11(self.cloud.plane) * eps * eps
        ratios = np.empty((dim, n))
        for a in range(dim):  # uniaxial strain along axis a, theta = 0
            stretch = eps * nvec[:, a] * nvec[:, a]
            gamma = eps * perp[:, a] * nvec[:, a]
            wb = bonds.bond_volume * bonds.bond_length * (k.axial * stretch**2 + k.shear * gamma**2)
            with np.errstate(divide="ignore"):  # ghosts without a family (MPI): exchanged
                ratios[a] = w_inf / (0.25 * np.bincount(bonds.bond_i, wb, minlength=n))
        return bond_factors_from_point_ratios(bonds, ratios, active_comm())
