"""The static elasticity cases of ``peridynamics verify``
(:mod:`peridynamics.app.verify_cases`): the interior moduli of free boxes (PMB against
its cubic lattice, LPS against the deck's E and nu), the tension plate against Hooke's
law (explicit and by dynamic relaxation), and the heated bar held at its ends."""

from __future__ import annotations

import numpy as np

from peridynamics.app import verify_moduli as _mod
from peridynamics.app.verify_base import Case, Check, Summary, material, probe

__all__ = [
    "PLATE_TENSION_ADR",
    "PLATE_TENSION_EXPLICIT",
    "PMB_BOX_MODULI",
    "THERMAL_EXPANSION_BAR",
    "lps_case",
]


def _plate_static(summary: Summary, a: str, b: str) -> float:
    """The difference of two displacement probes in the static state: the last record
    of a static solve, the mean after the ramp (t > 60 us) of a dynamic one."""
    pa, pb = probe(summary, a), probe(summary, b)
    diff = np.asarray(pa["values"]) - np.asarray(pb["values"])
    if summary["inputs"]["solver"].get("type") == "adr":
        return float(diff[-1])
    late = np.asarray(pa["time_s"]) > 60e-6
    return float(np.mean(diff[late]))


def _plate_stress(inputs: Summary) -> tuple[float, float, float, float]:
    """(traction (Pa), E (Pa), loaded length (m), width (m)) of the tension plate: the
    distance between the outermost rows of points, one spacing inside the outline."""
    e, _ = material(inputs)
    sigma = abs(float(inputs["boundary_conditions"][0]["value"][0]))
    dx = float(inputs["discretisation"]["spacing"])
    size = inputs["geometry"]["size"]
    return sigma, e, float(size[0]) - dx, float(size[1]) - dx


_HOOKE = "Hooke's law in uniaxial plane stress; nu = 1/3 of 2-D bond-based PD (Silling 2000)"


def _elongation(inputs: Summary) -> float:
    sigma, e, length, _ = _plate_stress(inputs)
    return sigma * length / e


def _width_change(inputs: Summary) -> float:
    sigma, e, _, width = _plate_stress(inputs)
    return -sigma * width / (3.0 * e)  # nu = 1/3


_LATTICE = (
    "the isotropic continuum, nu = 1/4 and E0 (Silling 2000, eq. 64), with "
    "discretisation.isotropic_family (the default); without it the cubic lattice of "
    "the family's fourth moment r = M_xxyy/M_xxxx: nu = r/(1+r), C11 = 1.2 E0 (Cauchy "
    "relation C12 = C44, Born & Huang 1954)"
)
_LPS_NU = "the deck's Poisson ratio (LPS, Silling et al. 2007), interior of a free box"


def _box(n: tuple[int, int, int]) -> str:
    """The ``geometry.size`` override of a box of n cells of 1 mm."""
    return "geometry.size=[" + ", ".join(f"{k * 1e-3:g}" for k in n) + "]"


def lps_case(nu: float, quick: tuple[int, int, int]) -> Case:
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


PMB_BOX_MODULI = Case(
    "pmb_box_moduli",
    "the interior of a free PMB box at the defaults (delta = 3.015 dx) has the "
    "isotropic moduli nu = 1/4 and E0 (the family made isotropic on the cubic grid)",
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

PLATE_TENSION_EXPLICIT = Case(
    "plate_tension_explicit",
    "a plate under a ramped uniaxial traction oscillates about Hooke's static state",
    "plate_tension_2d",
    quick=("discretisation.spacing=1e-3",),
    checks=_PLATE_CHECKS,
)

PLATE_TENSION_ADR = Case(
    "plate_tension_adr",
    "the same plate solved for equilibrium by adaptive dynamic relaxation",
    "plate_tension_2d/adr",
    quick=("discretisation.spacing=1e-3",),
    checks=_PLATE_CHECKS,
)


def _thermal_stress(inputs: Summary) -> float:
    """-E alpha dT (Pa): the axial stress of a bar held at its ends and heated by dT,
    free laterally (plane stress)."""
    t = inputs["thermal"]
    initial = float(t["initial_temperature"])
    reference = t.get("reference_temperature")
    dt = initial - (initial if reference is None else float(reference))
    return -float(inputs["material"]["youngs_modulus"]) * float(t["expansion"]) * dt


def _last_probe(summary: Summary, name: str) -> float:
    return float(probe(summary, name)["values"][-1])


THERMAL_EXPANSION_BAR = Case(
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
