"""Kernels of the remaining-life fatigue law (Silling & Askari (2014), eqs 1-3): the
cyclic bond strain, the life consumed per cycle and the cycles left to each bond, and
the advance of every bond's remaining life by a cycle jump. NumPy twins:
:mod:`peridynamics.kernels.reference_fatigue`."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

_exact = njit(parallel=True, fastmath=False, cache=True)


@_exact
def fatigue_rates(
    offsets, bond_j, stretch, intact, life, phase_two, can_fail, amplitude, a1, m1, a2, m2,
    rate, cycles,
):  # fmt: skip
    """Life consumed per cycle and cycles to failure of every directed bond.

    Parameters
    ----------
    offsets : (n + 1,) int64
        CSR row starts of the directed bond list.
    bond_j : (n_bonds,) int32
        Far end of each bond.
    stretch : (n_bonds,) float64
        Bond stretch s+ at the peak load.
    intact : (n_bonds,) uint8
    life : (n_bonds,) float64
        Remaining life lambda (1 at the start, the bond breaks at 0).
    phase_two : (n,) uint8
        1 at points whose bonds are in phase II (growth): a bond is in phase II when
        either end point is.
    can_fail : (n,) uint8
        0 at no-fail points: their bonds consume no life.
    amplitude : float
        |1 - R|: the cyclic strain is eps = |1 - R| |s+|.
    a1, m1, a2, m2 : float
        A and m of phase I and phase II.
    rate : (n_bonds,) float64, out
        A eps^m (0 for a broken bond).
    cycles : (n_bonds,) float64, out
        lambda / (A eps^m) (inf for a broken or unloaded bond).
    """
    n = len(offsets) - 1
    for i in prange(n):
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            r = 0.0
            if intact[k] != 0 and can_fail[i] != 0 and can_fail[j] != 0:
                eps = amplitude * abs(stretch[k])
                if phase_two[i] != 0 or phase_two[j] != 0:
                    r = a2 * eps**m2
                else:
                    r = a1 * eps**m1
            rate[k] = r
            cycles[k] = life[k] / r if r > 0.0 else np.inf


@_exact
def advance_life(life, rate, intact, dn):
    """``life -= dn * rate`` on every intact bond (a jump of ``dn`` cycles, in place)."""
    for k in prange(len(life)):
        if intact[k] != 0:
            life[k] -= dn * rate[k]
