"""The energy release rate from the energy of broken bonds.

A brittle bond-based bond (PMB with a critical stretch) stores the energy
w_k = 1/4 c_k V_j s_k^2 |xi_k| V_i at each end when it breaks at its threshold s_k
(``PMBForceModel.energy_density`` per directed bond, times the point's volume); that
energy is lost with the bond. The energy of every bond broken during a run, against the
crack length (2-D, times the thickness) or area (3-D) the package measures from the
same bonds (:mod:`peridynamics.analysis.crack_length`), gives an energy release rate
G = dE_broken/dA. Where a crack runs as one clean surface, G equals the fracture energy
G0 the critical stretch was calibrated with (Silling & Askari (2005) in 3-D, Ha & Bobaru
(2010) in 2-D): the calibration integrates the energy of the bonds that cross a unit
area of a plane, each at its critical stretch, over continuous families. A crack that breaks bonds
in a band wider than one surface (microbranching, a rough path) dissipates more, and
G/G0 measures how much more. docs/stress.md, "Energy release rate from broken bonds".
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["broken_bond_energy", "energy_release_rate", "supports_broken_bond_energy"]


def supports_broken_bond_energy(model: Any) -> bool:
    """Whether ``model`` (an :class:`~peridynamics.evaluation.evaluator.Evaluator`) has a broken
    bond energy: a PMB force model (no SED softening, no several bodies) with the
    critical-stretch law, whose bonds are linear up to breaking."""
    fm, law = model.force_model, model.damage_law
    return (
        getattr(fm, "name", None) == "pmb"
        and getattr(model, "softening", None) is None
        and hasattr(fm, "stiffness")
        and getattr(law, "stretch_thresholds", lambda: None)() is not None
        and getattr(model, "rigid", None) is None
        and not getattr(fm, "interfaces", ())
    )


def broken_bond_energy(
    model: Any, intact: NDArray[np.uint8], owned_bonds: int | None = None
) -> float:
    """Energy (J) the bonds broken during the run stored at their critical stretch.

    Parameters
    ----------
    model : Evaluator
        With a PMB force model and a critical-stretch law
        (:func:`supports_broken_bond_energy`).
    intact : (n_bonds,) uint8
        The bond flags of the state; bonds already broken in the reference state
        (pre-cracks, ``bonds.bond_intact == 0``) are left out.
    owned_bonds : int, optional
        Count only the first ``owned_bonds`` bonds (a rank's owned families).

    Returns
    -------
    float
        sum over broken directed bonds k = (i, j) of 1/4 c_k s_k^2 |xi_k| V_i, with
        c_k the bond's stiffness (N/m^6 times V_j, as the force model holds it) and
        s_k = (s0_i + s0_j)/2 its threshold.
    """
    fm, b = model.force_model, model.bonds
    end = b.n_bonds if owned_bonds is None else owned_bonds
    broken = np.flatnonzero((b.bond_intact[:end] != 0) & (intact[:end] == 0))
    if broken.size == 0:
        return 0.0
    point_s0, _ = model.damage_law.stretch_thresholds()
    i, j = b.bond_i[broken], b.bond_j[broken]
    s_star = 0.5 * (point_s0[i] + point_s0[j])
    length = np.linalg.norm(b.bond_xi[broken], axis=1)
    stiffness = np.asarray(fm.stiffness, dtype=np.float64)[broken]
    volume = model.cloud.volume[i]
    return float(np.sum(0.25 * stiffness * s_star**2 * length * volume))


def energy_release_rate(
    energy: NDArray[np.float64],
    crack: NDArray[np.float64],
    thickness: float = 1.0,
    start: float = 0.1,
    stop: float = 1.0,
) -> float:
    """G (J/m^2): the least-squares slope of the broken-bond energy against the crack
    area over the records where the crack grows.

    Parameters
    ----------
    energy : (k,) float
        Broken-bond energy at the records (J).
    crack : (k,) float
        Crack length (2-D, m) or area (3-D, m^2) at the same records.
    thickness : float
        2-D thickness (m), turning a length into an area; 1 in 3-D.
    start, stop : float
        The records used: those whose crack is between ``start`` and ``stop`` times the
        final crack (0.1 and 1 leave out the initiation, where a few broken bonds ahead of
        a notch make no length yet).

    Returns
    -------
    float
        dE/dA (J/m^2); ``nan`` with fewer than two records in the window or no growth.
    """
    e, a = np.asarray(energy, dtype=float), np.asarray(crack, dtype=float) * thickness
    if a.size < 2 or not a[-1] > 0:
        return float("nan")
    keep = (a >= start * a[-1]) & (a <= stop * a[-1])
    if np.count_nonzero(keep) < 2 or np.ptp(a[keep]) <= 0:
        return float("nan")
    slope = np.polyfit(a[keep], e[keep], 1)[0]
    return float(slope)
