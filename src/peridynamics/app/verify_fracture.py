"""The fracture and fatigue cases of ``peridynamics verify``
(:mod:`peridynamics.app.verify_cases`): crack branching in glass (Ha & Bobaru 2010), the
Kalthoff-Winkler plate (Kalthoff & Winkler 1988), the S-N bar of the fatigue solver
(Silling & Askari 2014) and the work of fracture of the notched beam with softening
bonds (RILEM TC 50-FMC 1985).

The Kalthoff-Winkler angle is the one the run itself measured (``results.crack_paths``,
the deck's ``output.crack_paths``: :func:`peridynamics.analysis.crack_path.extract_crack_paths`
with the settings of ``examples/kalthoff_winkler/refinement.py``), not a copy of that
measure.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from peridynamics.app.verify_base import Case, Check, Summary, material

__all__ = ["BEND_WORK_OF_FRACTURE", "CRACK_BRANCHING", "FATIGUE_SN_BAR", "KALTHOFF_WINKLER"]


def rayleigh_speed_pmb_plane_stress(inputs: Summary) -> float:
    """Rayleigh speed (m/s) of the bond-based plate as modelled: plane stress with
    nu = 1/3 (plane-strain equations with nu* = 1/4, c_R = 0.9194 c_s) and the interior
    modulus 0.855 E of the uncorrected model at delta = 4 dx (docs/deck.md)."""
    e, rho = material(inputs)
    corrected = inputs["discretisation"].get("surface_correction", True)
    e_model = e if corrected else 0.855 * e
    return 0.9194 * math.sqrt(e_model / (2.0 * (1.0 + 1.0 / 3.0)) / rho)


CRACK_BRANCHING = Case(
    "crack_branching",
    "a crack in a glass plate under sudden tension runs below the Rayleigh speed and "
    "branches (Ha & Bobaru 2010)",
    "crack_branching_2d",
    quick=("discretisation.spacing=5e-4", "discretisation.horizon=2e-3",
           "output.vtk_every=0"),
    checks=(
        Check(
            "largest crack-tip speed", "m/s",
            lambda s: float(s["results"]["max_crack_tip_speed_m_per_s"]),
            rayleigh_speed_pmb_plane_stress,
            "Rayleigh speed of the modelled plate (Freund 1990: a mode-I crack runs "
            "below it)", at_most=True,
        ),
        Check(
            "crack branches (number of branches at the end)", "-",
            lambda s: float(s["results"].get("crack_branches") or 1),
            lambda i: 2.0,
            "Ha & Bobaru (2010): the crack branches once at 12 MPa", abs=0.0,
        ),
    ),
)  # fmt: skip


def _sn_cycles(inputs: Summary) -> float:
    """N = 1 / (A1 ((1 - R) s)^m1) of a uniform bar at the stretch s = u/L (Silling &
    Askari 2014; A1 from the S-N point: A1 = 1 / (N_ref range_ref^m1))."""
    f = inputs["damage"]["fatigue"]
    m1 = float(f["m1"])
    a1 = f.get("a1")
    if a1 is None:
        ref = f["sn_point"]
        a1 = 1.0 / (float(ref["cycles"]) * float(ref["strain_range"]) ** m1)
    pull = [c for c in inputs["boundary_conditions"] if c["type"] == "displacement"][0]
    stretch = float(pull["components"]["x"]) / float(inputs["geometry"]["length"])
    r = float(inputs["solver"]["load_ratio"])
    return 1.0 / (float(a1) * (abs(1.0 - r) * stretch) ** m1)


FATIGUE_SN_BAR = Case(
    "fatigue_sn_bar",
    "a bar of equal bonds cycled at load ratio R fails at the cycles of the S-N law it "
    "was calibrated with (cycle jumping)",
    "fatigue/sn_bar",
    quick=(),
    checks=(
        Check(
            "cycles to the first broken bond", "cycles",
            lambda s: float(s["results"]["first_break_cycles"]), _sn_cycles,
            "the remaining-life law dlambda/dN = -A1 eps^m1 integrated at constant range "
            "(Silling & Askari 2014)", rel=1e-9,
        ),
    ),
)  # fmt: skip


def crack_path_value(summary: Summary, crack: str, key: str) -> float:
    """``results.crack_paths.<crack>.<key>`` of a run (a tracked crack's initial angle
    (deg), length (m), largest tip speed (m/s), ...)."""
    return float(summary["results"]["crack_paths"][crack][key])


def kw_mirror_gap(summary: Summary) -> float:
    """|upper + lower| (deg): how far the initial angles of the two notch cracks (the
    lower one measured with its sign) are from mirror images of each other."""
    up = crack_path_value(summary, "upper", "initial_angle_deg")
    lo = crack_path_value(summary, "lower", "initial_angle_deg")
    return abs(up + lo)


#: the experiment's crack angle from the notch direction (deg), Kalthoff & Winkler (1988)
KW_EXPERIMENT_DEG = 70.0

KALTHOFF_WINKLER = Case(
    "kalthoff_winkler",
    "each notch tip of the Kalthoff-Winkler plate (32 m/s, dx = 1 mm, delta = 3.015 dx) "
    "sends a crack off at about 70 deg, mirror images, below the Rayleigh speed "
    "(Kalthoff & Winkler 1988)",
    "kalthoff_winkler",
    quick=None,
    full=("discretisation.spacing=1.0e-3", "output.vtk_every=0"),
    checks=(
        Check(
            "initial angle of the upper crack: chord over its first 20 mm of path, from "
            "the notch direction", "deg",
            lambda s: crack_path_value(s, "upper", "initial_angle_deg"),
            lambda i: KW_EXPERIMENT_DEG,
            "Kalthoff & Winkler (1988): about 70 deg in the experiment; +-5 deg: the "
            "goal 65-72 deg of the issue, and one spacing sideways at the chord's end "
            "turns it by atan(1/20) = 2.9 deg",
            abs=5.0,
        ),
        Check(
            "|upper + lower| initial angle (mirror images)", "deg", kw_mirror_gap,
            lambda i: 0.0,
            "the plate, notches, impact and grid are symmetric about y = 0; 0.1 deg: the "
            "printed digit of the README's table", abs=0.1,
        ),
        Check(
            "largest tip speed of the upper crack (path length history)", "m/s",
            lambda s: crack_path_value(s, "upper", "max_tip_speed_m_per_s"),
            rayleigh_speed_pmb_plane_stress,
            "Rayleigh speed of the modelled plate (Freund 1990: a mode-I crack runs "
            "below it)", at_most=True,
        ),
    ),
)  # fmt: skip


def _pin_curve(summary: Summary, body: str) -> tuple[np.ndarray, np.ndarray]:
    """(load (N), downward displacement (m)) of the rigid body ``body``'s y reaction
    (``results.rigid_bodies``), one row per history sample."""
    rb = summary["results"]["rigid_bodies"][body]
    load = np.asarray(rb["force_N"], dtype=float)[:, 1]
    disp = -np.asarray(rb["displacement_m"], dtype=float)[:, 1]
    return load, disp


def work_of_fracture(summary: Summary, body: str = "pin") -> float:
    """W_F (J): the area under the load of the loading roller ``body`` (its y reaction,
    ``results.rigid_bodies``) against its downward displacement, over the whole run
    (trapezoids, nothing extrapolated; ``examples/bodies/bend_softening.py``)."""
    load, disp = _pin_curve(summary, body)
    return float(np.sum(0.5 * (load[1:] + load[:-1]) * np.diff(disp)))


def last_load_fraction(summary: Summary, body: str = "pin") -> float:
    """The load at the end of the run over the peak load (dimensionless)."""
    load, _ = _pin_curve(summary, body)
    return float(load[-1] / load.max())


#: the tail law is fitted to the samples after the peak whose load is below this
#: fraction of the peak (the far tail, Elices, Guinea & Planas (1992))
TAIL_FIT_BELOW = 0.05


def tail_work(summary: Summary, body: str = "pin") -> float:
    """The work (J) beyond the end of the run of the tail ``P = A / u^2`` (Elices,
    Guinea & Planas (1992)), ``A`` the least-squares fit to the samples after the peak
    with a load below :data:`TAIL_FIT_BELOW` of the peak (the last sample alone when
    none is): ``int_{u_end}^inf A / u^2 du = A / u_end``."""
    load, disp = _pin_curve(summary, body)
    peak = int(np.argmax(load))
    after = np.arange(len(load)) > peak
    fit = after & (load < TAIL_FIT_BELOW * load[peak]) & (disp > 0.0)
    if not fit.any():
        fit = np.arange(len(load)) == len(load) - 1
    inv2 = disp[fit] ** -2.0
    a = float(np.sum(load[fit] * inv2) / np.sum(inv2 * inv2))
    return max(a, 0.0) / float(disp[-1])


def work_of_fracture_with_tail(summary: Summary, body: str = "pin") -> float:
    """:func:`work_of_fracture` plus :func:`tail_work` (J)."""
    return work_of_fracture(summary, body) + tail_work(summary, body)


def ligament_fracture_energy(inputs: Summary) -> float:
    """G_F t (D - a0) (J): the fracture energy of the notched beam's ligament, D the
    depth, a0 the notch's top above the bottom face."""
    geo = inputs["geometry"]
    depth, bottom = float(geo["size"][1]), float(geo["origin"][1])
    a0 = max(float(p[1]) for p in inputs["precracks"][0]["points"]) - bottom
    return float(inputs["damage"]["fracture_energy"]) * float(geo["thickness"]) * (depth - a0)


def _finest(summary: Summary) -> Summary:
    """The finest run of a refinement case: its last ``series`` run."""
    return summary["series"][-1] if summary.get("series") else summary


def _shortfall(summary: Summary) -> float:
    """1 - W_F / (G_F t (D - a0)), nothing extrapolated."""
    return 1.0 - work_of_fracture(summary) / ligament_fracture_energy(summary["inputs"])


def shortfall_ratio(summary: Summary) -> float:
    """The finest run's shortfall of W_F over the case run's (< 1: the gap closes under
    refinement)."""
    return _shortfall(_finest(summary)) / _shortfall(summary)


_RILEM = "RILEM TC 50-FMC (1985): W_F = G_F t (D - a0); 5 %: the issue's goal"
_TAIL_LAW = "RILEM TC 50-FMC (1985); the tail law of Elices, Guinea & Planas (1992)"


def _work_check(quantity: str, measure: Callable[[Summary], float], source: str) -> Check:
    """A work of fracture (J) within 5 % (the issue's goal) of G_F t (D - a0)."""
    return Check(quantity, "J", measure, ligament_fracture_energy, source, rel=0.05)


BEND_WORK_OF_FRACTURE = Case(
    "bend_work_of_fracture",
    "the notched beam with bilinear softening bonds in three-point bending "
    "(examples/bodies, the grid's bonds calibrated to hold G_F: "
    "discretisation.lattice_fracture_energy as shipped), carried to 2 mm where the load "
    "is about 0.1 % of its peak, at dx = 2.5 mm (the deck) and 1.25 mm: the finer beam "
    "dissipates G_F over its ligament with nothing extrapolated; at 2.5 mm the top of "
    "the ligament under the loading roller stays a compressed hinge of about one "
    "horizon whose bonds never break, so only the tail-extrapolated area is checked "
    "there (examples/bodies/README.md)",
    "bodies/three_point_bend_softening",
    quick=None,
    full=("solver.end_time=0.2",),
    series=(("discretisation.spacing=0.00125",),),
    checks=(
        _work_check(
            "work of fracture W_F at dx = 1.25 mm: area under load against load-point "
            "displacement (nothing extrapolated)",
            lambda s: work_of_fracture(_finest(s)), _RILEM,
        ),
        Check(
            "load at the end of the run over the peak load, dx = 1.25 mm", "-",
            lambda s: last_load_fraction(_finest(s)), lambda i: 0.01,
            "the issue: the load carried to at most 1 % of the peak", at_most=True,
        ),
        _work_check(
            "W_F at dx = 1.25 mm with the tail beyond the run extrapolated as "
            "P = A / u^2 (reported separately)",
            lambda s: work_of_fracture_with_tail(_finest(s)), _TAIL_LAW,
        ),
        _work_check(
            "W_F at dx = 2.5 mm (the deck) with the tail extrapolated as P = A / u^2",
            work_of_fracture_with_tail, _TAIL_LAW,
        ),
        Check(
            "shortfall 1 - W_F / (G_F t (D - a0)) at dx = 1.25 mm over that at 2.5 mm "
            "(nothing extrapolated)", "-",
            shortfall_ratio, lambda i: 1.0,
            "convergence under refinement: the hinge's share of the ligament shrinks "
            "with the horizon", at_most=True,
        ),
    ),
)  # fmt: skip
