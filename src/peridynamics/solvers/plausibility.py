"""Admissible but implausible settings of an explicit run, named by their deck key.

:func:`findings` lists what is far outside what a run can use; the explicit solver
issues each as an :class:`ImplausibleSettingWarning` when it is built
(:func:`warn_implausible`, printed by the command line as ``warning: ...``), and
:func:`unstable_advice` names them again when a run goes unstable. The checks:

- ``material.youngs_modulus`` / ``material.density``: a wave speed sqrt(E / rho)
  outside :data:`WAVE_SPEED_RANGE` (solids: about 50 m/s for rubber to 1.8e4 m/s for
  diamond); the key blamed is the value farther, in decades, from a typical rock;
- ``solver.damping``: above critical damping 2 omega_1 of the first axial mode
  omega_1 = pi c / L (c = sqrt(E / rho), L the largest extent of the body). The real
  fundamental mode is usually lower (a fixed end halves it, bending lowers it more; in
  plane stress it is up to 6 % higher), so every mode is then over-damped: the body
  creeps to equilibrium more slowly than at critical damping, and a prescribed motion
  is resisted by a force rho c_d v;
- ``material.viscosity.linear``: a damping ratio of the fastest mode above
  :data:`MAX_VISCOUS_RATIO` (b1 of order 0.1 to 1 damps the spurious short waves);
- ``solver.time_step``: below :data:`MIN_STEP_FRACTION` x the stable step.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from peridynamics.evaluation.stability import StableStep

#: wave speeds sqrt(E / rho) of solids (m/s); outside: a warning naming E or rho
WAVE_SPEED_RANGE = (1.0, 1.0e5)
#: a user step below this fraction of the stable step: a warning naming solver.time_step
MIN_STEP_FRACTION = 1.0e-3
#: a damping ratio of the fastest mode from the linear viscosity above this: a warning
MAX_VISCOUS_RATIO = 10.0
#: a typical solid (rock): the reference for saying which of E and rho is off
_TYPICAL_E, _TYPICAL_RHO = 1.0e10, 2.5e3


class ImplausibleSettingWarning(UserWarning):
    """An admissible deck value far outside what a run can use (the key is named)."""


@dataclass(frozen=True)
class Finding:
    """One implausible setting: the deck ``key`` and why (``message``, naming it)."""

    key: str
    message: str


def _material(model: Any) -> tuple[float, float] | None:
    """(E (Pa), rho (kg/m^3)) of the model's (main) material, or None."""
    m = getattr(model, "material", None)
    E, rho = getattr(m, "youngs_modulus", None), getattr(m, "density", None)
    if E is None or rho is None:
        return None
    E, rho = float(E), float(np.mean(np.asarray(rho, dtype=float)))
    return (E, rho) if E > 0 and rho > 0 else None


def _wave_speed(model: Any) -> float | None:
    """sqrt(E / rho) (m/s), or None without a material that has both."""
    er = _material(model)
    return math.sqrt(er[0] / er[1]) if er is not None else None


def _material_finding(model: Any) -> Finding | None:
    er = _material(model)
    if er is None:
        return None
    E, rho = er
    c = math.sqrt(E / rho)
    lo, hi = WAVE_SPEED_RANGE
    if lo <= c <= hi:
        return None
    off_e = abs(math.log10(E / _TYPICAL_E))
    off_rho = abs(math.log10(rho / _TYPICAL_RHO))
    key = "material.youngs_modulus" if off_e >= off_rho else "material.density"
    value = f"{E:.6g} Pa" if key.endswith("modulus") else f"{rho:.6g} kg/m^3"
    return Finding(
        key,
        f"{key} = {value} gives a wave speed sqrt(E / rho) = {c:.3g} m/s (E = {E:.6g} Pa, "
        f"rho = {rho:.6g} kg/m^3), outside the {lo:g} to {hi:g} m/s of solids; check the "
        "units: youngs_modulus in Pa, density in kg/m^3",
    )


def critical_damping(model: Any) -> tuple[float, float, float] | None:
    """(c_crit = 2 omega_1 (1/s), c (m/s), L (m)): critical mass damping of the first
    axial mode omega_1 = pi c / L of the body; None without a material. Under MPI, L is
    the whole body's extent too (``PointCloud.body_size``, known from set-up), so every
    rank judges as the serial run does without a collective call."""
    c = _wave_speed(model)
    if c is None:
        return None
    size = float(model.cloud.size)  # the whole body's (PointCloud.body_size under MPI)
    return 2.0 * math.pi * c / size, c, size


def _damping_finding(model: Any, step: StableStep) -> Finding | None:
    cd = step.damping
    crit = critical_damping(model) if cd > 0 else None
    if crit is None or not cd > crit[0]:
        return None
    c_crit, c, size = crit
    cut = (
        f"; it also cuts the stable step from {step.elastic:.3g} s to {step.value:.3g} s"
        if step.limited_by() == "solver.damping"
        else ""
    )
    return Finding(
        "solver.damping",
        f"solver.damping = {cd:.6g} 1/s is above critical damping, about {c_crit:.3g} 1/s "
        f"(2 omega_1 with omega_1 = pi c / L = {c_crit / 2:.3g} rad/s, the first axial mode: "
        f"c = {c:.4g} m/s, L = {size:.4g} m): every mode is over-damped, the body creeps "
        "to equilibrium more slowly than at critical damping and resists a prescribed "
        f"motion with a force rho c_d v{cut}; a value up to {c_crit:.2g} 1/s damps the first "
        "mode at most critically",
    )


def _viscosity_finding(model: Any, step: StableStep) -> Finding | None:
    if not step.xi_viscous > MAX_VISCOUS_RATIO:
        return None
    b1 = float(getattr(getattr(model, "viscosity", None), "linear", 0.0))
    return Finding(
        "material.viscosity.linear",
        f"material.viscosity.linear = {b1:.6g} gives the fastest mode a damping ratio of "
        f"{step.xi_viscous:.3g} (b1 of order 0.1 to 1 damps the spurious short waves, PD "
        "wave dispersion (n.d.)): it over-damps the short waves and cuts the stable step "
        f"from {step.elastic:.3g} s to {step.value:.3g} s",
    )


def _time_step_finding(solver: Any) -> Finding | None:
    dt, stable = solver.time_step, solver.stable_time_step
    if dt is None or not (math.isfinite(stable) and dt < MIN_STEP_FRACTION * stable):
        return None
    mantissa = dt / 10.0 ** math.floor(math.log10(dt))
    guess = mantissa * 10.0 ** math.floor(math.log10(stable))
    if guess > stable:
        guess /= 10.0
    n = stable / dt
    reach = (
        f"; its {solver.n_steps} steps reach t = {solver.n_steps * dt:.3g} s"
        if solver.n_steps
        else ""
    )
    return Finding(
        "solver.time_step",
        f"solver.time_step = {dt:.6g} s is {dt / stable:.3g} x the stable limit "
        f"{stable:.3g} s: {n:.3g} steps would be needed to advance by one stable step"
        f"{reach}; did you mean {guess:.3g} s (an exponent off by "
        f"{round(math.log10(guess / dt))})? Leave solver.time_step out to get "
        f"{solver.safety_factor} x the limit",
    )


def findings(solver: Any) -> list[Finding]:
    """The implausible settings of an explicit ``solver`` and its model, each with its
    deck key (empty for a plausible run)."""
    model = solver.model
    step = solver.stable_step
    found = [
        _material_finding(model),
        _damping_finding(model, step),
        _viscosity_finding(model, step),
        _time_step_finding(solver),
    ]
    return [f for f in found if f is not None]


def warn_implausible(solver: Any) -> None:
    """Issue each finding as an :class:`ImplausibleSettingWarning` (on rank 0 only)."""
    comm = getattr(solver.model, "comm", None)
    if comm is not None and comm.rank != 0:
        return
    for f in findings(solver):
        warnings.warn(f.message, ImplausibleSettingWarning, stacklevel=2)


def unstable_advice(solver: Any) -> str:
    """What to change after an instability: ``solver.time_step`` when the user set it;
    with the automatic step the implausible key(s), else the loads and boundary
    conditions."""
    found = findings(solver)
    if solver.time_step is not None:
        text = (
            f"Reduce solver.time_step (now {solver.dt:.3g} s, stable limit "
            f"{solver.stable_time_step:.3g} s) or check the loads"
        )
        return text + "".join(f"; also {f.message}" for f in found)
    text = (
        f"The time step was automatic ({solver.dt:.3g} s = {solver.safety_factor} x the "
        f"stable limit {solver.stable_time_step:.3g} s, which includes the damping and the "
        "linear viscosity), so it is not the cause: "
    )
    if found:
        return text + "; ".join(f.message for f in found)
    return text + (
        "check the loads and boundary conditions (a load or a prescribed motion the "
        "material cannot carry), or lower solver.safety_factor where contact or rigid "
        "bodies take part (their stiffness is not in the limit)"
    )
