"""``damage.model: fatigue`` and ``solver.type: fatigue`` -> the remaining-life law and
the cycle-jumping solver (registry lines in :data:`~peridynamics.build.materials.DAMAGE_LAWS`
and :data:`~peridynamics.build.solvers.SOLVERS`)."""

from __future__ import annotations

import math
from typing import Any

from peridynamics import deck as dk
from peridynamics.bonds.bonds import Bonds
from peridynamics.build.errors import SetupError
from peridynamics.damage.fatigue import RemainingLife
from peridynamics.evaluation import Evaluator
from peridynamics.geometry import PointCloud
from peridynamics.solvers.base import Solver


def build_fatigue_law(
    dmg: dk.Damage, m: Any, material: Any, cloud: PointCloud, bonds: Bonds, no_fail: Any
) -> RemainingLife:
    """The remaining-life criterion of ``damage.fatigue`` (A1 given or from the S-N
    point)."""
    f = dmg.fatigue
    assert f is not None  # validated: model fatigue has its section
    return RemainingLife(
        a1=f.phase_one_a, m1=f.m1, a2=f.a2, m2=f.m2,
        phase_two_damage=f.phase_two_damage, no_fail=no_fail,
    )  # fmt: skip


def build_fatigue_solver(
    deck: dk.Deck, cloud: PointCloud, model: Evaluator, body: list, kin: list, init: list
) -> Solver:
    """The cycle-jumping solver from ``solver: {type: fatigue, ...}`` (every key of the
    section is a keyword of :class:`~peridynamics.solvers.fatigue.FatigueSolver`)."""
    from peridynamics.solvers.direct import direct_backend
    from peridynamics.solvers.fatigue import FatigueSolver

    if init:
        raise ValueError("initial velocities have no meaning in a fatigue (static) run")
    try:
        direct_backend()
    except ValueError as exc:
        raise SetupError("solver.linear_solver", str(exc)) from None
    options = deck.solver.model_dump(exclude={"type"})
    if options["max_increment"] is None:
        options["max_increment"] = math.inf
    return FatigueSolver(model, constraints=kin, **options)
