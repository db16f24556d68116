"""Bond failure of elastic-plastic correspondence models at a critical equivalent
plastic strain, with the critical stretch and principal-stress criteria.

A point whose equivalent plastic strain alpha (the accumulated ``sqrt(2/3) |d eps_p|``
of the law, docs/theory_plasticity.md) reaches the critical value alpha_c loses all its
bonds: a bond (i, j) breaks when ``max(alpha_i, alpha_j) >= alpha_c`` (a ductile
failure strain, Johnson & Cook (1985), eq. 1 with constant D1, D2 = D3 = D4 = D5 = 0).
The critical stretch and the tensile strength of
:class:`~peridynamics.damage.principal_stress.CorrespondenceFailure` may be given as
well (a bond breaks at whichever comes first), and a point left with a degenerate family
loses its remaining bonds in the same proposal.

alpha is read from the trial history of the force model's last evaluation (State field
``plastic_history_trial``, the column the law names as ``plastic_strain_index``): on an
accepted load step of dynamic relaxation or of the static solver that is the return map
at the converged displacement; in explicit dynamics, where the law runs before the
step's force pass, that of the previous step (one step late, as the committed history).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.damage.critical_stretch import CriticalStretch
from peridynamics.damage.principal_stress import CorrespondenceFailure, CorrespondenceFailureLaw

if TYPE_CHECKING:
    from peridynamics.state import State

#: the State field of the trial plastic history (plastic_force.TRIAL)
TRIAL_HISTORY = "plastic_history_trial"


@dataclass(frozen=True)
class PlasticStrainFailure:
    """Failure at a critical equivalent plastic strain (with optional stretch and stress
    criteria).

    Parameters
    ----------
    critical_plastic_strain : float
        alpha_c (dimensionless, > 0).
    stretch : CriticalStretch
        The critical-stretch criterion (``inf``: off, the default); its no-fail points
        keep every bond, whatever their plastic strain.
    tensile_strength : float
        f_t (Pa) of the maximum-principal-stress criterion, ``inf``: off.
    """

    critical_plastic_strain: float
    stretch: CriticalStretch = field(default_factory=lambda: CriticalStretch(math.inf))
    tensile_strength: float = math.inf

    def __post_init__(self) -> None:
        a = self.critical_plastic_strain
        if not (isinstance(a, int | float) and math.isfinite(a) and a > 0):
            raise ValueError(f"damage.critical_plastic_strain must be a finite value > 0, got {a}")

    def law(
        self, x: NDArray[np.float64], bonds: Bonds, global_ids: NDArray[np.int64] | None = None
    ) -> PlasticStrainLaw:
        """This criterion bound to a model's points and bonds; the evaluator binds the
        force model with :meth:`PlasticStrainLaw.bind`."""
        return PlasticStrainLaw(self, x, bonds, global_ids)


def plastic_strain_proposal(
    alpha: NDArray[np.float64],
    critical: float,
    bond_i: NDArray[np.intp],
    bond_j: NDArray[np.intp],
    intact: NDArray[np.bool_],
    protected: NDArray[np.bool_],
) -> NDArray[np.bool_]:
    """The intact, unprotected bonds with an end point at ``alpha >= critical``.

    Parameters
    ----------
    alpha : (n,) equivalent plastic strain per point.
    critical : alpha_c.
    bond_i, bond_j : (n_bonds,) end points of each directed bond.
    intact : (n_bonds,) bool, the bonds not yet broken.
    protected : (n_bonds,) bool, bonds that never break (a no-fail end point).

    Returns
    -------
    (n_bonds,) bool: the proposal.
    """
    hit = alpha >= critical
    return intact & (hit[bond_i] | hit[bond_j]) & ~protected


class PlasticStrainLaw(CorrespondenceFailureLaw):
    """Trial and commit of :class:`PlasticStrainFailure` (see the module docstring)."""

    name = "plastic_strain"

    def __init__(
        self,
        failure: PlasticStrainFailure,
        x: NDArray[np.float64],
        bonds: Bonds,
        global_ids: NDArray[np.int64] | None = None,
    ) -> None:
        base = CorrespondenceFailure(failure.stretch, failure.tensile_strength)
        super().__init__(base, x, bonds, global_ids)
        self.critical_plastic_strain = float(failure.critical_plastic_strain)
        self.column: int | None = None
        #: alpha per point read by the last trial (n,)
        self.last_alpha: NDArray[np.float64] | None = None

    def bind(self, force_model: Any) -> None:
        """Attach the force model: an elastic-plastic one whose law names the history
        column of alpha (``plastic_strain_index``); ValueError otherwise."""
        law = getattr(force_model, "plasticity", None)
        column = getattr(law, "plastic_strain_index", None)
        if not isinstance(column, int):
            raise ValueError(
                "damage.model 'plastic_strain' reads the equivalent plastic strain of "
                "material.plasticity (j2 or drucker_prager, or a law with a "
                "plastic_strain_index); give material.plasticity or use critical_stretch"
            )
        super().bind(force_model)
        self.column = column

    @property
    def active(self) -> bool:
        return True

    def alpha(self, state: State) -> NDArray[np.float64]:
        """Equivalent plastic strain per point (n,) of the last evaluation's trial
        history (zero before any evaluation)."""
        if self.column is None:
            raise RuntimeError("PlasticStrainLaw.bind(force_model) was not called")
        n = len(self.bonds.offsets) - 1
        if TRIAL_HISTORY not in state:
            return np.zeros(n)
        return np.asarray(state[TRIAL_HISTORY][:n, self.column])

    def trial(self, state: State) -> int:
        super().trial(state)  # stretch, stress and the degenerate families they leave
        proposed = self._proposed.view(bool)
        alpha = self.alpha(state)
        self.last_alpha = alpha
        extra = plastic_strain_proposal(
            alpha, self.critical_plastic_strain, self._bi, self._bj,
            state.intact.view(bool) & ~proposed, self.protected,
        )  # fmt: skip
        if extra.any():
            proposed |= extra
            self._add_degenerate(state, proposed)
        self._count = int(np.count_nonzero(proposed))
        return self._count
