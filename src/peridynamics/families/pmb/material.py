"""Bond-based prototype microelastic brittle (PMB) / linear microelastic material.

Micromodulus by energy equivalence with the classical strain energy
(Lu & Wang (2016), eq. 4; PD wave dispersion (n.d.), eq. 7) for a constant profile:

* 1-D bar of area A:          c = 2 E / (A delta^2)
* 2-D plane stress, thick h:  c = 9 E / (pi h delta^3)       (nu = 1/3 fixed)
* 2-D plane strain, thick h:  c = 48 E / (5 pi h delta^3)    (nu = 1/4 fixed)
* 3-D:                        c = 12 E / (pi delta^4)        (nu = 1/4 fixed)

A conical profile ``c(r) = c0 (1 - r/delta)`` keeps the same macroscopic modulus with
``c0 = (d + 2) * c_constant`` (d the dimension), because the elastic-energy moment
``int_0^1 g(t) t^d dt`` is ``1/(d+1)`` for g = 1 and ``1/((d+1)(d+2))`` for the cone.

Critical stretch from the fracture energy G0 (Silling & Askari 2005; Ha & Bobaru 2010)
follows from ``G0 = (s0^2 / 2) K_d int_0^delta c(r) r^(d+1) dr`` with K_1 = A,
K_2 = 2 h, K_3 = pi; for the constant profile this gives
``s0 = sqrt(3 G0 / (E delta))`` (1-D), ``sqrt(4 pi G0 / (9 E delta))`` (plane stress),
``sqrt(5 pi G0 / (12 E delta))`` (plane strain) and ``sqrt(5 G0 / (9 K delta))`` (3-D).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds, setup_chunk_bonds
from peridynamics.bonds.search import bond_chunks
from peridynamics.families.moduli import pmb_micromodulus
from peridynamics.families.pmb.force import PMBForceModel
from peridynamics.families.pmb.fracture_energy import fracture_energy_factor as lattice_factor
from peridynamics.geometry.cloud import PointCloud

Profile = Literal["constant", "conical"]
PROFILES: tuple[str, ...] = ("constant", "conical")


def fixed_poisson_ratio(dim: int, plane: str | None) -> float | None:
    """Poisson ratio implied by bond-based PD (None in 1-D, where it plays no role)."""
    if dim == 1:
        return None
    if dim == 2 and plane == "stress":
        return 1.0 / 3.0
    return 0.25


def _energy_moment(profile: str, dim: int) -> float:
    """int_0^1 g(t) t^(d+1) dt for the influence profile g."""
    if profile == "constant":
        return 1.0 / (dim + 2)
    return 1.0 / ((dim + 2) * (dim + 3))


def _angular_cos4(dim: int) -> float:
    """Integral of cos^4 over directions: 2 (1-D, two sides), 3 pi / 4 (2-D), 4 pi / 5 (3-D)."""
    return {1: 2.0, 2: 0.75 * math.pi, 3: 0.8 * math.pi}[dim]


@dataclass(frozen=True)
class BondBasedMaterial:
    """PMB / linear microelastic bond material.

    Parameters
    ----------
    youngs_modulus : float
        E (Pa), > 0.
    density : float
        rho (kg/m^3), > 0.
    profile : {"constant", "conical"}
        Micromodulus profile over the horizon.
    micromodulus_value : float, optional
        Use this constant-profile micromodulus c (N/m^6) instead of the energy-equivalent
        one, e.g. the 18 k / (pi delta^4) printed in SED-PD (2021), eq. 8, for its
        plane-stress model (see docs/theory_rock.md). E then only enters the outputs that
        quote it.
    isotropic_family : bool
        On a regular 3-D grid, multiply every bond's micromodulus by a factor quartic in
        its direction that makes the lattice family isotropic (interior nu = 1/4 and
        E = E0 instead of the cubic lattice's 0.269 and 0.962 E0 at delta = 3.015 dx;
        :mod:`peridynamics.families.pmb.isotropy`). Part of the surface correction: no
        effect without it, in 1-D, 2-D or on irregular clouds. The deck key is
        ``discretisation.isotropic_family``.
    fracture_energy_factor : float
        G0 is multiplied by this (> 0) before the critical stretch is computed; 1: the
        continuum calibration (Silling & Askari (2005)).
        :meth:`with_lattice_fracture_energy` sets it so that the bonds of the grid's
        interior family hold G0 across a plane
        (:mod:`peridynamics.families.pmb.fracture_energy`; the deck key is
        ``discretisation.lattice_fracture_energy``).

    Examples
    --------
    >>> import peridynamics as pd
    >>> pd.BondBasedMaterial(youngs_modulus=70e9, density=2700.0).density
    2700.0
    """

    youngs_modulus: float
    density: float
    profile: Profile = "constant"
    micromodulus_value: float | None = None
    isotropic_family: bool = True
    fracture_energy_factor: float = 1.0

    def __post_init__(self) -> None:
        if not (self.fracture_energy_factor > 0 and math.isfinite(self.fracture_energy_factor)):
            raise ValueError(
                "fracture_energy_factor must be a finite value > 0, got "
                f"{self.fracture_energy_factor}"
            )
        if not (self.youngs_modulus > 0 and math.isfinite(self.youngs_modulus)):
            raise ValueError(
                f"youngs_modulus must be a finite value > 0 Pa, got {self.youngs_modulus}"
            )
        if not (self.density > 0 and math.isfinite(self.density)):
            raise ValueError(f"density must be a finite value > 0 kg/m^3, got {self.density}")
        if self.micromodulus_value is not None and not (
            self.micromodulus_value > 0 and math.isfinite(self.micromodulus_value)
        ):
            raise ValueError(
                f"micromodulus must be a finite value > 0 N/m^6, got {self.micromodulus_value}"
            )
        if self.profile not in PROFILES:
            raise ValueError(
                f"unknown micromodulus profile {self.profile!r}; use one of {PROFILES}"
            )

    # -- calibration ---------------------------------------------------------------
    def micromodulus_constant(
        self, dim: int, horizon: float, cross_section: float, plane: str | None
    ) -> float:
        """Constant-profile micromodulus c (N/m^6), table in docs/theory_bond_based.md
        (or the value given as ``micromodulus_value``)."""
        if self.micromodulus_value is not None:
            return float(self.micromodulus_value)
        return pmb_micromodulus(self.youngs_modulus, dim, horizon, cross_section, plane)

    def micromodulus(
        self,
        length: NDArray[np.float64],
        dim: int,
        horizon: float,
        cross_section: float,
        plane: str | None,
    ) -> NDArray[np.float64]:
        """c(|xi|) for each bond length (N/m^6), shape like ``length``."""
        c = self.micromodulus_constant(dim, horizon, cross_section, plane)
        if self.profile == "constant":
            return np.full(np.shape(length), c)
        return (dim + 2) * c * np.clip(1.0 - np.asarray(length) / horizon, 0.0, None)

    def bond_stiffness(
        self, cloud: PointCloud, bonds: Bonds, corrected: bool = True
    ) -> NDArray[np.float64]:
        """stiffness_k = c(|xi_k|) * beta_k V_j * lambda_k (N/m^3 per unit stretch), shape
        (n_bonds,); made range by range, so lengths and volumes the bond list does not
        hold are not kept."""
        out = np.empty(bonds.n_bonds)
        for a, b in bond_chunks(bonds.offsets, setup_chunk_bonds(cloud.dim)):
            c = self.micromodulus(
                bonds.bond_range("bond_length", a, b), cloud.dim, bonds.horizon,
                cloud.cross_section, cloud.plane,
            )  # fmt: skip
            k = c * bonds.bond_range("bond_volume", a, b)
            out[a:b] = k * bonds.bond_range("bond_correction", a, b) if corrected else k
        return out

    def _cross_factor(self, dim: int, cross_section: float) -> float:
        return {1: cross_section, 2: cross_section, 3: 1.0}[dim]

    def uniaxial_energy_density(
        self, strain: float, dim: int, horizon: float, cross_section: float, plane: str | None
    ) -> float:
        """Continuum (exact-integral) W for uniaxial strain in the infinite body (J/m^3).

        W = 1/4 eps^2 [int cos^4 dOmega] K int_0^delta c(r) r^d dr; equals E eps^2/2 in
        1-D, 9 E eps^2 / 16 in plane stress and 0.6 E eps^2 in 3-D.
        """
        c0 = self.micromodulus_constant(dim, horizon, cross_section, plane)
        scale = 1.0 if self.profile == "constant" else float(dim + 2)
        moment = horizon ** (dim + 1) * (
            1.0 / (dim + 1) if self.profile == "constant" else 1.0 / ((dim + 1) * (dim + 2))
        )
        return (
            0.25
            * strain**2
            * _angular_cos4(dim)
            * self._cross_factor(dim, cross_section)
            * scale
            * c0
            * moment
        )

    def critical_stretch(
        self,
        fracture_energy: float,
        dim: int,
        horizon: float,
        cross_section: float,
        plane: str | None,
    ) -> float:
        """s0 from G0 (J/m^2): the continuous family's critical stretch (see the module
        docstring) of ``fracture_energy_factor * G0`` (the factor 1 unless
        ``discretisation.lattice_fracture_energy`` set it)."""
        if not fracture_energy > 0:
            raise ValueError(f"fracture_energy must be > 0 J/m^2, got {fracture_energy}")
        c0 = self.micromodulus_constant(dim, horizon, cross_section, plane)
        scale = 1.0 if self.profile == "constant" else float(dim + 2)
        k_d = {1: cross_section, 2: 2.0 * cross_section, 3: math.pi}[dim]
        integral = scale * c0 * horizon ** (dim + 2) * _energy_moment(self.profile, dim)
        energy = self.fracture_energy_factor * fracture_energy
        return math.sqrt(2.0 * energy / (k_d * integral))

    def with_lattice_fracture_energy(
        self, cloud: PointCloud, bonds: Bonds, surface_correction: bool
    ) -> BondBasedMaterial:
        """This material with the ``fracture_energy_factor`` that makes the interior
        family of the regular grid of ``cloud`` hold G0 across a plane normal to a grid
        axis (:func:`peridynamics.families.pmb.fracture_energy.fracture_energy_factor`;
        ValueError off a regular grid)."""
        factor = lattice_factor(self, cloud, bonds, surface_correction)
        return replace(self, fracture_energy_factor=factor)

    def force_model(
        self, cloud: PointCloud, bonds: Bonds, surface_correction: bool = False
    ) -> PMBForceModel:
        """The PMB force model of this material on ``bonds``."""
        return PMBForceModel(cloud, bonds, self, surface_correction)

    def wave_speed(self) -> float:
        """Bar wave speed sqrt(E / rho) (m/s)."""
        return math.sqrt(self.youngs_modulus / self.density)
