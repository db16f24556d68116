"""Bond-based PMB / linear microelastic force model (Silling 2000; Silling & Askari 2005).

The force pass is :mod:`peridynamics.kernels.bond_based` with an infinite breaking
threshold, so the pure evaluation and the explicit fast path (breaking and forces in
one pass, :meth:`PMBForceModel.force_and_break`) are the same compiled code.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar, Protocol

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.bonds.surface import energy_correction_factors, moment_correction_factors
from peridynamics.communicator import active_comm
from peridynamics.families.base import DamageLaw, ForceModel, FusedStep, LargestStretchPass
from peridynamics.families.calibration import calibrate_influence
from peridynamics.families.pmb.isotropy import grid_isotropy_factors
from peridynamics.families.pmb.tangent import pmb_tangent
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import bond_based

if TYPE_CHECKING:
    from peridynamics.state import State

#: uniaxial strain of the surface-correction calibration: small, so that the geometric
#: nonlinearity of the stretch (relative O(strain)) does not bias the factors
CALIBRATION_STRAIN = 1e-6


class PMBConstants(Protocol):
    """What the force model reads of its material
    (:class:`~peridynamics.families.pmb.material.BondBasedMaterial`)."""

    @property
    def isotropic_family(self) -> bool:
        """Regular 3-D grids: bond factors of the direction make the family isotropic."""
        ...

    def micromodulus(
        self,
        length: NDArray[np.float64],
        dim: int,
        horizon: float,
        cross_section: float,
        plane: str | None,
    ) -> NDArray[np.float64]: ...

    def bond_stiffness(
        self, cloud: PointCloud, bonds: Bonds, corrected: bool = True
    ) -> NDArray[np.float64]: ...

    def uniaxial_energy_density(
        self, strain: float, dim: int, horizon: float, cross_section: float, plane: str | None
    ) -> float: ...


class PMBForceModel(LargestStretchPass, ForceModel):
    """Prototype microelastic brittle bonds: f_ij = c s mu n, n = (xi + eta) / norm(xi + eta).

    Parameters
    ----------
    cloud : PointCloud
    bonds : Bonds
    material : BondBasedMaterial (:class:`PMBConstants`)
    surface_correction : bool
        Energy-method surface correction (Madenci & Oterkus 2014, section 4.2). On a
        regular 3-D grid the bonds first get the isotropy factors of
        :mod:`peridynamics.families.pmb.isotropy` when ``material.isotropic_family``.

    Attributes
    ----------
    stiffness : ndarray, shape (n_bonds,)
        c(L) beta V_j lambda (N/m^6 m^3) for a bond of length L: with the neighbour
        index and the intact flag the only per-bond data the force pass reads (L is
        recomputed from the positions); SED softening rescales it in place.
    inv_length : ndarray, shape (n_bonds,)
        1/L (1/m), made on first use (the NumPy-level tangent and stress maps read
        it; the kernels do not).
    """

    name = "pmb"
    sed_softening = True
    #: the evaluator tightens the per-point bound (2.9-4.1 times the largest eigenvalue
    #: of the plate and the box) by the Lanczos estimate: breaking a bond or softening it
    #: (SED, bond softening) only lowers the stiffness, so the estimate at the reference
    #: state stays an upper bound as bonds fail
    spectral_bound: ClassVar[bool] = True
    #: the explicit fast path (``force_and_break``) gives the same bits as trial,
    #: commit and :meth:`force` in turn
    fused_breaking: bool = True

    def __init__(
        self,
        cloud: PointCloud,
        bonds: Bonds,
        material: PMBConstants,
        surface_correction: bool = False,
    ) -> None:
        self.cloud = cloud
        self.material = material
        if surface_correction:
            # a regular 3-D grid's family has the cubic symmetry of the lattice: factors
            # of the bond direction make it isotropic (families/pmb/isotropy.py)
            iso = grid_isotropy_factors(material, cloud, bonds)
            raw = material.bond_stiffness(cloud, bonds, corrected=False)
            if iso is not None:
                raw = raw * iso
            w_inf = material.uniaxial_energy_density(
                CALIBRATION_STRAIN, cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane
            )
            # irregular clouds (jittered grids): the moment method calibrates every
            # uniform strain, not only stretches along the axes (nu stays right)
            if cloud.irregular:
                factors = moment_correction_factors(
                    cloud.x, bonds, raw, w_inf, CALIBRATION_STRAIN, calibrate=calibrate_influence
                )
            else:
                factors = energy_correction_factors(
                    cloud.x, bonds, raw, w_inf, CALIBRATION_STRAIN, active_comm()
                )
            bonds = bonds.with_correction(factors if iso is None else factors * iso)
        self.bonds = bonds
        self.stiffness = material.bond_stiffness(cloud, bonds)
        self._kernel = bond_based.FORCE_KERNELS[cloud.dim]
        n = len(bonds.offsets) - 1
        self._never = np.full(n, np.inf)  # no threshold is ever reached: the pure pass
        self._broken_scratch = np.zeros(n, dtype=np.int64)
        self.precision = "float64"
        self._f32: dict[str, NDArray] = {}

    def set_precision(self, precision: str) -> None:
        """``"float32"``: the force pass runs in float32 with the cancellation-free
        stretch (:mod:`peridynamics.kernels.bond_based_f32`) and the stiffness is kept
        in float32 (4 bytes per bond instead of 8; the diagnostics then use those
        values); the State stays float64 (time integration, damage). Irreversible."""
        if precision == self.precision:
            return
        if precision != "float32":
            raise ValueError(f"precision {precision!r}: use float64 or float32")
        x = self.cloud.x
        self.stiffness = self.stiffness.astype(np.float32)
        self._f32 = {
            "x": np.ascontiguousarray(x - x.mean(axis=0), dtype=np.float32),
            "u": np.empty(x.shape, dtype=np.float32),
            "force": np.empty(x.shape, dtype=np.float32),
            "never": np.full(len(x), np.inf, dtype=np.float32),
        }
        self.precision = precision

    def _force_f32(
        self, state: State, point_s0: NDArray[np.float64], family_s0_min: NDArray[np.float64]
    ) -> int:
        from peridynamics.kernels.bond_based_f32 import force_f32

        w, b = self._f32, self.bonds
        np.copyto(w["u"], state.u, casting="same_kind")
        never = point_s0 is self._never
        s0 = w["never"] if never else point_s0.astype(np.float32)
        s0_min = w["never"] if never else family_s0_min.astype(np.float32)
        n = force_f32(
            w["x"], w["u"], b.offsets, b.bond_j, self.stiffness, state.intact, s0, s0_min,
            w["force"], self._broken_scratch,
        )  # fmt: skip
        state.force[...] = w["force"]
        return int(n)

    @property
    def inv_length(self) -> NDArray[np.float64]:
        """Inverse bond lengths 1/L (1/m), shape (n_bonds,) (made and kept by the bond
        list on first use)."""
        return self.bonds.inv_length

    # -- forces -------------------------------------------------------------------------
    def force(self, state: State) -> None:
        """Bond force density (N/m^3) into ``state.force``; never breaks a bond. The
        largest stretch is not tracked here: ``update_max_stretch``
        (:class:`~peridynamics.families.base.LargestStretchPass`)."""
        if self.precision == "float32":
            self._force_f32(state, self._never, self._never)
            return
        b = self.bonds
        self._kernel(
            self.cloud.x, state.u, b.offsets, b.bond_j, self.stiffness, state.intact,
            self._never, self._never, state.force, self._broken_scratch,
        )  # fmt: skip

    def force_and_break(
        self, state: State, point_s0: NDArray[np.float64], family_s0_min: NDArray[np.float64]
    ) -> int:
        """Explicit fast path: the critical-stretch trial, its commit and :meth:`force` in
        one pass over the bonds (the same bits as the three calls in turn). Bonds whose
        stretch reaches (s0_i + s0_j)/2 break for good; returns the number broken."""
        if self.precision == "float32":
            return self._force_f32(state, point_s0, family_s0_min)
        b = self.bonds
        return int(
            self._kernel(
                self.cloud.x, state.u, b.offsets, b.bond_j, self.stiffness, state.intact,
                point_s0, family_s0_min, state.force, self._broken_scratch,
            )
        )  # fmt: skip

    def force_sed_and_break(
        self,
        state: State,
        point_s0: NDArray[np.float64],
        family_s0_min: NDArray[np.float64],
        k0l: NDArray[np.float64],
        tensile: bool,
        energy: NDArray[np.float64],
    ) -> int:
        """2-D: :meth:`force_and_break` plus the SED energy with the initial stiffness
        ``k0l`` = stiffness0 |xi| / 4 in the same pass (``energy`` (n,) J/m^3)."""
        b = self.bonds
        return int(
            bond_based.force_sed_2d(
                self.cloud.x, state.u, b.offsets, b.bond_j, self.stiffness, state.intact,
                point_s0, family_s0_min, state.force, self._broken_scratch, k0l, tensile,
                energy,
            )
        )  # fmt: skip

    # -- capabilities -------------------------------------------------------------------
    def fused_step(self, state: State, law: DamageLaw, sed: Any = None) -> FusedStep | None:
        """With a critical-stretch law (``law.stretch_thresholds()``): its trial, commit
        and the force in one pass (:meth:`force_and_break`), in 2-D with the SED energy of
        ``sed`` in the same pass (:meth:`force_sed_and_break`); None otherwise."""
        if not self.fused_breaking:
            return None
        thresholds = law.stretch_thresholds()
        if thresholds is None:
            return None
        point_s0, family_s0_min = thresholds
        if sed is not None and self.dim == 2:  # forces and SED energy in one pass
            broken = self.force_sed_and_break(
                state, point_s0, family_s0_min, sed.k0l, sed.tensile, sed.energy
            )
            return FusedStep(broken, counted=True, energy_done=True)
        return FusedStep(self.force_and_break(state, point_s0, family_s0_min))

    @property
    def broken_counts(self) -> NDArray[np.int64]:
        """Bonds broken per owned point by the last fused pass (n_owned,)."""
        return self._broken_scratch

    def pair_force_coefficients(self, state: State) -> NDArray[np.float64]:
        """g_k = stiffness_k mu_k (1/L_k - 1/r_k) (n_bonds,) (N/m^4): the force density
        of bond k on its point is ``g_k y_k`` (the kernel's pair force; the stress of
        ``point_stress``)."""
        b = self.bonds
        y = b.bond_xi + (state.u[b.bond_j] - state.u[b.bond_i])
        r = np.sqrt(np.einsum("ij,ij->i", y, y))
        stiff = np.asarray(self.stiffness, dtype=np.float64)
        return np.asarray(stiff * state.intact * (self.inv_length - 1.0 / r))

    # -- energy, bounds, tangent --------------------------------------------------------
    def energy_density(self, state: State) -> NDArray[np.float64]:
        """W_i = 1/4 sum_k stiffness_k mu_k s_k^2 |xi_k| (J/m^3), shape (n,)."""
        b = self.bonds
        out = np.empty(len(b.offsets) - 1)
        bond_based.strain_energy_density(
            self.cloud.x, state.u, b.offsets, b.bond_j, self.stiffness, state.intact, out
        )
        return out

    def stiffness_bound(self) -> NDArray[np.float64]:
        """K_i = sum_k stiffness_k / |xi_k| (N/m^4): Silling & Askari (2005), eq. 18
        gives dt_i = sqrt(2 rho / K_i)."""
        b = self.bonds
        out = np.empty(len(b.offsets) - 1)
        bond_based.stiffness_bound_per_point(self.cloud.x, b.offsets, b.bond_j, self.stiffness, out)
        return out

    def tangent(self, state: State) -> sp.csr_matrix:
        """Analytic tangent K = -d(V f)/du (N/m), shape (n dim, n dim)
        (:func:`peridynamics.families.pmb.tangent.pmb_tangent`)."""
        return pmb_tangent(self, state)
