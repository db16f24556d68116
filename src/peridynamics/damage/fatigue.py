"""Remaining-life fatigue of bonds (Silling & Askari (2014); Zhang, Jafarzadeh, Silling
et al. (2016)): every bond keeps a remaining life lambda (1 at the start) that each load
cycle lowers by

    d lambda / dN = -A eps^m,   eps = |s+ - s-| = |1 - R| |s+|,

with s+ the bond stretch at the peak load, R the load ratio, and (A, m) = (A1, m1) in
phase I (initiation) or (A2, m2) in phase II (growth); the bond breaks when lambda
reaches 0. A bond is in phase II when either of its end points has a local damage above
``phase_two_damage`` (a crack is in its family). The State field ``fatigue_life`` (per
directed bond) holds lambda, so a checkpoint keeps it. The fatigue solver
(:mod:`peridynamics.solvers.fatigue`) computes the rates at the peak equilibrium,
advances lambda by a cycle jump and breaks the bonds whose life is spent through
``trial`` / ``commit``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.damage.critical_stretch import break_proposed
from peridynamics.families.base import DamageLaw
from peridynamics.kernels.fatigue import advance_life, fatigue_rates

if TYPE_CHECKING:
    from peridynamics.state import State

#: the State field of the remaining life (per directed bond)
LIFE = "fatigue_life"


@dataclass(frozen=True)
class RemainingLife:
    """The fatigue parameters of the bonds.

    Parameters
    ----------
    a1, m1 : float
        Phase I (initiation): A1 (cycles^-1) and m1 (> 0). In a uniform bar in
        uniaxial cycling every bond has the same eps and breaks at N = 1 / (A1 eps^m1):
        the S-N (strain-life) curve of the material.
    a2, m2 : float
        Phase II (growth) near a crack; m2 is the exponent of the Paris law the model
        gives (docs/theory_fatigue.md).
    phase_two_damage : float
        A point whose local damage exceeds this is in phase II, and so is every bond
        at it (0 <= value < 1; 0: any broken bond in the family).
    no_fail : (k,) int array, optional
        Points whose bonds never fail.
    """

    a1: float
    m1: float
    a2: float
    m2: float
    phase_two_damage: float = 0.0
    no_fail: NDArray[np.intp] | None = None

    def __post_init__(self) -> None:
        for name in ("a1", "m1", "a2", "m2"):
            v = getattr(self, name)
            if not (v > 0 and math.isfinite(v)):
                raise ValueError(f"[fatigue.{name.upper()}] must be a finite value > 0, got {v}")
        if not 0.0 <= self.phase_two_damage < 1.0:
            raise ValueError(
                f"[fatigue.phase_two_damage] must be in [0, 1), got {self.phase_two_damage}"
            )

    def cycles_to_failure(self, strain_range: float, phase: int = 1) -> float:
        """N = 1 / (A eps^m) of a bond at the cyclic strain ``strain_range`` from
        lambda = 1 (phase 1 or 2)."""
        a, m = (self.a1, self.m1) if phase == 1 else (self.a2, self.m2)
        return 1.0 / (a * strain_range**m)

    def law(
        self, x: NDArray[np.float64], bonds: Bonds, global_ids: NDArray[np.int64] | None = None
    ) -> RemainingLifeLaw:
        """These parameters bound to a model's points and bonds."""
        return RemainingLifeLaw(self, bonds)


class RemainingLifeLaw(DamageLaw):
    """The remaining-life law bound to one model's bonds.

    ``trial`` proposes the intact bonds whose remaining life is spent (lambda <= 0);
    ``commit`` breaks them. :meth:`rates` and :meth:`advance` are what the fatigue
    solver calls between equilibria.
    """

    name = "fatigue"

    def __init__(self, criterion: RemainingLife, bonds: Bonds) -> None:
        self.criterion = criterion
        self.bonds = bonds
        n = bonds.n_points
        self.can_fail = np.ones(n, dtype=np.uint8)
        if criterion.no_fail is not None and len(criterion.no_fail):
            self.can_fail[np.asarray(criterion.no_fail)] = 0
        self.rate = np.zeros(bonds.n_bonds)
        self.cycles = np.full(bonds.n_bonds, np.inf)
        self._proposed = np.zeros(bonds.n_bonds, dtype=np.uint8)
        self._count = 0

    @property
    def proposed(self) -> NDArray[np.uint8]:
        """The last proposal (n_bonds,) uint8."""
        return self._proposed

    def init_state(self, state: State) -> None:
        """Add ``fatigue_life`` = 1 (per directed bond) to a State that has none."""
        if LIFE not in state:
            state[LIFE] = np.ones(self.bonds.n_bonds)

    def phase_two(self, damage: NDArray[np.float64]) -> NDArray[np.uint8]:
        """Phase-II flag per point (n,) from the local damage (n,)."""
        return (damage > self.criterion.phase_two_damage).astype(np.uint8)

    def rates(
        self,
        state: State,
        stretch: NDArray[np.float64],
        damage: NDArray[np.float64],
        load_ratio: float,
    ) -> float:
        """Compute (and keep) A eps^m and the cycles to failure of every bond at the
        peak stretch ``stretch`` (n_bonds,), with the phases from the local ``damage``
        (n,) and the load ratio R; returns the smallest cycles to failure (inf when no
        intact bond is loaded)."""
        c = self.criterion
        b = self.bonds
        fatigue_rates(
            b.offsets, b.bond_j, stretch, state.intact, state[LIFE], self.phase_two(damage),
            self.can_fail, abs(1.0 - load_ratio), c.a1, c.m1, c.a2, c.m2, self.rate,
            self.cycles,
        )  # fmt: skip
        return float(self.cycles.min(initial=np.inf))

    def advance(self, state: State, dn: float) -> None:
        """Lower every intact bond's life by ``dn`` cycles at the last :meth:`rates`."""
        advance_life(state[LIFE], self.rate, state.intact, float(dn))

    def spend(self, state: State, bonds: NDArray[np.intp]) -> None:
        """Set the life of ``bonds`` to 0 (the batch broken with the first one)."""
        state[LIFE][bonds] = 0.0

    def trial(self, state: State) -> int:
        """Propose the intact bonds whose life is spent (lambda <= 0)."""
        if LIFE not in state:
            self._count = 0
            return 0
        spent = (state[LIFE] <= 0.0) & (state.intact != 0)
        self._proposed[...] = spent
        self._count = int(np.count_nonzero(spent))
        return self._count

    def commit(self, state: State) -> int:
        """Break the proposed bonds."""
        n, self._count = break_proposed(state, self._proposed, self._count), 0
        return n
