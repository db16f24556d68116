"""Critical-stretch damage (PMB): a bond breaks for good once s >= s0 (Lu & Wang (2016),
eq. 5).

The bond threshold is the mean of its end points' critical stretch, so per-point
fields (Weibull heterogeneity, "no-fail" zones with s0 = inf) enter symmetrically.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.damage.weibull import WeibullField
from peridynamics.families.base import DamageLaw

if TYPE_CHECKING:
    from peridynamics.state import State


@dataclass(frozen=True)
class CriticalStretch:
    """Brittle bond breaking at a critical stretch.

    Parameters
    ----------
    critical_stretch : float
        s0 (dimensionless, > 0), ``inf`` disables breaking.
    no_fail : (k,) int array, optional
        Points whose bonds never break (any bond touching them is kept).
    weibull : WeibullField, optional
        Per-point heterogeneity: s0_i = s0 x factor_i (SED-PD (2021), eqs 25-26).

    Examples
    --------
    >>> import peridynamics as pd
    >>> pd.CriticalStretch(critical_stretch=0.01).critical_stretch
    0.01
    """

    critical_stretch: float
    no_fail: NDArray[np.intp] | None = None
    weibull: WeibullField | None = None

    def __post_init__(self) -> None:
        if not self.critical_stretch > 0 or math.isnan(self.critical_stretch):
            raise ValueError(f"critical_stretch must be > 0, got {self.critical_stretch}")

    def point_threshold(
        self, n_points: int, global_ids: NDArray[np.int64] | None = None
    ) -> NDArray[np.float64]:
        """Per-point s0, shape (n_points,), inf on no-fail points. Weibull factors are
        drawn by global point id (``arange(n_points)`` when not given)."""
        s0 = np.full(n_points, float(self.critical_stretch))
        if self.weibull is not None:
            s0 = s0 * self.weibull.stretch_factors(n_points, global_ids)
        if self.no_fail is not None and len(self.no_fail):
            s0[np.asarray(self.no_fail)] = np.inf
        return s0

    def law(
        self, x: NDArray[np.float64], bonds: Bonds, global_ids: NDArray[np.int64] | None = None
    ) -> CriticalStretchLaw:
        """This criterion bound to a model's points and bonds (what the evaluator runs)."""
        return CriticalStretchLaw(self, x, bonds, global_ids)


def break_proposed(state: State, proposed: NDArray[np.uint8], count: int) -> int:
    """Break the ``count`` bonds flagged in ``proposed`` (n_bonds,) for good: clear their
    ``state.intact`` and add them to ``state.bonds_broken``; returns ``count``. The
    commit of every law that proposes by a flag per bond."""
    if count:
        state.intact[proposed.view(bool)] = 0
        state.bonds_broken += count
    return count


def family_minimum(bonds: Bonds, s0: NDArray[np.float64]) -> NDArray[np.float64]:
    """Smallest bond threshold (s0_i + s0_j)/2 over each family, shape (n_points,).

    Taken as (s0_i + min_j s0_j)/2 (rounding is monotonic: the same bits), range by
    range of bonds, so no per-bond array is made."""
    from peridynamics.bonds.bonds import setup_chunk_bonds
    from peridynamics.bonds.search import bond_chunks

    offsets = bonds.offsets
    nearest = np.empty(bonds.n_points)
    for a, b in bond_chunks(offsets, setup_chunk_bonds(1, 16)):
        p0 = int(np.searchsorted(offsets, a, side="right")) - 1
        p1 = int(np.searchsorted(offsets, b, side="left"))
        # every family is non-empty, so reduceat sees increasing starts
        nearest[p0:p1] = np.minimum.reduceat(s0[bonds.bond_j[a:b]], offsets[p0:p1] - a)
    return 0.5 * (s0 + nearest)


NO_DAMAGE = CriticalStretch(critical_stretch=math.inf)


class CriticalStretchLaw(DamageLaw):
    """The critical-stretch criterion bound to one model's points and bonds.

    ``trial`` marks the intact bonds whose stretch reaches (s0_i + s0_j)/2 at the
    state's displacement; ``commit`` breaks them for good. An explicit solver commits
    every step; dynamic relaxation and static solvers commit on an accepted load step.

    Parameters
    ----------
    criterion : CriticalStretch
    x : (n, dim) reference positions (m).
    bonds : Bonds
    global_ids : (n,) global point ids, optional
        Random fields (Weibull) are drawn by global id, so a distributed run draws the
        same field as a serial one.
    """

    name = "critical_stretch"

    def __init__(
        self,
        criterion: CriticalStretch,
        x: NDArray[np.float64],
        bonds: Bonds,
        global_ids: NDArray[np.int64] | None = None,
    ) -> None:
        self.criterion = criterion
        self.x = x
        self.bonds = bonds
        n = len(bonds.offsets) - 1
        self.point_s0 = criterion.point_threshold(n, global_ids)
        self.family_s0_min = family_minimum(bonds, self.point_s0)
        self._proposed = np.zeros(bonds.n_bonds, dtype=np.uint8)
        self._counts: NDArray[np.int64] | None = None  # proposals per point (scratch)
        self._count = 0

    @property
    def active(self) -> bool:
        return bool(np.isfinite(self.point_s0).any())

    def stretch_thresholds(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(point_s0, family_s0_min): what a force model's fused step breaks bonds at."""
        return self.point_s0, self.family_s0_min

    def stretch_cap(self) -> float:
        """The largest point s0: a bond's threshold (s0_i + s0_j)/2 is at most that, so
        after a commit no intact bond is stretched beyond it (``inf`` with no-fail points
        or without breaking)."""
        s0 = self.point_s0
        return float(s0.max()) if s0.size else math.inf

    @property
    def proposed(self) -> NDArray[np.uint8]:
        """The last proposal (n_bonds,) uint8."""
        return self._proposed

    def trial(self, state: State) -> int:
        """Propose the intact bonds whose stretch reaches (s0_i + s0_j)/2: the exact test
        of :func:`~peridynamics.kernels.bond_trial.break_trial` on the families a
        vectorised filter finds near breaking
        (:func:`~peridynamics.kernels.bond_trial.break_trial_filtered`, the same
        proposals)."""
        from peridynamics.kernels.bond_trial import break_trial_filtered

        if not self.active:
            self._count = 0
            return 0
        if "thermal_strain" in state:  # thermal expansion: the mechanical stretch
            return self._trial_mechanical(state)
        b = self.bonds
        if self._counts is None:
            self._counts = np.zeros(len(b.offsets) - 1, dtype=np.int64)
        self._count = int(
            break_trial_filtered(
                self.x, state.u, b.offsets, b.bond_j, state.intact, self.point_s0,
                self.family_s0_min, self._proposed, self._counts,
            )
        )  # fmt: skip
        return self._count

    def _trial_mechanical(self, state: State) -> int:
        """The trial on the mechanical stretch ``s - (eps_i + eps_j)/2`` of a force model
        with thermal expansion (State field ``thermal_strain``; docs/theory_thermal.md)."""
        from peridynamics.kernels.thermal_expansion import mechanical_stretch

        b = self.bonds
        s = np.empty(b.n_bonds)
        mechanical_stretch(self.x, state.u, b.offsets, b.bond_j, state["thermal_strain"], s)
        s0 = self.point_s0
        hit = (state.intact > 0) & (s >= 0.5 * (s0[b.bond_i] + s0[b.bond_j]))
        self._proposed[:] = hit
        self._count = int(np.count_nonzero(hit))
        return self._count

    def commit(self, state: State) -> int:
        n, self._count = break_proposed(state, self._proposed, self._count), 0
        return n
