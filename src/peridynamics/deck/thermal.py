"""Deck section ``thermal``: heat conduction (docs/theory_thermal.md): the thermal
properties of the body, its initial temperature and the thermal conditions on node
sets (prescribed temperature, heat flux, convection); run by ``solver.type: heat``
(transient) or ``heat_steady``."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field

from peridynamics.deck.thermal_coupling import coupling_errors, coupling_of
from peridynamics.deck.time_functions import ConstantTF, TimeFunctionSpec
from peridynamics.deck.types import Errors, Finite, NonNegFloat, PosFloat, Strict


class _OnSet(Strict):
    set: str


class MirrorPlane(Strict):
    """The boundary plane through ``point`` with ``normal`` (m) that a fictitious layer
    mirrors the body across."""

    point: list[Finite]
    normal: list[Finite]


class TemperatureBC(_OnSet):
    """T = value * f(t) (K) held on the set; with ``mirror`` the set is a fictitious
    layer beyond that plane, ``T = 2 T_b - T(reflection)`` (second-order accurate
    boundary temperature T_b on the plane; docs/theory_thermal.md)."""

    type: Literal["temperature"]
    value: Finite
    mirror: MirrorPlane | None = None
    time_function: TimeFunctionSpec = ConstantTF(type="constant")


class HeatFluxBC(_OnSet):
    """A heat flux into the body q = value * f(t) (W/m^2) spread over the set's layer
    (thickness ``layer_thickness``, or the set's extent along ``normal`` plus a spacing)."""

    type: Literal["heat_flux"]
    value: Finite
    normal: list[Finite] | None = None
    layer_thickness: PosFloat | None = None
    time_function: TimeFunctionSpec = ConstantTF(type="constant")


class ConvectionBC(_OnSet):
    """Convection h (T_inf f(t) - T) (W/m^2) over the set's layer: ``film`` h
    (W/(m^2 K)), ``ambient`` T_inf (K) times the time function."""

    type: Literal["convection"]
    film: NonNegFloat
    ambient: Finite
    normal: list[Finite] | None = None
    layer_thickness: PosFloat | None = None
    time_function: TimeFunctionSpec = ConstantTF(type="constant")


ThermalCondition = Annotated[TemperatureBC | HeatFluxBC | ConvectionBC, Field(discriminator="type")]


class Thermal(Strict):
    """Heat conduction: ``conductivity`` k (W/(m K)), ``specific_heat`` c_v
    (J/(kg K), with ``material.density``), ``initial_temperature`` (K), the
    ``correction`` of the micro-conductivity (``surface``: the energy method per bond;
    ``bulk``: one factor from the largest family, for bodies completed by mirrored
    layers; ``none``: the analytic value), and the ``conditions``. With a mechanical
    solver, thermal expansion: ``expansion`` alpha (1/K) from ``reference_temperature``
    (K, default the initial temperature), ``coupling`` ``staggered`` (the explicit
    solver conducts heat in sub-steps of each mechanical step) or ``prescribed`` (the
    temperature stays the initial one and the held ones, no conduction; the default of
    the quasi-static solvers); docs/theory_thermal.md."""

    conductivity: PosFloat | None = None
    specific_heat: PosFloat | None = None
    initial_temperature: Finite = 0.0
    correction: Literal["surface", "bulk", "none"] = "surface"
    conditions: list[ThermalCondition] = []
    expansion: Finite | None = None
    reference_temperature: Finite | None = None
    coupling: Literal["staggered", "prescribed"] | None = None


def thermal_errors(deck: Any, sets: set[str]) -> Errors:
    """A heat solver needs ``thermal`` and no mechanical conditions; ``thermal`` with a
    mechanical solver needs ``thermal.expansion`` (:func:`coupling_errors`); heat
    conduction needs the conductivity and the specific heat; known node sets and
    normals of the model's dimension."""
    errors: Errors = []
    heat = deck.solver.type in ("heat", "heat_steady")
    th = deck.thermal
    if heat and th is None:
        errors.append(("thermal", f"solver.type {deck.solver.type} needs a thermal section"))
    if th is not None and not heat:
        errors += coupling_errors(deck)
    if th is not None and (heat or coupling_of(deck) == "staggered"):
        for key in ("conductivity", "specific_heat"):
            if getattr(th, key) is None:
                errors.append((f"thermal.{key}", "heat conduction needs it: give a value"))
    if heat and deck.boundary_conditions:
        errors.append(
            (
                "boundary_conditions",
                "a heat solver does not step the mechanics: give thermal.conditions instead",
            )
        )
    for n, bc in enumerate(th.conditions if th is not None else []):
        path = f"thermal.conditions.{n}"
        if bc.set not in sets:
            errors.append((f"{path}.set", f"unknown node set {bc.set!r}; known: {sorted(sets)}"))
        mirror = getattr(bc, "mirror", None)
        vectors = {"normal": getattr(bc, "normal", None)}
        if mirror is not None:
            vectors = {"mirror.point": mirror.point, "mirror.normal": mirror.normal}
        for key, vec in vectors.items():
            if vec is not None and len(vec) != deck.dim:
                errors.append((f"{path}.{key}", f"needs {deck.dim} components"))
    return errors
