"""Correspondence (non-ordinary state-based) material: elastic moduli, the constitutive
law and the zero-energy-mode control.

A correspondence material maps the nonlocal deformation gradient F of a point
(Silling et al. 2007, section 15) through a classical constitutive law to the first
Piola-Kirchhoff stress P; the force state is ``omega P K^-1 xi``
(:mod:`peridynamics.families.correspondence.force`). The laws here are hyperelastic, so every
variant of the model has a potential energy:

* ``st_venant_kirchhoff`` (default): Green strain ``E = (F^T F - I) / 2``,
  ``S = lambda' tr(E) I + 2 mu E``, ``P = F S``, ``W = lambda' tr(E)^2 / 2 + mu E:E``
  (PD zero-energy modes (n.d.), eqs 4-5);
* ``linear_elastic``: small strain ``eps = sym(F - I)``, ``P = sigma = lambda' tr(eps) I
  + 2 mu eps``, ``W = lambda' tr(eps)^2 / 2 + mu eps:eps``.

``lambda'`` is the Lame constant of the idealisation: 3-D and plane strain
``E nu / ((1 + nu)(1 - 2 nu))``, plane stress ``E nu / (1 - nu^2)`` (the out-of-plane
stress is zero); ``mu = E / (2 (1 + nu))``.

The interface (:class:`ConstitutiveLaw`) takes a batch of deformation gradients and
returns stresses; a law with history (plasticity) would add history fields and an
update on commit, without changing the model.

Zero-energy-mode control (``stabilization``):

* ``none``: the plain correspondence force state;
* ``silling2017``: Silling (2017), the bond-based penalty ``(G C / omega_0) omega z`` on
  the non-uniform part ``z = Y - F xi`` of the deformation (PD zero-energy modes
  (n.d.), eq. 16), with ``C = c / delta`` the bond-based micromodulus divided by the
  horizon (N/m^7) and ``omega_0 = sum omega V`` (m^3). G has the units of a volume;
  here it is given as the dimensionless ``stabilization_g = G / V_delta`` with
  ``V_delta`` the volume of the full horizon (pi delta^2 t in 2-D, 4 pi delta^3 / 3 in
  3-D), so that in the bulk (omega_0 = V_delta) the penalty is ``g C omega z``;
  default g = 1 (the penalty stiffness C = c/delta of a bond of length delta);
* ``lbscmm`` (default): the parameter-free linearised-bond stabilisation of PD
  zero-energy modes (n.d.), eqs 17-25, with the bond-based micromodulus
  ``c = 18 K / (pi delta^4)`` (3-D) and ``12 kappa / (pi t delta^3)`` (2-D, kappa the
  2-D bulk modulus ``lambda' + mu``).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.families import moduli
from peridynamics.families.correspondence.force import CorrespondenceForceModel
from peridynamics.families.correspondence.plastic_force import PlasticCorrespondenceModel
from peridynamics.geometry.cloud import PointCloud

Stabilization = Literal["none", "silling2017", "lbscmm"]
STABILIZATIONS: tuple[str, ...] = ("none", "silling2017", "lbscmm")
LAWS: tuple[str, ...] = ("st_venant_kirchhoff", "linear_elastic")


class ConstitutiveLaw(ABC):
    """A hyperelastic stress law evaluated on a batch of deformation gradients.

    Parameters
    ----------
    lame : float
        lambda' (Pa) of the idealisation (plane stress: E nu / (1 - nu^2)).
    shear : float
        mu (Pa).
    """

    name: ClassVar[str] = ""

    def __init__(self, lame: float, shear: float) -> None:
        self.lame = float(lame)
        self.shear = float(shear)

    @abstractmethod
    def strain(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        """Strain tensor, shape (n, d, d), of the deformation gradients f (n, d, d)."""

    @abstractmethod
    def first_piola(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        """First Piola-Kirchhoff stress P = dW/dF (Pa), shape (n, d, d)."""

    def energy_density(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        """W(F) = lambda' tr(E)^2 / 2 + mu E:E (J/m^3), shape (n,)."""
        e = self.strain(f)
        tr = np.trace(e, axis1=1, axis2=2)
        return np.asarray(0.5 * self.lame * tr * tr + self.shear * np.einsum("nab,nab->n", e, e))

    def _stress_of_strain(self, e: NDArray[np.float64]) -> NDArray[np.float64]:
        d = e.shape[1]
        tr = np.trace(e, axis1=1, axis2=2)
        return np.asarray(2.0 * self.shear * e + (self.lame * tr)[:, None, None] * np.eye(d))

    def max_modulus(self, dim: int) -> float:
        """Largest eigenvalue of the elasticity tensor on symmetric tensors (Pa):
        ``eps:C:eps <= max_modulus |eps|^2`` (d lambda' + 2 mu for lambda' >= 0)."""
        return max(dim * self.lame, 0.0) + 2.0 * self.shear


class StVenantKirchhoff(ConstitutiveLaw):
    """S = C:E with the Green strain E = (F^T F - I)/2, P = F S."""

    name = "st_venant_kirchhoff"

    def strain(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        d = f.shape[1]
        return np.asarray(0.5 * (np.einsum("nca,ncb->nab", f, f) - np.eye(d)))

    def first_piola(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(np.einsum("nac,ncb->nab", f, self._stress_of_strain(self.strain(f))))


class LinearElastic(ConstitutiveLaw):
    """sigma = C:eps with eps = sym(F - I); P = sigma (small strain)."""

    name = "linear_elastic"

    def strain(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        d = f.shape[1]
        h = f - np.eye(d)
        return np.asarray(0.5 * (h + np.swapaxes(h, 1, 2)))

    def first_piola(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        return self._stress_of_strain(self.strain(f))


_LAW_CLASSES: dict[str, type[ConstitutiveLaw]] = {
    "st_venant_kirchhoff": StVenantKirchhoff,
    "linear_elastic": LinearElastic,
}


@dataclass(frozen=True)
class CorrespondenceMaterial:
    """Isotropic elastic correspondence material.

    Parameters
    ----------
    youngs_modulus : float
        E (Pa), finite and > 0.
    poisson_ratio : float
        nu, -1 < nu < 0.5.
    density : float
        rho (kg/m^3), finite and > 0.
    stabilization : {"lbscmm", "silling2017", "none"}
        Zero-energy-mode control (module docstring).
    stabilization_g : float
        Silling's G over the horizon volume (dimensionless, > 0); used by
        ``silling2017`` only.
    law : {"st_venant_kirchhoff", "linear_elastic"}
        Constitutive law (elastic; with ``plasticity`` the elastic part is linear in the
        corotated strain and this key is not read).
    plasticity : J2Plasticity, DruckerPrager, a PlasticLaw or None
        A history-dependent law (:mod:`~peridynamics.families.correspondence.plasticity`);
        None: elastic.

    Raises
    ------
    ValueError
        Naming the offending key (``material.poisson_ratio`` ...) and its range.
    """

    youngs_modulus: float
    poisson_ratio: float
    density: float
    stabilization: Stabilization = "lbscmm"
    stabilization_g: float = 0.1
    law: str = "st_venant_kirchhoff"
    plasticity: Any = None

    def __post_init__(self) -> None:
        moduli.check_isotropic_constants(
            self.youngs_modulus, self.poisson_ratio, self.density, "correspondence"
        )
        if self.stabilization not in STABILIZATIONS:
            raise ValueError(
                f"material.stabilization must be one of {list(STABILIZATIONS)}, "
                f"got {self.stabilization!r}"
            )
        g = self.stabilization_g
        if not (isinstance(g, int | float) and math.isfinite(g) and g > 0):
            raise ValueError(f"material.stabilization_g must be a finite value > 0, got {g}")
        if self.law not in LAWS:
            raise ValueError(f"material.law must be one of {list(LAWS)}, got {self.law!r}")

    @property
    def shear_modulus(self) -> float:
        """mu = E / (2 (1 + nu)) (Pa)."""
        return moduli.shear_modulus(self.youngs_modulus, self.poisson_ratio)

    def lame(self, dim: int, plane: str | None) -> float:
        """lambda' (Pa) of the idealisation: plane stress E nu / (1 - nu^2), else
        E nu / ((1 + nu)(1 - 2 nu))."""
        return moduli.lame(self.youngs_modulus, self.poisson_ratio, dim, plane)

    def bulk_modulus(self, dim: int, plane: str | None) -> float:
        """d-dimensional bulk modulus lambda' + 2 mu / d (Pa): K in 3-D, kappa in 2-D."""
        return self.lame(dim, plane) + 2.0 * self.shear_modulus / dim

    def constitutive_law(self, dim: int, plane: str | None) -> ConstitutiveLaw:
        """The stress law of this material in ``dim`` dimensions."""
        return _LAW_CLASSES[self.law](self.lame(dim, plane), self.shear_modulus)

    def micromodulus(self, dim: int, horizon: float, thickness: float, plane: str | None) -> float:
        """Bond-based micromodulus c of the stabilisation (N/m^6): 18 K / (pi delta^4)
        (3-D), 12 kappa / (pi t delta^3) (2-D), PD zero-energy modes (n.d.), eq. 17."""
        k = self.bulk_modulus(dim, plane)
        if dim == 3:
            return 18.0 * k / (math.pi * horizon**4)
        if dim == 2:
            return 12.0 * k / (math.pi * thickness * horizon**3)
        raise ValueError("the correspondence model is 2-D or 3-D")

    def horizon_volume(self, dim: int, horizon: float, thickness: float) -> float:
        """Volume of the full horizon V_delta (m^3): pi delta^2 t or 4 pi delta^3 / 3."""
        if dim == 2:
            return math.pi * horizon**2 * thickness
        return 4.0 * math.pi * horizon**3 / 3.0

    def critical_stretch(
        self,
        fracture_energy: float,
        dim: int,
        horizon: float,
        cross_section: float = 1.0,
        plane: str | None = None,
    ) -> float:
        """Critical stretch s_c from the fracture energy G_c (J/m^2): the ordinary
        state-based form of Madenci & Oterkus (2014), section 4.5, which PD zero-energy
        modes (n.d.), eq. 8, uses:

        * 2-D: ``s_c = sqrt(G_c / ((6 mu / pi + 16 (kappa - 2 mu) / (9 pi^2)) delta))``,
          kappa the 2-D bulk modulus;
        * 3-D: ``s_c = sqrt(G_c / ((3 mu + (3/4)^4 (K - 5 mu / 3)) delta))``.
        """
        if not (math.isfinite(fracture_energy) and fracture_energy > 0):
            raise ValueError(f"damage.fracture_energy must be > 0 J/m^2, got {fracture_energy}")
        mu = self.shear_modulus
        k = self.bulk_modulus(dim, plane)
        if dim == 2:
            denom = 6.0 * mu / math.pi + 16.0 * (k - 2.0 * mu) / (9.0 * math.pi**2)
        elif dim == 3:
            denom = 3.0 * mu + (0.75**4) * (k - 5.0 * mu / 3.0)
        else:
            raise ValueError("the correspondence model is 2-D or 3-D")
        return math.sqrt(fracture_energy / (denom * horizon))

    def micromodulus_constant(
        self, dim: int, horizon: float, cross_section: float, plane: str | None
    ) -> float:
        """The bond-based micromodulus of :meth:`micromodulus` (contact stiffness)."""
        return self.micromodulus(dim, horizon, cross_section, plane)

    def force_model(
        self, cloud: PointCloud, bonds: Bonds, surface_correction: bool = False
    ) -> CorrespondenceForceModel:
        """The correspondence force model on ``cloud`` and ``bonds``. The deformation
        gradient is exact for every affine field at every point, surfaces included, so
        no surface correction is applied (``surface_correction`` is ignored). With
        ``plasticity``: :class:`~.plastic_force.PlasticCorrespondenceModel`."""
        if self.plasticity is not None:
            return PlasticCorrespondenceModel(cloud, bonds, self, self.plasticity)
        return CorrespondenceForceModel(cloud, bonds, self)
