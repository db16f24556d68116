"""NumPy twins of :mod:`peridynamics.kernels.fatigue` (test oracles): the same
quantities from ``bond_i``, ``bond_j`` with no loop over bonds."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F = NDArray[np.float64]


def fatigue_rates(
    bond_i: NDArray, bond_j: NDArray, stretch: F, intact: NDArray, life: F,
    phase_two: NDArray, can_fail: NDArray, amplitude: float, a1: float, m1: float,
    a2: float, m2: float,
) -> tuple[F, F]:  # fmt: skip
    """(rate A eps^m, cycles to failure lambda / rate) of every directed bond, each
    (n_bonds,); 0 and inf for broken, no-fail or unloaded bonds."""
    eps = amplitude * np.abs(stretch)
    two = (phase_two[bond_i] != 0) | (phase_two[bond_j] != 0)
    live = (intact != 0) & (can_fail[bond_i] != 0) & (can_fail[bond_j] != 0)
    rate = np.where(two, a2 * eps**m2, a1 * eps**m1) * live
    with np.errstate(divide="ignore"):
        cycles = np.where(rate > 0, life / np.where(rate > 0, rate, 1.0), np.inf)
    return rate, cycles


def advance_life(life: F, rate: F, intact: NDArray, dn: float) -> F:
    """The remaining life after ``dn`` cycles (a new array)."""
    return np.where(intact != 0, life - dn * rate, life)
