"""The breaking events of a double cantilever beam (DCB) solved quasi-statically with
bond breaking between solves, against the LEFM propagation branch
(:func:`peridynamics.analysis.dcb.dcb_lefm_curve`).

A static solve that breaks bonds is followed by a re-solve at the same load level, so
the records of a run hold the whole saw-tooth P-Delta curve: a breaking event is the
first of a run of records at the same load time (its peak, before the bonds break).
The crack length at an event is the pre-crack's a0 plus the tracked path's length;
the events on the *straight part* are those whose ligament (from the crack tip to the
clamp) is longer than three arm heights, where the arms are long beams and the clamp
does not stiffen them (used by ``examples/micropolar/make_figures.py`` and the verify
case ``micropolar_dcb``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from peridynamics.analysis.beams import Plane
from peridynamics.analysis.dcb import dcb_lefm_curve

__all__ = ["DcbEvents", "breaking_events", "dcb_event_ratios"]


def breaking_events(time_s: ArrayLike) -> NDArray[np.intp]:
    """Indices of the records that are followed by a breaking solve at the same load
    level: the first of every run of equal load times (the peaks of the saw-tooth).

    Parameters
    ----------
    time_s : array_like, shape (n,)
        Load time (the static solver's load parameter) of every record.

    Returns
    -------
    ndarray of int, shape (k,)
        Record indices, increasing.
    """
    t = np.asarray(time_s, dtype=float)
    same = np.flatnonzero(np.diff(t) == 0.0)
    if not len(same):
        return same
    return same[np.r_[True, np.diff(same) > 1]]


@dataclass(frozen=True)
class DcbEvents:
    """The breaking events of a DCB run against LEFM.

    Attributes
    ----------
    index : ndarray of int, shape (k,)
        Record index of each event.
    crack_length : ndarray, shape (k,)
        Crack length from the load line at each event, m.
    ratio : ndarray, shape (k,)
        P / P_LEFM(Delta) at each event.
    straight : ndarray of bool, shape (k,)
        Events whose ligament is longer than three arm heights.
    """

    index: NDArray[np.intp]
    crack_length: NDArray[np.float64]
    ratio: NDArray[np.float64]
    straight: NDArray[np.bool_]

    def straight_mean(self) -> float:
        """Mean P / P_LEFM of the events on the straight part (NaN when none)."""
        if not self.straight.any():
            return float("nan")
        return float(self.ratio[self.straight].mean())


def dcb_event_ratios(
    load: ArrayLike,
    opening: ArrayLike,
    time_s: ArrayLike,
    growth: ArrayLike,
    a0: float,
    beam_length: float,
    arm_height: float,
    thickness: float,
    E: float,
    nu: float,
    fracture_energy: float,
    spacing: float,
    plane: Plane = "stress",
) -> DcbEvents:
    """P / P_LEFM at the breaking events of a DCB run (module docstring).

    Parameters
    ----------
    load : array_like, shape (n,)
        Load P of every record (the reaction of one arm's load line), N.
    opening : array_like, shape (n,)
        Total load-line opening Delta of every record, m.
    time_s : array_like, shape (n,)
        Load time of every record (equal for a re-solve after breaking).
    growth : array_like, shape (n,)
        Length of the tracked crack path beyond the pre-crack tip at every record, m.
    a0 : float
        Initial crack length from the load line, m.
    beam_length : float
        Distance from the load line to the clamp, m.
    arm_height : float
        Height h of one arm, m.
    thickness : float
        Width B, m.
    E : float
        Young's modulus, Pa.
    nu : float
        Poisson's ratio.
    fracture_energy : float
        G_c, J/m^2.
    spacing : float
        Grid spacing dx, m (the crack tip lies half a spacing past the last point).
    plane : {"stress", "strain"}
        Plane state of the beam formulas.
    """
    p = np.asarray(load, dtype=float)
    d = np.asarray(opening, dtype=float)
    peaks = breaking_events(time_s)
    a = a0 + np.asarray(growth, dtype=float)[peaks]
    straight = (beam_length - (a + 0.5 * spacing)) > 3.0 * arm_height
    lefm = dcb_lefm_curve(d[peaks], arm_height, thickness, E, nu, fracture_energy, plane)
    return DcbEvents(peaks, a, p[peaks] / lefm, np.asarray(straight, dtype=bool))
