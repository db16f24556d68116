"""The model evaluator: owns the physics order of one force evaluation.

Order (ARCHITECTURE.md): damage (bond breaking) -> bond forces -> external loads.
Solvers never compute physics; they call :meth:`Model.internal_force` and
:meth:`Model.external_force`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.bonds.surface import energy_correction_factors
from peridynamics.damage.critical_stretch import NO_DAMAGE, CriticalStretch, family_minimum
from peridynamics.damage.sed import SEDSoftening
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import bond_based
from peridynamics.kernels.sed import (
    sed_levels,
    sed_stiffness,
    sed_stiffness_raised,
    sed_update,
)
from peridynamics.kernels.viscous import add_viscous_force
from peridynamics.loading.conditions import BodyForce
from peridynamics.materials.bond_based import BondBasedMaterial
from peridynamics.materials.viscosity import BondViscosity

#: uniaxial strain of the surface-correction calibration: small, so that the geometric
#: nonlinearity of the stretch (relative O(strain)) does not bias the factors
_CALIBRATION_STRAIN = 1e-6


@dataclass
class Model:
    """Bond-based peridynamic model of one body.

    Parameters
    ----------
    cloud : PointCloud
    bonds : Bonds
    material : BondBasedMaterial
    damage : CriticalStretch
        ``NO_DAMAGE`` keeps every bond.
    body_forces : sequence of BodyForce
        Force-like loads (body forces, tractions spread over a layer).
    surface_correction : bool
        Apply the energy-method surface correction (Madenci & Oterkus 2014).
    viscosity : BondViscosity, optional
        Viscous bond forces (seed 003 eqs 52-56) evaluated from the velocity passed to
        :meth:`internal_force`; ``None`` or both coefficients 0 is plain PD.
    softening : SEDSoftening, optional
        Strain-energy-density softening of the point moduli (seed 001 eqs 18-24),
        updated at every force evaluation before the bond forces.
    contact : object with ``add_force(u, intact, force)``, optional
        Short-range contact between points not joined by an intact bond.
    damping : float
        Mass-proportional damping coefficient c_d (1/s): adds -rho c_d v to the force
        density (local damping for quasi-static runs by explicit dynamics).
    """

    cloud: PointCloud
    bonds: Bonds
    material: BondBasedMaterial
    damage: CriticalStretch = NO_DAMAGE
    body_forces: Sequence[BodyForce] = ()
    surface_correction: bool = False
    viscosity: BondViscosity | None = None
    softening: SEDSoftening | None = None
    contact: Any = None
    damping: float = 0.0
    stiffness: NDArray[np.float64] = field(init=False, repr=False)
    point_s0: NDArray[np.float64] = field(init=False, repr=False)
    family_s0_min: NDArray[np.float64] = field(init=False, repr=False)
    density: NDArray[np.float64] = field(init=False, repr=False)
    inv_length: NDArray[np.float64] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        c = self.cloud
        if self.surface_correction:
            raw = self.material.bond_stiffness(c, self.bonds, corrected=False)
            w_inf = self.material.uniaxial_energy_density(
                _CALIBRATION_STRAIN, c.dim, self.bonds.horizon, c.cross_section, c.plane
            )
            factors = energy_correction_factors(c.x, self.bonds, raw, w_inf, _CALIBRATION_STRAIN)
            self.bonds = self.bonds.with_correction(factors)
        self.stiffness = self.material.bond_stiffness(c, self.bonds)
        self.inv_length = 1.0 / self.bonds.bond_length
        self._broken_scratch = np.zeros(c.n_points, dtype=np.int64)
        self.point_s0 = self.damage.point_threshold(c.n_points)
        self.family_s0_min = family_minimum(self.bonds, self.point_s0)
        self.density = np.full(c.n_points, self.material.density)
        self._force_kernel = bond_based.FORCE_KERNELS[c.dim]
        if not (np.isfinite(self.damping) and self.damping >= 0):
            raise ValueError(f"damping must be >= 0 (1/s), got {self.damping}")
        if self.softening is not None:
            self._stiffness0 = self.stiffness.copy()
            self.stiffness = self.stiffness.copy()
            w_a, w_c = self.softening.thresholds(self.material.youngs_modulus, self.point_s0)
            # no-fail points (s0 = inf) never soften: a finite sentinel keeps the kernel's
            # arithmetic free of infinities
            self._w_a = np.where(np.isfinite(w_a), w_a, 1e300)
            self._w_c = np.where(np.isfinite(w_c), w_c, 1e300)
            self.sed_level = np.zeros(c.n_points, dtype=np.int64)
            self.sed_factor = np.ones(c.n_points)
            self.sed_energy = np.zeros(c.n_points)
            self._sed_raised = np.zeros(c.n_points, dtype=np.uint8)
            self._k0l = 0.25 * self._stiffness0 * self.bonds.bond_length
            self._reverse = self.bonds.reverse_index()
        self._viscous: tuple[float, float] | None = None
        if self.viscosity is not None and self.viscosity.active:
            self._viscous = self.viscosity.coefficients(
                c.dim,
                self.bonds.horizon,
                c.cross_section,
                self.material.youngs_modulus,
                self.material.density,
            )

    @property
    def dim(self) -> int:
        """Spatial dimension."""
        return self.cloud.dim

    @property
    def n_points(self) -> int:
        """Number of points."""
        return self.cloud.n_points

    def internal_force(
        self,
        u: NDArray,
        intact: NDArray[np.uint8],
        force: NDArray,
        max_stretch: NDArray,
        v: NDArray | None = None,
    ) -> int:
        """Break bonds, then fill ``force`` (n, dim) with the bond force density (N/m^3).

        ``intact`` (n_bonds,) is updated in place; ``max_stretch`` (n,) receives the
        largest tensile stretch of an intact bond per point (0 if none is stretched).
        ``v`` (n, dim) is the velocity the viscous forces use (required when the model
        has viscosity; ignored otherwise). Returns the number of directed bonds broken.
        """
        b = self.bonds
        soft = self.softening
        if soft is not None and self.dim == 2:  # forces and SED energy in one pass
            broken = int(
                bond_based.force_sed_2d(
                    self.cloud.x, u, b.offsets, b.bond_j, self.inv_length, self.stiffness,
                    intact, self.point_s0, self.family_s0_min, force, max_stretch,
                    self._broken_scratch, self._k0l, soft.energy == "tensile",
                    self.sed_energy,
                )
            )  # fmt: skip
            changed = sed_levels(
                self.sed_energy, self._w_a, self._w_c, soft.levels, self.sed_level,
                self._sed_raised,
            )  # fmt: skip
        else:
            broken = int(
                self._force_kernel(
                    self.cloud.x,
                    u,
                    b.offsets,
                    b.bond_j,
                    self.inv_length,
                    self.stiffness,
                    intact,
                    self.point_s0,
                    self.family_s0_min,
                    force,
                    max_stretch,
                    self._broken_scratch,
                )
            )
            changed = 0
            if soft is not None:
                changed = sed_update(
                    self.cloud.x, u, b.offsets, b.bond_j, b.bond_length, self._stiffness0,
                    intact, self._w_a, self._w_c, soft.levels, self.sed_level, self.sed_energy,
                    soft.energy == "tensile", self._sed_raised,
                )  # fmt: skip
        if changed:  # the new moduli act from the next force evaluation on
            assert soft is not None
            sed_stiffness_raised(
                b.offsets, b.bond_j, self._reverse, self._stiffness0, self.sed_level,
                soft.levels, soft.residual, self.sed_factor, self.stiffness,
                self._sed_raised,
            )  # fmt: skip
        if self.contact is not None:
            self.contact.add_force(u, intact, force)
        if self.damping > 0 and v is not None:
            force -= (self.damping * self.density)[:, None] * v
        if self._viscous is not None:
            if v is None:
                raise ValueError("a model with viscosity needs the velocity v in internal_force")
            add_viscous_force(
                self.cloud.x, u, v, b.offsets, b.bond_j, self.inv_length, b.bond_volume,
                intact, self._viscous[0], self._viscous[1], force,
            )  # fmt: skip
        return broken

    def history_arrays(self) -> dict[str, NDArray]:
        """History variables kept in the model (for checkpoints): the SED levels."""
        return {} if self.softening is None else {"sed_level": self.sed_level.copy()}

    def restore_history(self, arrays: dict[str, NDArray]) -> None:
        """Restore :meth:`history_arrays` (and the moduli that follow from them)."""
        if self.softening is None:
            return
        if "sed_level" not in arrays or arrays["sed_level"].shape != self.sed_level.shape:
            raise ValueError("the checkpoint has no SED softening levels for this model")
        self.sed_level[:] = arrays["sed_level"]
        self._sed_stiffness()

    def _sed_stiffness(self) -> None:
        """Point factors and bond stiffness from the SED levels (eq. 24)."""
        assert self.softening is not None
        b = self.bonds
        sed_stiffness(
            b.offsets, b.bond_j, self._stiffness0, self.sed_level, self.softening.levels,
            self.softening.residual, self.sed_factor, self.stiffness,
        )  # fmt: skip

    def viscous_power(self, u: NDArray, v: NDArray, intact: NDArray[np.uint8]) -> float:
        """Power of the viscous forces sum_i V_i F_visc_i . v_i (W); never positive. 0 for
        a model without viscosity."""
        if self._viscous is None:
            return 0.0
        b = self.bonds
        f = np.zeros_like(u)
        add_viscous_force(
            self.cloud.x, u, v, b.offsets, b.bond_j, self.inv_length, b.bond_volume,
            intact, self._viscous[0], self._viscous[1], f,
        )  # fmt: skip
        return float(np.sum(self.cloud.volume[:, None] * f * v))

    def external_force(self, t: float, out: NDArray) -> None:
        """Fill ``out`` (n, dim) with the external body-force density at time t (N/m^3)."""
        if not self.body_forces and not out.any():
            return  # nothing to add and already zero (the common case)
        out.fill(0.0)
        for load in self.body_forces:
            load.add_to(out, t)

    def strain_energy_density(self, u: NDArray, intact: NDArray[np.uint8]) -> NDArray:
        """W_i (J/m^3), shape (n,)."""
        b = self.bonds
        out = np.empty(self.n_points)
        bond_based.strain_energy_density(
            self.cloud.x, u, b.offsets, b.bond_j, b.bond_length, self.stiffness, intact, out
        )
        return out

    def strain_energy(self, u: NDArray, intact: NDArray[np.uint8]) -> float:
        """Total strain energy sum W_i V_i (J)."""
        # np.sum, not @: a BLAS dot can wake OpenBLAS threads that then spin against
        # Numba's workers and slow the next force evaluations
        return float(np.sum(self.strain_energy_density(u, intact) * self.cloud.volume))

    def kinetic_energy(self, v: NDArray) -> float:
        """Total kinetic energy 1/2 sum rho_i V_i |v_i|^2 (J)."""
        return float(0.5 * np.sum(self.density * self.cloud.volume * np.sum(v * v, axis=1)))

    def point_damage(self, intact: NDArray[np.uint8]) -> NDArray:
        """Local damage phi (seed 000 eq. 7), shape (n,)."""
        out = np.empty(self.n_points)
        bond_based.damage(self.bonds.offsets, self.bonds.bond_volume, intact, out)
        return out

    def section_stress(self, u: NDArray, intact: NDArray[np.uint8], position: float) -> float:
        """1-D stress (Pa, tension positive) across the section x = ``position``: the sum
        of the forces of all intact bonds that cross it, divided by the area (seed 000
        section 3: PD stress from the force flux, comparable with the FDM stress)."""
        if self.dim != 1:
            raise ValueError("section_stress is defined for 1-D bars")
        b = self.bonds
        x = self.cloud.x[:, 0]
        cross = (x[b.bond_i] < position) & (x[b.bond_j] > position)
        k = np.flatnonzero(cross)
        i, j = b.bond_i[k], b.bond_j[k]
        e = (x[j] - x[i]) + (u[j, 0] - u[i, 0])
        r = np.abs(e)
        # force on the left point i from j (N): stiffness (1/L - 1/r) e mu V_i
        f = self.stiffness[k] * (self.inv_length[k] - 1.0 / r) * e * intact[k]
        return float(np.sum(f * self.cloud.volume[i]) / self.cloud.cross_section)

    def point_stress(self, u: NDArray, intact: NDArray[np.uint8]) -> NDArray:
        """Peridynamic (virial) stress of each point, shape (n, dim, dim) (Pa):
        sigma_i = 1/2 sum_k f_k (xi_k + eta_k) (x) xi_k, with f_k the elastic bond force
        density of bond k times V_j (Lehoucq & Silling 2008, the bond-based form used for
        stress maps; viscous forces are not included). For a uniform strain it equals the
        continuum stress of the model in the bulk. Not used in the time loop (NumPy)."""
        b = self.bonds
        xi = b.bond_xi
        e = xi + (u[b.bond_j] - u[b.bond_i])
        r = np.linalg.norm(e, axis=1)
        g = self.stiffness * intact * (self.inv_length - 1.0 / r)  # c V s / r
        pair = 0.5 * g[:, None, None] * e[:, :, None] * xi[:, None, :]
        out = np.zeros((self.n_points, self.dim, self.dim))
        np.add.at(out, b.bond_i, pair)
        return out

    def pressure(self, u: NDArray, intact: NDArray[np.uint8]) -> NDArray:
        """Mean compressive stress -tr(sigma) / dim of each point, shape (n,) (Pa)."""
        return -np.trace(self.point_stress(u, intact), axis1=1, axis2=2) / self.dim

    def stable_time_step(self) -> float:
        """Largest stable explicit step, min over points of Silling & Askari's bound (s).

        With linear viscosity the bound shrinks as for a damped oscillator integrated
        explicitly: dt = dt_el (sqrt(1 + xi^2) - xi), where xi = gamma / dt_el is the
        damping ratio of the fastest mode (omega = 2 / dt_el) and gamma (s) the largest
        ratio of viscous to elastic bond coefficient (the 1-D rate constant of seed 003
        eq. 39). The quadratic term depends on the amplitude and is not included.
        """
        out = np.empty(self.n_points)
        bond_based.stable_time_step_per_point(
            self.bonds.offsets, self.bonds.bond_length, self.stiffness, self.density, out
        )
        dt = float(out.min())
        if self._viscous is not None and self._viscous[0] > 0:
            ok = self.stiffness > 0
            ratio = self.bonds.bond_volume[ok] / self.stiffness[ok]
            gamma = float(self._viscous[0] * ratio.max())
            xi = gamma / dt
            dt *= np.sqrt(1.0 + xi * xi) - xi
        return dt
