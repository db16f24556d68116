"""The wave cases of ``peridynamics verify`` (:mod:`peridynamics.app.verify_cases`): a
triangular pulse in the 1-D bar against d'Alembert's solution, and the bar with
delta = dx against the finite-difference scheme it is."""

from __future__ import annotations

import math

import numpy as np

from peridynamics.app.verify_base import Case, Check, Summary, material, probe

__all__ = ["BAR_NEAREST_EQUALS_FDM", "BAR_WAVE_1D"]


def _bar_speed(inputs: Summary) -> float:
    e, rho = material(inputs)
    return math.sqrt(e / rho)


def _pulse(inputs: Summary) -> tuple[float, float]:
    """(peak stress (Pa), rise time (s)) of the bar's triangular pulse."""
    load = inputs["boundary_conditions"][0]
    tf = load["time_function"]
    return abs(float(load["value"][0]) * float(tf["peak"])), float(tf["rise_time"])


def _gauge_x(inputs: Summary) -> float:
    return float(inputs["node_sets"]["gauge"]["point"][0])


def _companion_gap(summary: Summary, name: str) -> float:
    """max_t |p(t) - p_c(t)| / max_t |p_c(t)| of the probe ``name`` of the run and of
    its companion run (the same records)."""
    a = np.asarray(probe(summary, name)["values"], dtype=float)
    b = np.asarray(probe(summary["companion"], name)["values"], dtype=float)
    if a.shape != b.shape:
        raise ValueError(f"{name}: {a.shape} records against {b.shape}")
    return float(np.abs(a - b).max() / np.abs(b).max())


_WAVE = "d'Alembert solution of the local bar, c = sqrt(E / rho)"
_FDM = (
    "the explicit finite-difference scheme on the same nodes (Lu & Wang 2016, eq. 17), "
    "which bond-based PD with delta = dx and the truncated partial volumes is"
)
#: delta = dx with the default surface correction (true), spelled out: the example deck
#: turns it off for Lu & Wang's uncorrected delta = 3 dx
_NEAREST = ("discretisation.horizon_factor=1", "discretisation.surface_correction=true")

BAR_WAVE_1D = Case(
    "bar_wave_1d",
    "a triangular stress pulse travels along a 1-D bar at the bar speed (Lu & Wang 2016)",
    "bar_wave_1d",
    quick=("discretisation.spacing=0.01", "solver.time_step=2e-6"),
    checks=(
        Check(
            "arrival of 10 % of the peak velocity at the gauge", "s",
            lambda s: float(probe(s, "gauge_velocity")["arrival_time_s"]),
            lambda i: _gauge_x(i) / _bar_speed(i) + 0.1 * _pulse(i)[1],
            _WAVE, abs=6e-6,
        ),
        Check(
            "peak particle velocity at the gauge", "m/s",
            lambda s: abs(float(probe(s, "gauge_velocity")["peak"])),
            lambda i: _pulse(i)[0] / (material(i)[1] * _bar_speed(i)),
            _WAVE + ": v = sigma / (rho c)", rel=0.03,
        ),
    ),
)  # fmt: skip

BAR_NEAREST_EQUALS_FDM = Case(
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
)  # fmt: skip
