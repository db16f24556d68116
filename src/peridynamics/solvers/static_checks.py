"""Argument and model checks of :class:`peridynamics.solvers.static.StaticSolver`: each
raises ValueError with the deck key in brackets where there is one."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.evaluation import Evaluator
from peridynamics.loading.conditions import Kinematic, PrescribedVelocity
from peridynamics.solvers import linear as lin
from peridynamics.solvers.explicit import SimulationUnstable
from peridynamics.state import State

__all__ = ["check_arguments", "check_damage", "check_finite"]


def _check_int(name: str, value: Any, low: int) -> None:
    if int(value) != value or value < low:
        raise ValueError(f"solver.{name} must be an integer >= {low}, got {value}")


def check_arguments(
    constraints: Sequence[Kinematic],
    load_steps: int,
    tolerance: float,
    max_iterations: int,
    max_cutbacks: int,
    load_time: float,
    linear_solver: str,
    max_solves: int,
) -> None:
    """ValueError for an argument of :class:`StaticSolver` out of its range."""
    _check_int("load_steps", load_steps, 1)
    _check_int("max_iterations", max_iterations, 1)
    _check_int("max_cutbacks", max_cutbacks, 0)
    _check_int("max_solves", max_solves, 1)
    if not 0.0 < tolerance < 1.0:
        raise ValueError(f"solver.tolerance must be in (0, 1), got {tolerance}")
    if not (load_time > 0 and math.isfinite(load_time)):
        raise ValueError(f"solver.load_time must be a finite value > 0, got {load_time}")
    lin.choose(linear_solver, 1)  # validates the name
    for c in constraints:
        if isinstance(c, PrescribedVelocity):
            raise ValueError(
                "a prescribed velocity has no meaning in a static run; prescribe the "
                "displacement instead"
            )


def check_damage(model: Evaluator) -> None:
    """ValueError for a damage model the static solver cannot run."""
    law = model.damage_law
    if getattr(law, "name", "") == "plastic_strain":
        raise ValueError(
            "[damage.model] 'plastic_strain' breaks bonds in explicit and adr runs; the "
            "static solver breaks them by critical stretch only: use solver.type adr"
        )
    if math.isfinite(getattr(law, "tensile_strength", math.inf)):
        raise ValueError(
            "[damage.tensile_strength] the principal-stress failure criterion breaks "
            "bonds in explicit and adr runs only; the static solver breaks bonds by "
            "critical stretch between solves: remove tensile_strength (with "
            "damage.model: critical_stretch and fracture_energy or critical_stretch) "
            "or use solver.type: adr"
        )
    if getattr(law, "name", "") == "bodies" and law.active:
        raise ValueError(
            "[bodies] the static solver breaks bonds by one critical-stretch law; the "
            "bonds of several bodies and their interfaces would never break in it: use "
            "solver.type: adr (or explicit), or make every body and interface unbreakable "
            "(no critical_stretch or fracture_energy) for a linear elastic solve"
        )
    if getattr(model, "softening", None) is not None:
        raise ValueError(
            "[damage.sed_softening] the static solver does not soften bonds (it breaks "
            "them by critical stretch between solves): use solver.type: adr, or remove "
            "sed_softening"
        )


def check_finite(
    q: NDArray[np.float64], x: NDArray[np.float64], s: State, last_good: State | None
) -> None:
    """Raise :class:`SimulationUnstable` when the dofs ``q`` (n, width) of the solution
    ``s`` are not all finite (``x``: the points' positions (n, dim), m; ``last_good``:
    the state to report)."""
    bad = ~np.isfinite(q).all(axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        coords = x[k].tolist()
        raise SimulationUnstable(
            f"the static solution is not finite at point {k} ({coords}) after solve "
            f"{s.step}: check the constraints (rigid-body motion must be prevented)",
            step=s.step,
            time=s.t,
            point=k,
            coordinates=coords,
            last_good=last_good,
        )
