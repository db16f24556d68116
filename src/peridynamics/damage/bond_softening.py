"""Tension-softening bond laws for bond-based PMB: bilinear and trilinear (Petersson 1981).

A bond follows the linear PMB law f = c s up to its strength s0 = f_t / E, then softens
linearly to zero force at s_f (bilinear), or in two linear pieces through the knee
(s1, beta s0) with s1 = s0 + r (s_f - s0) (trilinear; Petersson's concrete curve has
r = w1/w_c = 0.8/3.6 = 2/9 and beta = sigma1/f_t = 1/3). Unloading and reloading follow
the secant to the origin, compression keeps the full stiffness, and a bond whose
largest stretch reached kappa reaches s_f breaks for good.

s0 is a material strength and does not depend on the horizon delta; s_f is chosen so
that breaking one bond costs the energy of the brittle PMB bond of the same fracture
energy G0 (the envelope and its formulas: :mod:`peridynamics.families.pmb_softening`).

Here are the law's parameters (:class:`SofteningBonds`, which names the family that
builds the force model, ``force_family``) and the trial/commit law
(:class:`BondSofteningLaw`), which reads the family's force model through its
capabilities (``kappa_field``, ``point_sf``, ``trial``) without importing it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import DamageLaw, ForceModel

if TYPE_CHECKING:
    from peridynamics.state import State

#: Petersson's (1981) trilinear concrete curve: knee at w1/w_c = 0.8/3.6, sigma1 = f_t/3
PETERSSON_KNEE = (2.0 / 9.0, 1.0 / 3.0)
#: the bilinear law is the trilinear one with its knee on the straight line
BILINEAR_KNEE = (0.5, 0.5)

SofteningLawName = Literal["bilinear", "trilinear"]


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

    #: the model family (registry name) that builds the force model of this law:
    #: :func:`peridynamics.families.pmb_softening.force.softening_force_model`
    force_family: ClassVar[str] = "pmb_softening"

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

    def law(
        self, x: NDArray[np.float64], bonds: Bonds, global_ids: NDArray[np.int64] | None = None
    ) -> BondSofteningLaw:
        """The trial/commit law; ``Evaluator`` binds it to the force model of the family
        :attr:`force_family`."""
        return BondSofteningLaw(self, bonds)


class BondSofteningLaw(DamageLaw):
    """Commits the softening history of a tension-softening PMB force model
    (:class:`~peridynamics.families.pmb_softening.force.PMBSofteningForceModel`).

    ``trial`` computes kappa' = max(kappa, s) of every intact bond and proposes the bonds
    with kappa' >= s_f; ``commit`` writes kappa' into ``state["bond_kappa"]`` and breaks
    the proposed bonds for good. The explicit evaluator runs both inside the force pass
    (:attr:`fused_model`); dynamic relaxation commits on an accepted load step.
    """

    name = "bond_softening"

    def __init__(self, criterion: SofteningBonds, bonds: Bonds) -> None:
        self.criterion = criterion
        self.bonds = bonds
        self.model: Any = None
        self._kappa = np.zeros(bonds.n_bonds)
        self._proposed = np.zeros(bonds.n_bonds, dtype=np.uint8)
        self._count = 0
        self._ready = False
        self._active = False

    def bind(self, force_model: ForceModel) -> None:
        """Attach the force model whose per-point s0, s_f the law reads: one with a
        softening history (``kappa_field``, ``point_sf``, ``trial``)."""
        if getattr(force_model, "kappa_field", None) is None:
            raise ValueError(
                "damage.bond_law: a softening bond law needs its own force model "
                "(Evaluator builds it from the family SofteningBonds.force_family)"
            )
        self.model = force_model
        b, sf = self.bonds, force_model.point_sf  # type: ignore[attr-defined]
        self._active = bool(np.isfinite(sf[b.bond_i] + sf[b.bond_j]).any())

    @property
    def fused_model(self) -> Any:
        """The force model whose ``force_and_commit`` runs this law's trial and commit
        inside the force pass (the explicit evaluator's fast path)."""
        return self.model if self.active else None

    @property
    def active(self) -> bool:
        """False when no bond can fail (unbound, or every bond touches a no-fail point)."""
        return self._active

    @property
    def proposed(self) -> NDArray[np.uint8]:
        """The last proposal (n_bonds,) uint8."""
        return self._proposed

    def _bound(self) -> Any:
        if self.model is None:
            raise RuntimeError("BondSofteningLaw is not bound to a force model (use Evaluator)")
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
        np.copyto(state[self._bound().kappa_field], self._kappa)
        n, self._count, self._ready = self._count, 0, False
        if n:
            state.intact[self._proposed.view(bool)] = 0
            state.bonds_broken += n
        return n
