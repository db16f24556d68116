"""History-dependent (elastic-plastic) laws of the correspondence family.

A law maps the corotated small strain ``e = U - I`` of a point (``F = R U``, the polar
decomposition of the nonlocal deformation gradient; Warren et al. (2009) use the
unrotated rate form of the same idea) and the committed history to the stress ``s`` in
the unrotated frame and the trial history; the force model turns ``s`` into ``P = J R s
U^-1`` (:mod:`~peridynamics.families.correspondence.plastic_force`). With ``strain=
"logarithmic"`` the same return map runs on the Hencky strain ``e = ln U`` and returns
the rotated Kirchhoff stress T, ``P = R T U^-1`` (finite strain; Eterovic & Bathe
(1990)). Elasticity is isotropic and linear in e; equations: docs/theory_plasticity.md.

* :class:`J2Plasticity`: von Mises yield with linear isotropic (``hardening_modulus``)
  and linear kinematic (``kinematic_modulus``) hardening, radial return (Simo & Hughes
  (1998), box 3.2); the uniaxial hardening slope is ``E H / (E + H)``, H the sum of the
  two moduli.
* :class:`DruckerPrager`: perfectly plastic Drucker & Prager (1952) cone fitted to the
  Mohr-Coulomb compressive meridian (de Souza Neto et al. (2008), eq. 6.121), non-
  associated flow through the dilation angle, and a tension cut-off on the mean stress.
* A user law: any object with the :class:`PlasticLaw` protocol (``history_size`` and a
  vectorised ``update``), given in Python (``CorrespondenceMaterial(...,
  plasticity=law)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from peridynamics.kernels import plasticity as kernels
from peridynamics.kernels import reference_plasticity as twins

F64 = NDArray[np.float64]


@runtime_checkable
class PlasticLaw(Protocol):
    """What the correspondence force model asks of a history-dependent law.

    ``history_size`` (int): the history components per point, stored in the State field
    ``plastic_history`` (n, history_size), zero at the start, kept in checkpoints.
    ``update(strain, history, lame, shear)``: strains (n, 3, 3) (corotated small
    strain, symmetric), committed history (n, history_size) and the elastic constants
    (Pa) -> (stress (n, 3, 3) in Pa, the trial history (n, history_size)); vectorised
    over points (NumPy, or a Numba function called on the whole batch), and pure: it
    must not change its arguments. The trial history is committed by the solver on an
    accepted step (every step of explicit dynamics)."""

    history_size: int

    def update(self, strain: F64, history: F64, lame: float, shear: float) -> tuple[F64, F64]: ...


#: ``material.plasticity.strain``: the strain measure of the return map
STRAINS = ("small", "logarithmic")


def check_strain(value: str) -> None:
    """A ValueError naming ``material.plasticity.strain`` unless ``value`` is in
    :data:`STRAINS`."""
    if value not in STRAINS:
        raise ValueError(
            f"material.plasticity.strain must be 'small' (corotated U - I) or 'logarithmic' "
            f"(Hencky ln U, finite strain), got {value!r}"
        )


def _positive(key: str, value: float, zero: bool = False) -> None:
    ok = isinstance(value, int | float) and math.isfinite(value)
    if not ok or value < 0 or (value == 0 and not zero):
        need = ">= 0" if zero else "> 0"
        raise ValueError(f"material.plasticity.{key} must be a finite value {need}, got {value}")


@dataclass(frozen=True)
class J2Plasticity:
    """Von Mises plasticity with linear isotropic and kinematic hardening.

    Parameters
    ----------
    yield_stress : float
        Initial uniaxial yield stress sigma_y (Pa), > 0.
    hardening_modulus : float
        Linear isotropic hardening modulus H_iso (Pa), >= 0: the yield radius is
        ``sqrt(2/3) (sigma_y + H_iso alpha)``, alpha the equivalent plastic strain.
    kinematic_modulus : float
        Linear kinematic hardening modulus H_kin (Pa), >= 0: the back stress grows by
        ``2/3 H_kin d eps_p``.
    strain : {"small", "logarithmic"}
        The strain of the return map: the corotated small strain U - I (stress s, P = J
        R s U^-1), or the Hencky strain ln U (rotated Kirchhoff stress T, P = R T U^-1;
        finite strain, Eterovic & Bathe (1990)).
    """

    yield_stress: float
    hardening_modulus: float = 0.0
    kinematic_modulus: float = 0.0
    strain: str = "small"

    name: ClassVar[str] = "j2"
    law_id: ClassVar[int] = kernels.LAW_J2
    history_size: ClassVar[int] = kernels.J2_HISTORY
    #: the history column of the equivalent plastic strain alpha (read by damage laws)
    plastic_strain_index: ClassVar[int] = kernels.J2_HISTORY - 1

    def __post_init__(self) -> None:
        _positive("yield_stress", self.yield_stress)
        _positive("hardening_modulus", self.hardening_modulus, zero=True)
        _positive("kinematic_modulus", self.kinematic_modulus, zero=True)
        check_strain(self.strain)

    def params(self, lame: float, shear: float) -> F64:
        """The kernel's parameters [lambda, mu, sigma_y, H_iso, H_kin]."""
        return np.array(
            [lame, shear, self.yield_stress, self.hardening_modulus, self.kinematic_modulus]
        )

    def update(self, strain: F64, history: F64, lame: float, shear: float) -> tuple[F64, F64]:
        """:class:`PlasticLaw` (the NumPy twin of the kernel)."""
        return twins.j2_return(strain, history, self.params(lame, shear))


@dataclass(frozen=True)
class DruckerPrager:
    """Perfectly plastic Drucker-Prager cone with non-associated flow and a tension
    cut-off (tension positive; p = tr(sigma)/3).

    Yield ``sqrt(J2) + eta p - xi c <= 0`` and ``p <= T``; plastic potential
    ``sqrt(J2) + eta_bar p``; ``eta = 6 sin(phi) / (sqrt(3) (3 - sin(phi)))``, ``xi = 6
    cos(phi) / (sqrt(3) (3 - sin(phi)))``, eta_bar with the dilation angle psi (the
    cone through the compressive meridian of Mohr-Coulomb).

    Parameters
    ----------
    cohesion : float
        c (Pa), > 0.
    friction_angle : float
        phi (degrees), 0 <= phi < 90.
    dilation_angle : float
        psi (degrees), 0 <= psi <= phi (psi = phi: associated flow).
    tension_cutoff : float or None
        T (Pa), the largest mean stress, 0 <= T <= xi c / eta (the apex of the cone);
        None: the apex (no cut-off beyond the cone).
    strain : {"small", "logarithmic"}
        As :class:`J2Plasticity` (tension positive in T, the rotated Kirchhoff stress).
    """

    cohesion: float
    friction_angle: float
    dilation_angle: float = 0.0
    tension_cutoff: float | None = None
    strain: str = "small"

    name: ClassVar[str] = "drucker_prager"
    law_id: ClassVar[int] = kernels.LAW_DRUCKER_PRAGER
    history_size: ClassVar[int] = kernels.DP_HISTORY
    #: the history column of the equivalent plastic strain alpha (read by damage laws)
    plastic_strain_index: ClassVar[int] = kernels.DP_HISTORY - 1

    def __post_init__(self) -> None:
        _positive("cohesion", self.cohesion)
        check_strain(self.strain)
        for key in ("friction_angle", "dilation_angle"):
            _positive(key, getattr(self, key), zero=True)
        if self.friction_angle >= 90.0:
            raise ValueError(
                f"material.plasticity.friction_angle must be below 90 degrees, got "
                f"{self.friction_angle}"
            )
        if self.dilation_angle > self.friction_angle:
            raise ValueError(
                f"material.plasticity.dilation_angle ({self.dilation_angle}) must not exceed "
                f"friction_angle ({self.friction_angle}): the flow would dissipate negatively"
            )
        if self.tension_cutoff is not None:
            _positive("tension_cutoff", self.tension_cutoff, zero=True)
            if self.tension_cutoff > self.apex:
                raise ValueError(
                    f"material.plasticity.tension_cutoff ({self.tension_cutoff} Pa) lies "
                    f"beyond the apex of the cone ({self.apex:.6g} Pa); give a value up to "
                    "it or omit the key"
                )

    @staticmethod
    def _eta(angle: float) -> float:
        s = math.sin(math.radians(angle))
        return 6.0 * s / (math.sqrt(3.0) * (3.0 - s))

    @property
    def eta(self) -> float:
        """eta of the yield function (friction angle)."""
        return self._eta(self.friction_angle)

    @property
    def eta_bar(self) -> float:
        """eta_bar of the plastic potential (dilation angle)."""
        return self._eta(self.dilation_angle)

    @property
    def xi(self) -> float:
        """xi of the yield function."""
        s = math.sin(math.radians(self.friction_angle))
        return 6.0 * math.cos(math.radians(self.friction_angle)) / (math.sqrt(3.0) * (3.0 - s))

    @property
    def apex(self) -> float:
        """Mean stress of the apex xi c / eta (Pa); inf when phi = 0."""
        return self.xi * self.cohesion / self.eta if self.eta > 0 else math.inf

    @property
    def cutoff(self) -> float:
        """T (Pa): ``tension_cutoff`` or the apex."""
        return self.apex if self.tension_cutoff is None else float(self.tension_cutoff)

    def uniaxial_strengths(self) -> tuple[float, float]:
        """(tensile, compressive) uniaxial yield stress (Pa, both > 0)."""
        xic = self.xi * self.cohesion
        tension = min(xic / (1.0 / math.sqrt(3.0) + self.eta / 3.0), 3.0 * self.cutoff)
        return tension, xic / (1.0 / math.sqrt(3.0) - self.eta / 3.0)

    def params(self, lame: float, shear: float) -> F64:
        """The kernel's parameters [lambda, mu, eta, eta_bar, xi c, T]."""
        cut = min(self.cutoff, 1e300)
        return np.array([lame, shear, self.eta, self.eta_bar, self.xi * self.cohesion, cut])

    def update(self, strain: F64, history: F64, lame: float, shear: float) -> tuple[F64, F64]:
        """:class:`PlasticLaw` (the NumPy twin of the kernel)."""
        return twins.dp_return(strain, history, self.params(lame, shear))


#: deck name -> law class
PLASTIC_LAWS: dict[str, type] = {"j2": J2Plasticity, "drucker_prager": DruckerPrager}


def plastic_law(spec: Any) -> Any:
    """The law of a deck's ``material.plasticity`` section (None: elastic)."""
    if spec is None:
        return None
    fields = {k: v for k, v in spec.model_dump().items() if k != "type"}
    return PLASTIC_LAWS[spec.type](**fields)
