"""The verification cases of ``peridynamics verify``: a shipped example deck at a stated
size, and the quantities measured from its run against references that do not come
from this code (closed-form solutions, published observations), each with its source
and a tolerance.

A case is data: the example, the overrides of each tier, and its checks. A check reads
the run's ``summary.json`` mapping (with ``"folder"``, the run's folder, for a check
that reads the final fields) and returns the measured value; the reference is a
number computed from the deck's own parameters (so an override that changes E also
changes the reference), never a number an earlier run of this code printed.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from peridynamics.app import verify_moduli as _mod

Summary = dict[str, Any]


@dataclass(frozen=True)
class Check:
    """One measured quantity against its reference.

    Attributes
    ----------
    quantity : str
        What is measured (a sentence fragment, with the unit in ``unit``).
    unit : str
        Unit of the measured and reference values (SI).
    measure : callable
        ``measure(summary) -> float``: the value from the run.
    reference : callable
        ``reference(inputs) -> float``: the reference from the deck's parameters
        (``summary["inputs"]``, the validated deck as data).
    source : str
        Where the reference comes from (an author-year citation listed in
        ``docs/references.md``, or the closed form it is).
    rel : float
        Relative tolerance (``|measured - reference| <= rel |reference| + abs``).
    abs : float
        Absolute tolerance, in ``unit``.
    at_most : bool
        An upper bound: passes when ``measured <= reference (1 + rel)`` (a crack speed
        below the Rayleigh speed, ...).
    """

    quantity: str
    unit: str
    measure: Callable[[Summary], float]
    reference: Callable[[Summary], float]
    source: str
    rel: float = 0.0
    abs: float = 0.0
    at_most: bool = False

    def judge(self, measured: float, reference: float) -> bool:
        """Whether ``measured`` is within the tolerance of ``reference``."""
        if not (math.isfinite(measured) and math.isfinite(reference)):
            return False
        if self.at_most:
            return measured <= reference * (1.0 + self.rel) + self.abs
        return abs(measured - reference) <= self.rel * abs(reference) + self.abs


@dataclass(frozen=True)
class Case:
    """A shipped example run at a tier's size, and its checks.

    Attributes
    ----------
    name : str
        The case's name (``--only`` matches it).
    title : str
        One line on what is verified.
    deck : str
        The example deck, as ``peridynamics examples`` names it (``bar_wave_1d``,
        ``plate_tension_2d/adr``).
    quick : tuple of str or None
        ``--set`` overrides of the quick tier (``None``: not in the quick tier).
    full : tuple of str
        Overrides of the full tier (the shipped deck: ``()``).
    checks : tuple of Check
        What is compared.
    companion : tuple of str or None
        Overrides added to the tier's for a second run of the same deck (into
        ``<case>/companion/``), whose summary the checks read as ``summary["companion"]``:
        a case whose reference is another scheme's run of the same problem (the 1-D
        finite-difference scheme against peridynamics with delta = dx). ``None``: one run.
    """

    name: str
    title: str
    deck: str
    quick: tuple[str, ...] | None
    full: tuple[str, ...] = ()
    checks: tuple[Check, ...] = field(default_factory=tuple)
    companion: tuple[str, ...] | None = None

    def overrides(self, tier: str) -> tuple[str, ...] | None:
        """The overrides of ``tier`` (``"quick"`` or ``"full"``), ``None`` when the case
        is not in it."""
        return self.quick if tier == "quick" else self.full


# -- the quantities --------------------------------------------------------------------
def _probe(summary: Summary, name: str) -> dict[str, Any]:
    return dict(summary["results"]["probes"][name])


def _material(inputs: Summary) -> tuple[float, float]:
    m = inputs["material"]
    return float(m["youngs_modulus"]), float(m["density"])


def _bar_speed(inputs: Summary) -> float:
    e, rho = _material(inputs)
    return math.sqrt(e / rho)


def _pulse(inputs: Summary) -> tuple[float, float]:
    """(peak stress (Pa), rise time (s)) of the bar's triangular pulse."""
    load = inputs["boundary_conditions"][0]
    tf = load["time_function"]
    return abs(float(load["value"][0]) * float(tf["peak"])), float(tf["rise_time"])


def _gauge_x(inputs: Summary) -> float:
    return float(inputs["node_sets"]["gauge"]["point"][0])


def _plate_static(summary: Summary, a: str, b: str) -> float:
    """The difference of two displacement probes in the static state: the last record
    of a static solve, the mean after the ramp (t > 60 us) of a dynamic one."""
    pa, pb = _probe(summary, a), _probe(summary, b)
    diff = np.asarray(pa["values"]) - np.asarray(pb["values"])
    if summary["inputs"]["solver"].get("type") == "adr":
        return float(diff[-1])
    late = np.asarray(pa["time_s"]) > 60e-6
    return float(np.mean(diff[late]))


def _plate_stress(inputs: Summary) -> tuple[float, float, float, float]:
    """(traction (Pa), E (Pa), loaded length (m), width (m)) of the tension plate: the
    distance between the outermost rows of points, one spacing inside the outline."""
    e, _ = _material(inputs)
    sigma = abs(float(inputs["boundary_conditions"][0]["value"][0]))
    dx = float(inputs["discretisation"]["spacing"])
    size = inputs["geometry"]["size"]
    return sigma, e, float(size[0]) - dx, float(size[1]) - dx


def _rayleigh_speed_pmb_plane_stress(inputs: Summary) -> float:
    """Rayleigh speed of the bond-based plate as modelled: plane stress with nu = 1/3
    (plane-strain equations with nu* = 1/4, c_R = 0.9194 c_s) and the interior modulus
    0.855 E of the uncorrected model at delta = 4 dx (docs/deck.md)."""
    e, rho = _material(inputs)
    corrected = inputs["discretisation"].get("surface_correction", True)
    e_model = e if corrected else 0.855 * e
    return 0.9194 * math.sqrt(e_model / (2.0 * (1.0 + 1.0 / 3.0)) / rho)


_WAVE = "d'Alembert solution of the local bar, c = sqrt(E / rho)"
_HOOKE = "Hooke's law in uniaxial plane stress; nu = 1/3 of 2-D bond-based PD (Silling 2000)"


def _elongation(inputs: Summary) -> float:
    sigma, e, length, _ = _plate_stress(inputs)
    return sigma * length / e


def _width_change(inputs: Summary) -> float:
    sigma, e, _, width = _plate_stress(inputs)
    return -sigma * width / (3.0 * e)  # nu = 1/3


def _companion_gap(summary: Summary, probe: str) -> float:
    """max_t |p(t) - p_c(t)| / max_t |p_c(t)| of the probe ``probe`` of the run and of
    its companion run (the same records)."""
    a = np.asarray(_probe(summary, probe)["values"], dtype=float)
    b = np.asarray(_probe(summary["companion"], probe)["values"], dtype=float)
    if a.shape != b.shape:
        raise ValueError(f"{probe}: {a.shape} records against {b.shape}")
    return float(np.abs(a - b).max() / np.abs(b).max())


_FDM = (
    "the explicit finite-difference scheme on the same nodes (Lu & Wang 2016, eq. 17), "
    "which bond-based PD with delta = dx and the truncated partial volumes is"
)
#: delta = dx with the default surface correction (true), spelled out: the example deck
#: turns it off for Lu & Wang's uncorrected delta = 3 dx
_NEAREST = ("discretisation.horizon_factor=1", "discretisation.surface_correction=true")

_LATTICE = (
    "the cubic lattice of the family's fourth moment r = M_xxyy/M_xxxx: nu = r/(1+r), "
    "C11 = 1.2 E0 (Cauchy relation C12 = C44, Born & Huang 1954; not the "
    "isotropic nu = 1/4 of Silling 2000 at this m)"
)
_LPS_NU = "the deck's Poisson ratio (LPS, Silling et al. 2007), interior of a free box"


def _box(n: tuple[int, int, int]) -> str:
    """The ``geometry.size`` override of a box of n cells of 1 mm."""
    return "geometry.size=[" + ", ".join(f"{k * 1e-3:g}" for k in n) + "]"


def _lps_case(nu: float, quick: tuple[int, int, int]) -> Case:
    """An LPS box at Poisson ratio ``nu``: interior strain ratio and modulus."""
    return Case(
        f"lps_box_nu_{nu:g}",
        f"the interior of a free LPS box under uniaxial traction at the defaults has the "
        f"nominal E and nu = {nu:g}",
        "box_moduli_3d/lps",
        quick=(f"material.poisson_ratio={nu}", _box(quick)),
        full=(f"material.poisson_ratio={nu}", _box((60, 24, 24))),
        checks=(
            Check(
                "interior strain ratio -(eps_yy + eps_zz)/(2 eps_xx)", "-", _mod.interior_nu,
                lambda i: float(i["material"]["poisson_ratio"]), _LPS_NU, rel=0.02,
            ),
            Check(
                "interior modulus sigma/(eps_xx E0)", "-", _mod.interior_e_ratio,
                lambda i: 1.0, "Hooke's law, uniaxial stress", rel=0.02,
            ),
        ),
    )  # fmt: skip


_PLATE_CHECKS = (
    Check(
        "elongation between the loaded rows", "m",
        lambda s: _plate_static(s, "right_ux", "left_ux"), _elongation, _HOOKE, rel=0.03,
    ),
    Check(
        "change of width between the edge rows", "m",
        lambda s: _plate_static(s, "top_uy", "bottom_uy"), _width_change, _HOOKE, rel=0.05,
    ),
)  # fmt: skip


def _thermal_stress(inputs: Summary) -> float:
    """-E alpha dT (Pa): the axial stress of a bar held at its ends and heated by dT,
    free laterally (plane stress)."""
    t = inputs["thermal"]
    initial = float(t["initial_temperature"])
    reference = t.get("reference_temperature")
    dt = initial - (initial if reference is None else float(reference))
    return -float(inputs["material"]["youngs_modulus"]) * float(t["expansion"]) * dt


def _last_probe(summary: Summary, name: str) -> float:
    return float(_probe(summary, name)["values"][-1])


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


_THERMAL_CASE = Case(
    "thermal_expansion_bar",
    "an LPS bar held at its ends and heated by 100 K carries the axial stress -E alpha dT "
    "and no lateral stress (static solve)",
    "thermal/expansion",
    quick=("output.vtk_every=0",),
    checks=(
        Check(
            "mean axial stress in the middle of the bar", "Pa",
            lambda s: _last_probe(s, "middle_sxx"), _thermal_stress,
            "thermal stress of a bar held at its ends (Timoshenko & Goodier 1970)",
            rel=0.015,  # measured 1.0089 at dx = 0.5 mm, 1.045 at 1 mm
        ),
        Check(
            "mean lateral stress in the middle of the bar", "Pa",
            lambda s: _last_probe(s, "middle_syy"), lambda i: 0.0,
            "plane stress, free lateral edges", abs=1e6,  # 0.6 % of E alpha dT = 161 MPa
        ),
    ),
)  # fmt: skip

_FATIGUE_CASE = Case(
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

#: every case, in report order
CASES: tuple[Case, ...] = (
    Case(
        "bar_wave_1d",
        "a triangular stress pulse travels along a 1-D bar at the bar speed (Lu & Wang 2016)",
        "bar_wave_1d",
        quick=("discretisation.spacing=0.01", "solver.time_step=2e-6"),
        checks=(
            Check(
                "arrival of 10 % of the peak velocity at the gauge", "s",
                lambda s: float(_probe(s, "gauge_velocity")["arrival_time_s"]),
                lambda i: _gauge_x(i) / _bar_speed(i) + 0.1 * _pulse(i)[1],
                _WAVE, abs=6e-6,
            ),
            Check(
                "peak particle velocity at the gauge", "m/s",
                lambda s: abs(float(_probe(s, "gauge_velocity")["peak"])),
                lambda i: _pulse(i)[0] / (_material(i)[1] * _bar_speed(i)),
                _WAVE + ": v = sigma / (rho c)", rel=0.03,
            ),
        ),
    ),
    Case(
        "bar_nearest_equals_fdm",
        "1-D PD with delta = dx and the default surface correction is the finite-"
        "difference scheme to round-off (the correction is the identity)",
        "bar_wave_1d",
        quick=(*_NEAREST, "discretisation.spacing=0.01", "solver.time_step=2e-6"),
        full=_NEAREST,
        companion=("solver.method=fdm",),
        checks=(
            Check(
                "largest gap of the gauge velocity (PD - FDM), relative to its peak", "-",
                lambda s: _companion_gap(s, "gauge_velocity"), lambda i: 0.0,
                # round-off of (u+ - u-) / 2 dt: 1.3e-12 measured, the same uncorrected
                _FDM, abs=1e-11,
            ),
            Check(
                "largest gap of the gauge displacement (PD - FDM), relative to its peak", "-",
                lambda s: _companion_gap(s, "gauge_displacement"), lambda i: 0.0,
                _FDM, abs=1e-12,
            ),
        ),
    ),
    Case(
        "pmb_box_moduli",
        "the interior of a free PMB box at the defaults (delta = 3.015 dx) has the moduli "
        "of its cubic lattice (nu 0.269, E 0.962 E0, not 1/4 and E0)",
        "box_moduli_3d",
        quick=(_box((40, 24, 24)),),
        full=(_box((60, 36, 36)),),
        checks=(
            Check(
                "interior strain ratio -(eps_yy + eps_zz)/(2 eps_xx)", "-", _mod.interior_nu,
                lambda i: _mod.lattice_moduli(i)[1], _LATTICE, rel=0.02,
            ),
            Check(
                "interior modulus sigma/(eps_xx E0)", "-", _mod.interior_e_ratio,
                lambda i: _mod.lattice_moduli(i)[0], _LATTICE, rel=0.02,
            ),
        ),
    ),
    _lps_case(0.1, (30, 20, 20)),
    _lps_case(0.25, (30, 20, 20)),
    _lps_case(0.35, (30, 20, 20)),
    Case(
        "plate_tension_explicit",
        "a plate under a ramped uniaxial traction oscillates about Hooke's static state",
        "plate_tension_2d",
        quick=("discretisation.spacing=1e-3",),
        checks=_PLATE_CHECKS,
    ),
    Case(
        "plate_tension_adr",
        "the same plate solved for equilibrium by adaptive dynamic relaxation",
        "plate_tension_2d/adr",
        quick=("discretisation.spacing=1e-3",),
        checks=_PLATE_CHECKS,
    ),
    Case(
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
                _rayleigh_speed_pmb_plane_stress,
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
    ),
    _THERMAL_CASE,
    _FATIGUE_CASE,
)  # fmt: skip


def select(tier: str, pattern: str | None = None) -> list[Case]:
    """The cases of ``tier`` whose name matches the shell pattern ``pattern``."""
    from fnmatch import fnmatch

    return [
        c for c in CASES
        if c.overrides(tier) is not None and (pattern is None or fnmatch(c.name, pattern))
    ]  # fmt: skip
