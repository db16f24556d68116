"""The deck's ``thermal`` section and ``solver.type: heat`` / ``heat_steady`` -> a heat
solver (:mod:`peridynamics.solvers.heat`); registered in
:data:`peridynamics.build.solvers.SOLVERS`. With a mechanical solver and
``thermal.expansion``: the force model's thermal-expansion variant
(:func:`install_expansion`) and the coupled solver (:func:`couple`,
:mod:`peridynamics.solvers.thermomechanical`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from peridynamics import deck as dk
from peridynamics.build.errors import SetupError
from peridynamics.build.loads import time_function
from peridynamics.deck.thermal_coupling import coupling_of
from peridynamics.evaluation import Evaluator
from peridynamics.evaluation.heat import HeatConduction
from peridynamics.families.pmb.material import fixed_poisson_ratio
from peridynamics.families.registry import FAMILIES
from peridynamics.geometry import PointCloud
from peridynamics.loading import thermal as th
from peridynamics.solvers.heat import HeatSolver, SteadyHeatSolver
from peridynamics.solvers.thermomechanical import ThermoMechanicalSolver


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
    if t.conductivity is None or t.specific_heat is None:
        raise SetupError("thermal.conductivity", "heat conduction needs it: give a value")
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


def _strain_per_kelvin(deck: dk.Deck, model: Evaluator) -> float:
    """alpha, or (1 + nu) alpha in plane strain (the in-plane free expansion of a body
    held at eps_zz = 0), nu the material's (bond-based: the fixed one)."""
    assert deck.thermal is not None and deck.thermal.expansion is not None
    alpha = float(deck.thermal.expansion)
    cloud = model.cloud
    if cloud.dim != 2 or cloud.plane != "strain":
        return alpha
    nu: Any = getattr(model.material, "poisson_ratio", None)
    if nu is None:
        nu = fixed_poisson_ratio(cloud.dim, cloud.plane)
    return (1.0 + float(nu)) * alpha


def install_expansion(deck: dk.Deck, model: Evaluator) -> None:
    """Replace the evaluator's force model by its thermal-expansion variant (the
    registry's ``Family.thermal``), configured from ``thermal``."""
    t = deck.thermal
    assert t is not None
    family = FAMILIES.get(getattr(deck.material, "model", ""))
    fm = model.force_model
    if family is None or family.thermal is None or type(fm) is not family.force_model:
        raise SetupError(
            "thermal.expansion", f"the force model {fm.name!r} has no thermal expansion"
        )
    variant: Any = family.thermal(fm)
    t0 = float(t.initial_temperature)
    ref = t0 if t.reference_temperature is None else float(t.reference_temperature)
    variant.configure(_strain_per_kelvin(deck, model), ref, t0)
    model.force_model = variant
    model.damage_law.bind(variant)


def couple(deck: dk.Deck, cloud: PointCloud, model: Evaluator, mechanical: Any) -> Any:
    """The mechanical solver with the temperature: conducted in sub-steps of each step
    (``thermal.coupling: staggered``) or held (``prescribed``)."""
    assert deck.thermal is not None
    temps, sources, conv = thermal_conditions(deck, cloud)
    t0 = deck.thermal.initial_temperature
    if coupling_of(deck) == "prescribed":
        held = HeatSolver.__new__(HeatSolver)  # the held temperatures only
        held.temperatures = temps
        return ThermoMechanicalSolver(mechanical, model.force_model, None, held)
    heat = HeatSolver(
        _conduction(deck, model), None, t0, temps, sources, conv, steps=1,
    )  # fmt: skip
    return ThermoMechanicalSolver(mechanical, model.force_model, heat)
