"""Linear peridynamic solid (LPS): the ordinary state-based isotropic elastic material.

3-D (Silling, Epton, Weckner, Xu & Askari 2007, "Peridynamic states and constitutive
modeling", J. Elasticity 88, 151-184, the linear peridynamic solid; the same force state
as Peridigm's ``elastic`` material, c1 = omega theta (9K - 15 mu) / (3m)): with the
weighted volume
``m = sum omega |xi|^2 V``, the dilatation ``theta = (3/m) sum omega |xi| e V`` and the
deviatoric extension ``e^d = e - theta |xi| / 3``,

    W = K theta^2 / 2 + (15 mu / 2m) sum omega (e^d)^2 V,
    t = (3 K theta / m) omega |xi| + (15 mu / m) omega e^d.

2-D: Le, Chan & Schwartz (2014), "A two-dimensional ordinary, state-based peridynamic
model for linearly elastic solids", Int. J. Numer. Meth. Engng 98, 547-561 (plane
strain and plane stress).
The same derivation in d dimensions (the d-dimensional dilatation ``theta_d = (d/m) sum
omega |xi| e V`` is tr(eps) for a homogeneous strain; the angular average
``<(n.A.n)^2> = 2 A:A / (d (d + 2))`` for a traceless A fixes the deviatoric modulus)
gives

    W = k_d theta_d^2 / 2 + (alpha / 2m) sum omega (e - theta_d |xi| / d)^2 V,
    alpha = d (d + 2) mu,  i.e. 15 mu (3-D) and 8 mu (2-D),

with the d-dimensional bulk modulus k_d of the in-plane stress-strain law
``sigma = lambda' tr(eps) I + 2 mu eps`` (k_d = lambda' + 2 mu / d):

* 3-D:           k_3 = K = E / (3 (1 - 2 nu))
* plane strain:  k_2 = lambda + mu = E / (2 (1 + nu) (1 - 2 nu))
* plane stress:  k_2 = lambda' + mu = E / (2 (1 - nu)),  lambda' = E nu / (1 - nu^2)

Expanding the square, with ``sum omega |xi| e^d V = 0``, the same energy reads
``W = A theta_d^2 / 2 + (alpha / 2m) sum omega e^2 V`` with ``A = k_d - (d + 2) mu / d``
(``K - 5 mu / 3`` in 3-D, ``k_2 - 2 mu`` in 2-D); that form is the one evaluated (it is
the exact potential of the standard force state also after bonds break).

The dilatation stored in the State is the *volumetric* strain, ``theta = tf / m sum
omega |xi| e V``, with ``tf = 3`` (3-D), ``tf = 2`` (plane strain: eps_zz = 0) and
``tf = 2 (1 - 2 nu) / (1 - nu)`` in plane stress, where the out-of-plane strain
``eps_zz = -nu / (1 - nu) tr(eps_2D)`` is added (Le et al. 2014, plane stress). In
terms of it

    W = k_theta theta^2 / 2 + (alpha / 2m) sum omega e^2 V,   k_theta = A d^2 / tf^2,
    t = omega (k_theta tf / m) theta |xi| + omega (alpha / m) e,

which reproduces the 3-D coefficients ``(3K - 5 mu)/m`` and ``15 mu / m`` of Peridigm's
elastic model and Le et al.'s 2-D ones: ``2 (K - 5 mu / 3) / m`` and ``8 mu / m`` in
plane strain; in plane stress ``tf = 2 (2 nu - 1)/(nu - 1)`` and
``k_theta tf = tf (K + mu/9 ((nu + 1)/(2 nu - 1))^2) - 8/3 mu (2 - tf/3)`` (the form of
the PDtools code of the same model; checked numerically in the tests).

Admissible Poisson ratio: K > 0 and mu > 0, i.e. -1 < nu < 1/2, in 3-D and in plane
strain. The plane-stress model alone is positive definite up to nu < 1, but it
idealises a thin sheet of a 3-D isotropic material, whose nu is below 1/2; the same
range -1 < nu < 1/2 is therefore required in every case.

Influence functions ``omega``: ``"constant"`` (omega = 1, Peridigm's default) and
``"inverse"`` (omega = delta / |xi|, Madenci & Oterkus 2014). A constant factor in
omega cancels (t is proportional to omega / m), so delta / |xi| and 1 / |xi| are the
same model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

from peridynamics.bonds.bonds import Bonds
from peridynamics.families import moduli
from peridynamics.families.lps.force import LPSForceModel
from peridynamics.families.lps.plastic import PlasticLPSModel
from peridynamics.families.lps.viscoelastic import ViscoelasticLPSModel
from peridynamics.geometry.cloud import PointCloud

Influence = Literal["constant", "inverse"]
INFLUENCES: tuple[str, ...] = ("constant", "inverse")

#: Critical-stretch integrals (see :meth:`LPSMaterial.critical_stretch`):
#: (dim, influence) -> (P_b, P_theta) with G0 = s0^2 delta (P_b mu + P_theta A).
#: P_b is closed-form: 15 (5 - p) / (4 (6 - p)) (3-D), 8 (4 - p) / (pi (5 - p)) (2-D)
#: for omega = (delta/|xi|)^p; P_theta = int_0^1 theta_hat(z)^2 dz with theta_hat the
#: dilatation (per unit stretch) of a point at depth z delta under a crack plane when
#: only its bonds crossing the plane are stretched: 375/616 and 26/45 in 3-D, by
#: quadrature in 2-D (checked in the tests).
_FRACTURE_INTEGRALS: dict[tuple[int, str], tuple[float, float]] = {
    (3, "constant"): (75.0 / 24.0, 375.0 / 616.0),
    (3, "inverse"): (3.0, 26.0 / 45.0),
    (2, "constant"): (32.0 / (5.0 * math.pi), 0.3525236868827),
    (2, "inverse"): (6.0 / math.pi, 0.3225997464260),
}


@dataclass(frozen=True)
class LPSCoefficients:
    """Constants of the LPS force state in one idealisation.

    Attributes
    ----------
    theta_factor : float
        tf: dilatation ``theta = tf / m sum omega |xi| e V`` (volumetric strain).
    k_theta : float
        Dilatation modulus (Pa): ``W = k_theta theta^2 / 2 + ...``.
    alpha : float
        Extension modulus times m (Pa): ``d (d + 2) mu``.
    """

    theta_factor: float
    k_theta: float
    alpha: float


@dataclass(frozen=True)
class LPSMaterial:
    """Linear peridynamic solid (ordinary state-based, isotropic, elastic).

    Parameters
    ----------
    youngs_modulus : float
        E (Pa), finite and > 0.
    poisson_ratio : float
        nu, -1 < nu < 0.5 (see the module docstring).
    density : float
        rho (kg/m^3), finite and > 0.
    influence : {"constant", "inverse"}
        Influence function omega(|xi|): 1 or delta / |xi|.
    viscoelastic : Viscoelasticity or None
        A standard-linear-solid deviatoric response (3-D,
        :mod:`~peridynamics.families.lps.viscoelastic`); None: elastic.
    plasticity : LPSPlasticity or None
        Yield stress and linear isotropic hardening of the elastic-plastic LPS (3-D,
        :mod:`~peridynamics.families.lps.plastic`); None: elastic.

    Raises
    ------
    ValueError
        Naming the offending key (``material.poisson_ratio`` ...) and its range.
    """

    youngs_modulus: float
    poisson_ratio: float
    density: float
    influence: Influence = "constant"
    viscoelastic: Any = None
    plasticity: Any = None

    def __post_init__(self) -> None:
        moduli.check_isotropic_constants(
            self.youngs_modulus, self.poisson_ratio, self.density, "LPS"
        )
        if self.viscoelastic is not None and self.plasticity is not None:
            raise ValueError(
                "material.viscoelastic and material.plasticity do not combine; give one"
            )
        if self.influence not in INFLUENCES:
            raise ValueError(
                f"material.influence must be one of {INFLUENCES}, got {self.influence!r}"
            )

    # -- moduli -------------------------------------------------------------------------
    @property
    def bulk_modulus(self) -> float:
        """3-D bulk modulus K = E / (3 (1 - 2 nu)) (Pa)."""
        return moduli.bulk_modulus(self.youngs_modulus, self.poisson_ratio)

    @property
    def shear_modulus(self) -> float:
        """Shear modulus mu = E / (2 (1 + nu)) (Pa)."""
        return moduli.shear_modulus(self.youngs_modulus, self.poisson_ratio)

    def dimensional_bulk_modulus(self, dim: int, plane: str | None) -> float:
        """k_d (Pa): K in 3-D, E / (2 (1 + nu)(1 - 2 nu)) in plane strain,
        E / (2 (1 - nu)) in plane stress."""
        _check_dim(dim, plane)
        return moduli.dimensional_bulk_modulus(self.youngs_modulus, self.poisson_ratio, dim, plane)

    def in_plane_moduli(self, dim: int, plane: str | None) -> tuple[float, float]:
        """(E', nu') of the in-plane uniaxial-stress response (Pa, -): (E, nu) in 3-D and
        plane stress, (E / (1 - nu^2), nu / (1 - nu)) in plane strain."""
        _check_dim(dim, plane)
        return moduli.in_plane_moduli(self.youngs_modulus, self.poisson_ratio, dim, plane)

    def coefficients(self, dim: int, plane: str | None) -> LPSCoefficients:
        """Force-state constants (module docstring): tf, k_theta = A d^2 / tf^2 with
        A = k_d - (d + 2) mu / d, and alpha = d (d + 2) mu."""
        _check_dim(dim, plane)
        nu, mu = self.poisson_ratio, self.shear_modulus
        k_d = self.dimensional_bulk_modulus(dim, plane)
        a_mod = k_d - (dim + 2) * mu / dim
        if dim == 3:
            tf = 3.0
        elif plane == "strain":
            tf = 2.0
        else:
            tf = 2.0 * (1.0 - 2.0 * nu) / (1.0 - nu)
        return LPSCoefficients(
            theta_factor=tf, k_theta=a_mod * dim * dim / (tf * tf), alpha=dim * (dim + 2) * mu
        )

    # -- fracture -----------------------------------------------------------------------
    def critical_stretch(
        self,
        fracture_energy: float,
        dim: int,
        horizon: float,
        cross_section: float = 1.0,
        plane: str | None = None,
    ) -> float:
        """Critical stretch s0 from the fracture energy G0 (J/m^2).

        G0 is the energy, per unit crack area, of the points within delta of a crack
        plane when every bond crossing it has stretch s0 and no other bond is stretched
        (the construction of Silling & Askari 2005, applied to the LPS energy as Madenci
        & Oterkus 2014, "Peridynamic Theory and Its Applications", do for their
        ordinary state-based model):

            G0 = 2 int_0^delta W(z) dz = s0^2 delta (P_b mu + P_theta A),

        ``A = k_d - (d + 2) mu / d``; P_b comes from the ``alpha`` term and P_theta from
        the dilatation of the crossing bonds (table ``_FRACTURE_INTEGRALS``). For
        omega = delta/|xi| the ``mu`` terms are Madenci & Oterkus's exactly (3 mu in 3-D,
        6 mu / pi in 2-D); their dilatation terms, (3/4)^4 (K - 5 mu / 3) and
        16 / (9 pi^2) (k - 2 mu), are approximations of P_theta A (P_theta = 0.578 and
        0.323 here). The bracket is > 0 for every admissible nu (W >= k_d theta_d^2 / 2).
        ``cross_section`` cancels (G0 and W are both per unit thickness in 2-D).
        """
        if not (math.isfinite(fracture_energy) and fracture_energy > 0):
            raise ValueError(
                f"material.fracture_energy must be a finite value > 0 J/m^2, got {fracture_energy}"
            )
        if not horizon > 0:
            raise ValueError(f"horizon must be > 0 m, got {horizon}")
        _check_dim(dim, plane)
        p_b, p_t = _FRACTURE_INTEGRALS[(dim, self.influence)]
        mu = self.shear_modulus
        a_mod = self.dimensional_bulk_modulus(dim, plane) - (dim + 2) * mu / dim
        return math.sqrt(fracture_energy / ((p_b * mu + p_t * a_mod) * horizon))

    # -- waves, contact -----------------------------------------------------------------
    def wave_speed(self) -> float:
        """Bar wave speed sqrt(E / rho) (m/s) (3-D bar, plane-stress strip)."""
        return math.sqrt(self.youngs_modulus / self.density)

    def bar_wave_speed(self, dim: int, plane: str | None) -> float:
        """Long-wave speed of a thin bar / strip, sqrt(E' / rho) (m/s), E' of
        :meth:`in_plane_moduli` (E / (1 - nu^2) in a plane-strain strip)."""
        return math.sqrt(self.in_plane_moduli(dim, plane)[0] / self.density)

    def p_wave_speed(self, dim: int, plane: str | None) -> float:
        """Dilatational (P) wave speed sqrt((k_d + 2 (d - 1) mu / d) / rho) (m/s):
        sqrt((lambda + 2 mu) / rho) in 3-D and plane strain, sqrt((lambda' + 2 mu) / rho)
        in plane stress."""
        m = self.dimensional_bulk_modulus(dim, plane) + 2.0 * (dim - 1) * self.shear_modulus / dim
        return math.sqrt(m / self.density)

    def shear_wave_speed(self) -> float:
        """Shear (S) wave speed sqrt(mu / rho) (m/s)."""
        return math.sqrt(self.shear_modulus / self.density)

    def micromodulus_constant(
        self, dim: int, horizon: float, cross_section: float, plane: str | None
    ) -> float:
        """Constant-profile PMB micromodulus c of the same E (N/m^6),
        :func:`peridynamics.families.moduli.pmb_micromodulus` (contact stiffness,
        viscous rate constants)."""
        return moduli.pmb_micromodulus(self.youngs_modulus, dim, horizon, cross_section, plane)

    # -- model --------------------------------------------------------------------------
    def force_model(
        self, cloud: PointCloud, bonds: Bonds, surface_correction: bool = False
    ) -> LPSForceModel:
        """The :class:`~peridynamics.families.lps.force.LPSForceModel` of this material;
        ``surface_correction=True`` calibrates the influence function of every point
        (:func:`~peridynamics.families.calibration.calibrate_influence`); with
        ``viscoelastic`` the
        :class:`~peridynamics.families.lps.viscoelastic.ViscoelasticLPSModel`; with
        ``plasticity`` the :class:`~peridynamics.families.lps.plastic.PlasticLPSModel`."""
        if self.plasticity is not None:
            return PlasticLPSModel(
                cloud, bonds, self, self.plasticity, surface_correction=surface_correction
            )
        if self.viscoelastic is not None:
            return ViscoelasticLPSModel(
                cloud, bonds, self, self.viscoelastic, surface_correction=surface_correction
            )
        return LPSForceModel(cloud, bonds, self, surface_correction=surface_correction)


def _check_dim(dim: int, plane: str | None) -> None:
    if dim not in (2, 3):
        raise ValueError(
            f"the LPS model is implemented in 2-D and 3-D, got dimension {dim} "
            "(a 1-D bar has no Poisson effect: use the bond-based model)"
        )
    if dim == 2 and plane not in ("stress", "strain"):
        raise ValueError(f"2-D LPS needs plane 'stress' or 'strain', got {plane!r}")
