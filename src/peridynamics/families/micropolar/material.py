"""Micropolar bond-based material (2-D): axial, shear and rotational bond springs.

Every point carries a displacement (u, v) and a rotation theta (counter-clockwise
positive). A bond i -> j of reference length xi and unit vectors n = xi/|xi|,
n_perp = e_z x n has (small deformation; Diana & Casolo 2019, section 2; Zhou, Zhu &
Li (n.d.), eqs 2-6)

    axial stretch      l     = (u_j - u_i) . n / xi,
    shear deformation  gamma = (u_j - u_i) . n_perp / xi - (theta_i + theta_j) / 2,
    relative rotation  phi   = theta_j - theta_i,

and the micropotential (energy per V_i V_j, J/m^6)

    w = 1/2 xi (k_n l^2 + k_t gamma^2 + k_phi phi^2).

A rigid rotation (u_j - u_i = omega e_z x xi, theta = omega) gives l = gamma = phi = 0.
Under a homogeneous strain eps with theta the macro-rotation, gamma = n_perp.eps.n and
phi = 0, so k_phi does not enter homogeneous deformation. Energy equivalence with the
isotropic 2-D continuum (isotropic expansion fixes k_n, pure shear k_t; t the
thickness, delta the horizon):

* plane stress: k_n = 6 E / (pi t delta^3 (1 - nu)),
  k_t = 6 E (1 - 3 nu) / (pi t delta^3 (1 - nu^2));
* plane strain: k_n = 6 E / (pi t delta^3 (1 + nu)(1 - 2 nu)),
  k_t = 6 E (1 - 4 nu) / (pi t delta^3 (1 + nu)(1 - 2 nu)).

k_t >= 0 limits nu to [-1, 1/3] (plane stress) and [-1, 1/4] (plane strain); at the
limit k_t = 0 and the model is the PMB model (whose micromodulus is k_n there).

k_phi: the formula of the paper (its eq. 11) is lost. The default is the beam-lattice
relation k_phi = k_t / 12: the exact two-node Timoshenko beam energy of a shear-rigid
beam splits into a shear term k_s (dv - L (theta_i + theta_j)/2)^2 and a relative
rotation term (EI / L)(theta_j - theta_i)^2 with EI / L = k_s L^2 / 12. Any ratio
k_phi / k_t >= 0 can be chosen (``rotational_stiffness_ratio``; 0 is Diana &
Casolo's model without a rotational spring, stable for k_t > 0).

Critical stretch from the fracture energy G_c (J/m^2): the energy of the axial springs
crossing a unit crack area when they reach l_c (only k_n stores energy at rupture),
G_c = 4 kappa beta l_c^2 with beta = 3 delta / (4 pi) and kappa the 2-D bulk modulus
(E / (2 (1 - nu)) in plane stress, E / (2 (1 + nu)(1 - 2 nu)) in plane strain); for
nu = 1/3 (plane stress) it is the PMB value sqrt(4 pi G_c / (9 E delta)).

Rotational inertia (explicit dynamics): a point is the square cell of side dx around
it, whose polar moment of inertia per unit volume is rho dx^2 / 6 (kg/m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from peridynamics.bonds.bonds import Bonds
from peridynamics.families import moduli
from peridynamics.families.micropolar.force import MicropolarForceModel
from peridynamics.families.micropolar.springs import SpringConstants
from peridynamics.geometry.cloud import PointCloud

#: k_phi / k_t of the beam-lattice relation (the default)
BEAM_ROTATIONAL_RATIO = 1.0 / 12.0


@dataclass(frozen=True)
class MicropolarMaterial:
    """Micropolar bond-based elastic material (2-D, plane stress or plane strain).

    Parameters
    ----------
    youngs_modulus : float
        E (Pa), finite and > 0.
    poisson_ratio : float
        nu, in [-1, 1/3] in plane stress and [-1, 1/4] in plane strain (checked when
        the plane is known, :meth:`springs`).
    density : float
        rho (kg/m^3), finite and > 0.
    rotational_stiffness_ratio : float
        k_phi / k_t >= 0 (default 1/12, the beam-lattice relation).
    corrected_critical_stretch : bool
        With the surface correction on, a bond whose springs the correction scales by
        g_k breaks at the axial stretch l_c / sqrt(g_k), so that the energy its axial
        spring stores at rupture, 1/2 g_k k_n l^2 xi, is the one l_c is calibrated
        with (G_c of the uncorrected continuum springs). Default False.

    Raises
    ------
    ValueError
        Naming the offending key (``material.poisson_ratio`` ...) and its range.
    """

    youngs_modulus: float
    poisson_ratio: float
    density: float
    rotational_stiffness_ratio: float = BEAM_ROTATIONAL_RATIO
    corrected_critical_stretch: bool = False

    def __post_init__(self) -> None:
        E, nu, rho = self.youngs_modulus, self.poisson_ratio, self.density
        if not (math.isfinite(E) and E > 0):
            raise ValueError(f"material.youngs_modulus must be a finite value > 0 Pa, got {E}")
        if not (math.isfinite(rho) and rho > 0):
            raise ValueError(f"material.density must be a finite value > 0 kg/m^3, got {rho}")
        if not (math.isfinite(nu) and -1.0 < nu <= 1.0 / 3.0):
            raise ValueError(
                f"material.poisson_ratio = {nu} is outside the micropolar model's range "
                "-1 < nu <= 1/3 (plane stress; 1/4 in plane strain): the shear spring "
                "k_t would be negative. Use a smaller poisson_ratio or material.model lps"
            )
        r = self.rotational_stiffness_ratio
        if not (math.isfinite(r) and r >= 0):
            raise ValueError(
                f"material.rotational_stiffness_ratio must be a finite value >= 0, got {r}"
            )

    # -- moduli -------------------------------------------------------------------------
    def max_poisson_ratio(self, plane: str | None) -> float:
        """Largest admissible nu: 1/3 (plane stress), 1/4 (plane strain)."""
        return 0.25 if plane == "strain" else 1.0 / 3.0

    def bulk_modulus_2d(self, plane: str | None) -> float:
        """2-D bulk modulus kappa (Pa): E/(2(1-nu)) (stress), E/(2(1+nu)(1-2nu)) (strain)."""
        return moduli.plane_bulk_modulus(self.youngs_modulus, self.poisson_ratio, plane)

    @property
    def shear_modulus(self) -> float:
        """mu = E / (2 (1 + nu)) (Pa)."""
        return moduli.shear_modulus(self.youngs_modulus, self.poisson_ratio)

    def in_plane_moduli(self, plane: str | None) -> tuple[float, float]:
        """(E', nu') of the 2-D stress-strain law: (E/(1-nu^2), nu/(1-nu)) in plane
        strain, (E, nu) in plane stress."""
        return moduli.in_plane_moduli(self.youngs_modulus, self.poisson_ratio, 2, plane)

    def c11(self, plane: str | None) -> float:
        """sigma_xx / eps_xx under uniaxial strain (Pa): E'/(1 - nu'^2)."""
        e, nu = self.in_plane_moduli(plane)
        return e / (1.0 - nu * nu)

    def springs(
        self, dim: int, horizon: float, thickness: float, plane: str | None
    ) -> SpringConstants:
        """k_n, k_t, k_phi (N/m^6) from energy equivalence (module docstring).

        Raises
        ------
        ValueError
            For a model that is not 2-D, or nu beyond the plane-strain limit 1/4.
        """
        _check_dim(dim, plane)
        if not (horizon > 0 and thickness > 0):
            raise ValueError(f"horizon and thickness must be > 0 m, got {horizon}, {thickness}")
        nu = self.poisson_ratio
        if nu > self.max_poisson_ratio(plane) + 1e-12:
            raise ValueError(
                f"material.poisson_ratio = {nu} is above the micropolar plane-strain limit "
                "1/4 (the shear spring k_t would be negative); use nu <= 0.25, plane "
                "stress (nu <= 1/3) or material.model lps"
            )
        kappa = self.bulk_modulus_2d(plane)
        mu = self.shear_modulus
        scale = 12.0 / (math.pi * thickness * horizon**3)
        kn = scale * kappa
        shear = 2.0 * mu - kappa
        kt = 0.0 if shear <= 1e-12 * kappa else scale * shear  # exactly 0 at the limit
        return SpringConstants(kn, kt, self.rotational_stiffness_ratio * kt)

    # -- fracture, waves, contact -------------------------------------------------------
    def critical_stretch(
        self,
        fracture_energy: float,
        dim: int,
        horizon: float,
        cross_section: float = 1.0,
        plane: str | None = None,
    ) -> float:
        """l_c = sqrt(G_c / (4 kappa beta)), beta = 3 delta / (4 pi) (module docstring)."""
        if not (math.isfinite(fracture_energy) and fracture_energy > 0):
            raise ValueError(
                f"damage.fracture_energy must be a finite value > 0 J/m^2, got {fracture_energy}"
            )
        _check_dim(dim, plane)
        beta = 3.0 * horizon / (4.0 * math.pi)
        return math.sqrt(fracture_energy / (4.0 * self.bulk_modulus_2d(plane) * beta))

    def micromodulus_constant(
        self, dim: int, horizon: float, cross_section: float = 1.0, plane: str | None = None
    ) -> float:
        """The axial spring k_n (N/m^6): the PMB-equivalent micromodulus that contact and
        viscous bond forces are scaled with."""
        return self.springs(dim, horizon, cross_section, plane).axial

    def wave_speed(self) -> float:
        """sqrt(E / rho) (m/s)."""
        return math.sqrt(self.youngs_modulus / self.density)

    def bar_wave_speed(self, dim: int, plane: str | None) -> float:
        """sqrt(E' / rho) (m/s) of the 2-D idealisation."""
        return math.sqrt(self.in_plane_moduli(plane)[0] / self.density)

    def p_wave_speed(self, dim: int, plane: str | None) -> float:
        """sqrt(C11 / rho) (m/s)."""
        return math.sqrt(self.c11(plane) / self.density)

    def shear_wave_speed(self) -> float:
        """sqrt(mu / rho) (m/s)."""
        return math.sqrt(self.shear_modulus / self.density)

    def force_model(
        self, cloud: PointCloud, bonds: Bonds, surface_correction: bool = False
    ) -> MicropolarForceModel:
        """The micropolar force model of this material on ``cloud`` and ``bonds``."""
        return MicropolarForceModel(cloud, bonds, self, surface_correction=surface_correction)


def _check_dim(dim: int, plane: str | None) -> None:
    if dim != 2:
        raise ValueError(
            f"material.model micropolar is a 2-D model (plane stress or strain); got {dim}-D"
        )
    if plane not in ("stress", "strain"):
        raise ValueError(f"2-D micropolar needs plane 'stress' or 'strain', got {plane!r}")
