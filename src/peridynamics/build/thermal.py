"""The deck's ``thermal`` section and ``solver.type: heat`` / ``heat_steady`` -> a heat
solver (:mod:`peridynamics.solvers.heat`); registered in
:data:`peridynamics.build.solvers.SOLVERS`."""

from __future__ import annotations

from typing import Any

import numpy as np

from peridynamics import deck as dk
from peridynamics.build.errors import SetupError
from peridynamics.build.loads import time_function
from peridynamics.evaluation import Evaluator
from peridynamics.evaluation.heat import HeatConduction
from peridynamics.geometry import PointCloud
from peridynamics.loading import thermal as th
from peridynamics.solvers.heat import HeatSolver, SteadyHeatSolver


def _held(c: Any, n: int, nodes: Any, cloud: PointCloud, f: Any) -> Any:
    """A ``temperature`` condition: constant on its set, or a mirrored layer."""
    if c.mirror is None:
        return th.PrescribedTemperature(nodes, float(c.value), f)
    p, nn = (np.asarray(v, dtype=float) for v in (c.mirror.point, c.mirror.normal))
    try:
        mirror = th.mirror_points(nodes, cloud.x, cloud.spacing, p, nn)
    except ValueError as exc:
        raise SetupError(f"thermal.conditions.{n}.mirror", str(exc)) from None
    return th.MirroredTemperature(nodes, mirror, float(c.value), f)


def thermal_conditions(
    spec: dk.Deck, cloud: PointCloud
) -> tuple[list[Any], list[th.HeatSource], list[th.Convection]]:
    """``thermal.conditions`` -> (held temperatures, flux sources, convection)."""
    assert spec.thermal is not None
    temps: list[Any] = []
    sources: list[th.HeatSource] = []
    conv: list[th.Convection] = []
    for n, c in enumerate(spec.thermal.conditions):
        nodes = cloud.node_set(c.set)
        if len(nodes) == 0:
            raise SetupError(f"thermal.conditions.{n}.set", f"node set {c.set!r} is empty")
        f = time_function(c.time_function)
        if c.type == "temperature":
            temps.append(_held(c, n, nodes, cloud, f))
            continue
        normal = None if c.normal is None else np.asarray(c.normal, dtype=float)
        geo: dict[str, Any] = dict(normal=normal, layer_thickness=c.layer_thickness, function=f)
        try:
            if c.type == "heat_flux":
                sources.append(th.flux_as_source(nodes, c.value, cloud.x, cloud.spacing, **geo))
            else:
                conv.append(
                    th.convection_on_layer(nodes, c.film, c.ambient, cloud.x, cloud.spacing, **geo)
                )
        except ValueError as exc:
            raise SetupError(f"thermal.conditions.{n}", str(exc)) from None
    return temps, sources, conv


def _conduction(deck: dk.Deck, model: Evaluator) -> HeatConduction:
    """The conduction operator on the model's bonds (density from ``material``)."""
    t = deck.thermal
    if t is None:
        raise SetupError("thermal", f"solver.type {deck.solver.type} needs a thermal section")
    density = getattr(deck.material, "density", None)
    if density is None:
        raise SetupError("material.density", "heat conduction needs the density")
    return HeatConduction(
        model.cloud,
        model.bonds,
        t.conductivity,
        float(density),
        t.specific_heat,
        correction=t.correction,
    )


def build_heat(
    deck: dk.Deck, cloud: PointCloud, model: Evaluator, body: list, kin: list, init: list
) -> Any:
    """Transient conduction from ``solver: {type: heat, ...}``."""
    s = deck.solver
    assert isinstance(s, dk.HeatSolverSpec) and deck.thermal is not None
    temps, sources, conv = thermal_conditions(deck, cloud)
    return HeatSolver(
        _conduction(deck, model),
        model,
        deck.thermal.initial_temperature,
        temps,
        sources,
        conv,
        time_step=s.time_step,
        safety_factor=s.safety_factor,
        end_time=s.end_time,
        steps=s.steps,
        allow_unstable=s.allow_unstable,
    )


def build_heat_steady(
    deck: dk.Deck, cloud: PointCloud, model: Evaluator, body: list, kin: list, init: list
) -> Any:
    """The steady state from ``solver: {type: heat_steady}``."""
    assert deck.thermal is not None
    temps, sources, conv = thermal_conditions(deck, cloud)
    return SteadyHeatSolver(
        _conduction(deck, model), model, deck.thermal.initial_temperature, temps, sources, conv
    )
