"""Tension-softening bond laws for bond-based PMB: bilinear and trilinear (Petersson 1981).

A bond follows the linear PMB law f = c s up to its strength s0 = f_t / E, then softens
linearly to zero force at s_f (bilinear), or in two linear pieces through the knee
(s1, beta s0) with s1 = s0 + r (s_f - s0) (trilinear; Petersson's concrete curve has
r = w1/w_c = 0.8/3.6 = 2/9 and beta = sigma1/f_t = 1/3). Unloading and reloading follow
the secant to the origin, compression keeps the full stiffness, and a bond whose
largest stretch reached kappa reaches s_f breaks for good.

s0 is a material strength and does not depend on the horizon delta. s_f is chosen so
that breaking one bond costs the same energy as the brittle PMB bond of the critical
stretch s_c that the fracture energy G0 gives at this horizon
(:meth:`~peridynamics.materials.bond_based.BondBasedMaterial.critical_stretch`):
int_0^s_f g(s) ds = s_c^2 / 2, i.e.

* bilinear:  s0 s_f / 2 = s_c^2 / 2                        -> s_f = s_c^2 / s0
* trilinear: s0^2/2 + s0 (s_f - s0)(r + beta)/2 = s_c^2/2   -> s_f = s0 + (s_c^2/s0 - s0)/(r + beta)

so G0 is conserved whatever delta (docs/theory_bond_based.md, "Tension softening").
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.geometry.cloud import PointCloud
from peridynamics.models.base import DamageLaw
from peridynamics.models.pmb_softening import KAPPA, PMBSofteningForceModel

if TYPE_CHECKING:
    from peridynamics.models.base import ForceModel
    from peridynamics.state import State

#: Petersson's (1981) trilinear concrete curve: knee at w1/w_c = 0.8/3.6, sigma1 = f_t/3
PETERSSON_KNEE = (2.0 / 9.0, 1.0 / 3.0)
#: the bilinear law is the trilinear one with its knee on the straight line
BILINEAR_KNEE = (0.5, 0.5)

SofteningLawName = Literal["bilinear", "trilinear"]


@dataclass(frozen=True)
class SofteningEnvelope:
    """The softening envelope of a bond (stretch units: force = c g(s)).

    Parameters
    ----------
    s0 : float
        Peak stretch f_t / E (dimensionless).
    s_c : float
        Critical stretch of the brittle bond with the same fracture energy.
    s_f : float
        Stretch at which the bond carries nothing (> s0).
    r, beta : float
        Knee: s1 = s0 + r (s_f - s0), g(s1) = beta s0 (0 < r, beta < 1).
    """

    s0: float
    s_c: float
    s_f: float
    r: float
    beta: float

    @property
    def s1(self) -> float:
        """Stretch of the knee."""
        return self.s0 + self.r * (self.s_f - self.s0)

    def g(self, s: NDArray[np.float64] | float) -> NDArray[np.float64]:
        """Envelope g(s), shape like ``s`` (s >= 0)."""
        from peridynamics.kernels.reference_softening import envelope

        return envelope(np.asarray(s, dtype=np.float64), self.s0, self.s_f, self.r, self.beta)

    def work(self) -> float:
        """int_0^s_f g(s) ds (exact for the piecewise-linear envelope) = s_c^2 / 2."""
        s0, s1, sf, b = self.s0, self.s1, self.s_f, self.beta
        return 0.5 * s0 * s0 + 0.5 * (s1 - s0) * (s0 + b * s0) + 0.5 * (sf - s1) * b * s0


def _check_unit(name: str, value: float) -> None:
    if not (math.isfinite(value) and 0.0 < value < 1.0):
        raise ValueError(f"damage.trilinear_knee: {name} must be in (0, 1), got {value}")


@dataclass(frozen=True)
class SofteningBonds:
    """Tension-softening bond law (parameters, as from the deck).

    Parameters
    ----------
    bond_law : {"bilinear", "trilinear"}
        Shape of the envelope (the deck's ``damage.bond_law``).
    tensile_strength : float
        f_t (Pa): the bond strength is s0 = f_t / E.
    fracture_energy : float
        G0 (J/m^2): fixes the failure stretch s_f (module docstring).
    knee : (r, beta), optional
        Trilinear knee (default Petersson's (2/9, 1/3)); not used by ``bilinear``.
    no_fail : (k,) int array, optional
        Points whose bonds never soften nor break.
    """

    bond_law: SofteningLawName
    tensile_strength: float
    fracture_energy: float
    knee: tuple[float, float] | None = None
    no_fail: NDArray[np.intp] | None = None

    def __post_init__(self) -> None:
        if self.bond_law not in ("bilinear", "trilinear"):
            raise ValueError(
                f"damage.bond_law: unknown softening law {self.bond_law!r}; use bilinear or "
                "trilinear"
            )
        for key, v in (
            ("tensile_strength", self.tensile_strength),
            ("fracture_energy", self.fracture_energy),
        ):
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"damage.{key} must be a finite value > 0, got {v}")
        if self.knee is not None:
            if self.bond_law != "trilinear":
                raise ValueError("damage.trilinear_knee is only used by bond_law trilinear")
            if len(self.knee) != 2:
                raise ValueError(f"damage.trilinear_knee takes [r, beta], got {self.knee}")
            _check_unit("r", self.knee[0])
            _check_unit("beta", self.knee[1])

    def knee_point(self) -> tuple[float, float]:
        """(r, beta) of the law."""
        if self.bond_law == "bilinear":
            return BILINEAR_KNEE
        return PETERSSON_KNEE if self.knee is None else (float(self.knee[0]), float(self.knee[1]))

    def envelope(
        self,
        material: object,
        dim: int,
        horizon: float,
        cross_section: float,
        plane: str | None,
    ) -> SofteningEnvelope:
        """The envelope for ``material`` (a BondBasedMaterial) at this horizon (m).

        Raises ValueError when the brittle critical stretch s_c of G0 at this horizon
        does not exceed s0 = f_t / E: the bond could not reach f_t with that energy."""
        youngs = getattr(material, "youngs_modulus", None)
        critical = getattr(material, "critical_stretch", None)
        if youngs is None or critical is None:
            raise ValueError(
                "damage.bond_law: softening bond laws are for bond-based material.model "
                f"pmb / bond_based (got {type(material).__name__})"
            )
        s0 = self.tensile_strength / youngs
        s_c = float(critical(self.fracture_energy, dim, horizon, cross_section, plane))
        if not s_c > s0:
            raise ValueError(
                f"damage.fracture_energy G0 = {self.fracture_energy:g} J/m^2 gives the "
                f"brittle critical stretch s_c = {s_c:.6g} at horizon {horizon:.6g} m, not "
                "above the bond strength s0 = damage.tensile_strength / E = "
                f"{self.tensile_strength:g} / {youngs:g} = {s0:.6g}: no softening tail is "
                "left. Use a smaller horizon (s_c grows as 1/sqrt(delta)), a lower "
                "tensile_strength, a larger fracture_energy, or bond_law 'brittle'"
            )
        r, beta = self.knee_point()
        s_f = s0 + (s_c * s_c / s0 - s0) / (r + beta)
        return SofteningEnvelope(s0=s0, s_c=s_c, s_f=s_f, r=r, beta=beta)

    def force_model(
        self, material: object, cloud: PointCloud, bonds: Bonds, surface_correction: bool = False
    ) -> PMBSofteningForceModel:
        """The PMB force model with this bond law (what ``Model`` builds instead of the
        material's own force model when given this damage object)."""
        from peridynamics.materials.bond_based import BondBasedMaterial

        if not isinstance(material, BondBasedMaterial):
            raise ValueError(
                "damage.bond_law: softening bond laws are for bond-based material.model "
                f"pmb / bond_based (got {type(material).__name__})"
            )
        env = self.envelope(material, cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane)
        return PMBSofteningForceModel(cloud, bonds, material, surface_correction, env, self.no_fail)

    def law(
        self, x: NDArray[np.float64], bonds: Bonds, global_ids: NDArray[np.int64] | None = None
    ) -> BondSofteningLaw:
        """The trial/commit law; ``Model`` binds it to the force model built by
        :meth:`force_model`."""
        return BondSofteningLaw(self, bonds)


class BondSofteningLaw(DamageLaw):
    """Commits the softening history of a :class:`PMBSofteningForceModel`.

    ``trial`` computes kappa' = max(kappa, s) of every intact bond and proposes the bonds
    with kappa' >= s_f; ``commit`` writes kappa' into ``state["bond_kappa"]`` and breaks
    the proposed bonds for good. The explicit evaluator runs both inside the force pass
    (:attr:`fused_model`); dynamic relaxation commits on an accepted load step.
    """

    name = "bond_softening"

    def __init__(self, criterion: SofteningBonds, bonds: Bonds) -> None:
        self.criterion = criterion
        self.bonds = bonds
        self.model: PMBSofteningForceModel | None = None
        self._kappa = np.zeros(bonds.n_bonds)
        self._proposed = np.zeros(bonds.n_bonds, dtype=np.uint8)
        self._count = 0
        self._ready = False
        self._active = False

    def bind(self, force_model: ForceModel) -> None:
        """Attach the force model whose per-point s0, s_f the law reads."""
        if not isinstance(force_model, PMBSofteningForceModel):
            raise ValueError(
                "damage.bond_law: a softening bond law needs its own force model "
                "(Model builds it from SofteningBonds.force_model)"
            )
        self.model = force_model
        b, sf = self.bonds, force_model.point_sf
        self._active = bool(np.isfinite(sf[b.bond_i] + sf[b.bond_j]).any())

    @property
    def fused_model(self) -> PMBSofteningForceModel | None:
        """The force model whose ``force_and_commit`` runs this law's trial and commit
        inside the force pass (the explicit evaluator's fast path)."""
        return self.model if self.active else None

    @property
    def active(self) -> bool:
        """False when no bond can fail (unbound, or every bond touches a no-fail point)."""
        return self._active

    def _bound(self) -> PMBSofteningForceModel:
        if self.model is None:
            raise RuntimeError("BondSofteningLaw is not bound to a force model (use Model)")
        return self.model

    def trial(self, state: State) -> int:
        """Trial history and the bonds that fail at ``state.u``; returns how many fail."""
        self._count = self._bound().trial(state, self._kappa, self._proposed)
        self._ready = True
        return self._count

    def commit(self, state: State) -> int:
        """Write the trial history and break the proposed bonds; returns how many."""
        if not self._ready:
            return 0
        np.copyto(state[KAPPA], self._kappa)
        n, self._count, self._ready = self._count, 0, False
        if n:
            state.intact[self._proposed.view(bool)] = 0
            state.bonds_broken += n
        return n
