"""The Brazilian-disc convergence studies of ``peridynamics verify``
(:mod:`peridynamics.app.verify_cases`): the splitting strength 2 P / (pi D t) of the rock
disc between rigid platens (``examples/bodies/brazilian_disc.yaml``; ISRM (1978), ASTM
D3967) over three refinements, with m = delta/dx fixed (delta shrinks with dx) and with
delta fixed (m grows). Each study is one case: the deck at the coarsest of its three
spacings and the two finer ones as its ``series`` runs; the measures are those of
``examples/bodies/brazilian_disc.py`` (the peak y reaction of the top platen).
"""

from __future__ import annotations

import math

import numpy as np

from peridynamics.app.verify_base import Case, Check, Summary

__all__ = ["BRAZILIAN_DELTA_CONVERGENCE", "BRAZILIAN_M_CONVERGENCE"]

#: the disc's diameter (m) in the shipped deck: the spacings of the studies are D / ratio
DIAMETER = 0.05


def splitting_strength(summary: Summary) -> float:
    """2 P / (pi D t) (Pa) of one run: P the peak y reaction of the rigid body
    ``top_platen``, D the diameter of the deck's disc (the circle its one hole keeps), t
    the thickness."""
    geo = summary["inputs"]["geometry"]
    radius = float(geo["holes"][0]["not"]["circle"]["radius"])
    force = np.asarray(summary["results"]["rigid_bodies"]["top_platen"]["force_N"])
    peak = float(np.max(force[:, 1]))
    return 2.0 * peak / (math.pi * 2.0 * radius * float(geo["thickness"]))


def _strengths(summary: Summary) -> np.ndarray:
    """The splitting strengths (Pa) of the case's run and its series, coarse to fine."""
    return np.asarray([splitting_strength(s) for s in (summary, *summary["series"])])


def strength_spread(summary: Summary) -> float:
    """(max - min) / mean of the splitting strength over the study's runs."""
    s = _strengths(summary)
    return float(np.ptp(s) / s.mean())


def step_ratio(summary: Summary) -> float:
    """|last step| / |step before| of the splitting strength over three refinements
    (< 1: the steps shrink, the study converges)."""
    s = _strengths(summary)
    return float(abs(s[-1] - s[-2]) / abs(s[-2] - s[-3]))


def finest_over_tensile_strength(summary: Summary) -> float:
    """Splitting strength of the finest run over the bonds' strength f_t."""
    f_t = float(summary["inputs"]["damage"]["tensile_strength"])
    return float(_strengths(summary)[-1] / f_t)


def _spacing(ratio: int) -> str:
    return f"discretisation.spacing={DIAMETER / ratio!r}"


_SPREAD = Check(
    "spread (max - min) / mean of the splitting strength 2P/(pi D t) over the three "
    "refinements", "-", strength_spread, lambda i: 0.05,
    "the issue: converged within 5 % over the last three refinements (ISRM (1978) for "
    "the strength)", at_most=True,
)  # fmt: skip
_STEPS = Check(
    "last step of the strength over the step before", "-", step_ratio, lambda i: 1.0,
    "a converging sequence: the steps shrink", at_most=True,
)  # fmt: skip

#: the quiet run of the studies: no VTK frames (the checks read summary.json)
_QUIET = ("output.vtk_every=0",)

BRAZILIAN_M_CONVERGENCE = Case(
    "brazilian_m_convergence",
    "the splitting strength of the Brazilian disc converges with the grid at m = "
    "delta/dx = 3.015 fixed (D/dx = 60, 80, 100; delta shrinks to 0.06 R) toward the "
    "bonds' strength f_t from below",
    "bodies/brazilian_disc",
    quick=None,
    full=(_spacing(60), *_QUIET),
    series=((_spacing(80),), (_spacing(100),)),
    checks=(
        _SPREAD,
        _STEPS,
        Check(
            "splitting strength at D/dx = 100 over f_t", "-",
            finest_over_tensile_strength, lambda i: 1.0,
            "below the bonds' uniaxial strength f_t (the limit as delta/R -> 0)",
            at_most=True,
        ),
    ),
)  # fmt: skip

#: the fixed horizon of the delta study (m): 0.1 R
_DELTA = ("discretisation.horizon=2.5e-3", "discretisation.horizon_factor=null")

BRAZILIAN_DELTA_CONVERGENCE = Case(
    "brazilian_delta_convergence",
    "the splitting strength of the Brazilian disc converges with the grid at delta = "
    "2.5 mm = 0.1 R fixed (D/dx = 80, 100, 120: m = 4, 5, 6) to the nonlocal body's "
    "strength, below f_t (the horizon-wide softening zone is not small against the disc)",
    "bodies/brazilian_disc",
    quick=None,
    full=(_spacing(80), *_DELTA, "solver.end_time=2.0e-3", *_QUIET),
    series=((_spacing(100),), (_spacing(120),)),
    checks=(_SPREAD, _STEPS),
)  # fmt: skip
