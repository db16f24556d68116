"""Bond failure of correspondence models: critical stretch, maximum principal stress,
and degenerate families.

PD zero-energy modes (n.d.), eqs 7-11: a bond breaks for good when its stretch
reaches the critical stretch s_c, or when the average of the largest principal Cauchy
stresses of its two points reaches the tensile strength f_t,
``(sigma_1(x) + sigma_1(x')) / 2 >= f_t`` (either criterion or both). A point whose
family becomes degenerate (``degenerate_families`` of the force model,
:data:`peridynamics.families.correspondence.force.DEGENERATE_RATIO`) when the proposed
bonds break has no deformation gradient left: its remaining bonds
break in the same proposal, so that the point is fully damaged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.damage.critical_stretch import CriticalStretch, CriticalStretchLaw

if TYPE_CHECKING:
    from peridynamics.state import State


class StressModel(Protocol):
    """The capability the law asks of its force model (the correspondence family
    provides it): principal stresses and the degenerate-family test."""

    det_reference: NDArray[np.float64]

    def max_principal_stress(
        self, u: NDArray[np.float64], intact: NDArray[np.uint8]
    ) -> NDArray[np.float64]: ...

    def degenerate_families(
        self, intact: NDArray[np.uint8], det: NDArray[np.float64]
    ) -> NDArray[np.bool_]: ...


#: rounds of degenerate-family propagation per proposal (each round breaks the bonds of
#: the points that the previous round made degenerate)
_DEGENERATE_ROUNDS = 8


@dataclass(frozen=True)
class CorrespondenceFailure:
    """Failure criteria of a correspondence model.

    Parameters
    ----------
    stretch : CriticalStretch
        The critical-stretch criterion (``critical_stretch = inf``: off); its no-fail
        points also keep every stress-failing bond.
    tensile_strength : float
        f_t (Pa) of the maximum-principal-stress criterion, ``inf``: off.
    """

    stretch: CriticalStretch
    tensile_strength: float = math.inf

    def __post_init__(self) -> None:
        if not self.tensile_strength > 0 or math.isnan(self.tensile_strength):
            raise ValueError(f"damage.tensile_strength must be > 0 Pa, got {self.tensile_strength}")

    def law(
        self, x: NDArray[np.float64], bonds: Bonds, global_ids: NDArray[np.int64] | None = None
    ) -> CorrespondenceFailureLaw:
        """This criterion bound to a model's points and bonds; the model binds its force
        model with :meth:`CorrespondenceFailureLaw.bind`."""
        return CorrespondenceFailureLaw(self, x, bonds, global_ids)


class CorrespondenceFailureLaw(CriticalStretchLaw):
    """Trial and commit of :class:`CorrespondenceFailure` (see the module docstring).

    ``point_s0`` and ``family_s0_min`` are those of the critical-stretch part (inf where
    it is off), so the model's critical-stretch attributes keep working.
    """

    name = "correspondence_failure"

    def __init__(
        self,
        failure: CorrespondenceFailure,
        x: NDArray[np.float64],
        bonds: Bonds,
        global_ids: NDArray[np.int64] | None = None,
    ) -> None:
        super().__init__(failure.stretch, x, bonds, global_ids)
        self.failure = failure
        self.tensile_strength = float(failure.tensile_strength)
        self.force_model: StressModel | None = None
        keep = np.zeros(len(bonds.offsets) - 1, dtype=bool)
        if failure.stretch.no_fail is not None and len(failure.stretch.no_fail):
            keep[np.asarray(failure.stretch.no_fail)] = True
        self._bi = bonds.bond_i.astype(np.intp)
        self._bj = bonds.bond_j.astype(np.intp)
        # serial bond lists: every far point is owned (a distributed run would need the
        # ghosts' stresses and flags exchanged first)
        self.protected = keep[self._bi] | keep[self._bj]
        self.last_stress: NDArray[np.float64] | None = None

    def bind(self, force_model: Any) -> None:
        """Attach the force model whose stresses and shape tensors the law reads (one
        with the :class:`StressModel` capability, as the correspondence family)."""
        self.force_model = force_model

    @property
    def active(self) -> bool:
        return bool(np.isfinite(self.point_s0).any() or math.isfinite(self.tensile_strength))

    def trial(self, state: State) -> int:
        fm = self.force_model
        if fm is None:
            raise RuntimeError("CorrespondenceFailureLaw.bind(force_model) was not called")
        if not self.active:
            self._count = 0
            return 0
        proposed = self._proposed.view(bool)
        if np.isfinite(self.point_s0).any():
            super().trial(state)  # fills self._proposed with the stretch failures
        else:
            proposed[:] = False
        intact = state.intact.view(bool)
        if math.isfinite(self.tensile_strength):
            s1 = fm.max_principal_stress(state.u, state.intact)
            self.last_stress = s1
            mean = 0.5 * (s1[self._bi] + s1[self._bj])
            proposed |= intact & (mean >= self.tensile_strength) & ~self.protected
        if proposed.any():
            self._add_degenerate(state, proposed)
        self._count = int(np.count_nonzero(proposed))
        return self._count

    def _add_degenerate(self, state: State, proposed: NDArray[np.bool_]) -> None:
        """Propose every intact bond of the points that the proposal leaves degenerate."""
        fm = self.force_model
        assert fm is not None
        intact = state.intact.view(bool)
        n = len(fm.det_reference)
        det = np.empty(n)
        for _ in range(_DEGENERATE_ROUNDS):
            after = (intact & ~proposed).view(np.uint8)
            bad = fm.degenerate_families(after, det)
            bad &= np.bincount(self._bi, after, minlength=n) > 0  # still has bonds
            if not bad.any():
                return
            proposed |= intact & (bad[self._bi] | bad[self._bj])
