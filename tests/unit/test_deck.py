"""The YAML deck schema: malformed decks are rejected with the key path and a hint.

Every malformed deck below starts from one valid 2-D deck (``base_deck``) and changes one
thing; ``parse_deck`` must raise ``DeckError`` whose message names the exact key path of
the problem (``material.youngs_modulus: ...``) and says what is allowed.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import yaml

from peridynamics.build.cloud import build_cloud
from peridynamics.build.errors import SetupError
from peridynamics.deck import (
    Deck,
    DeckError,
    apply_overrides,
    load_deck,
    parse_deck,
)

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*/deck.yaml"))

DELETE = object()


def base_deck() -> dict[str, Any]:
    """A small valid 2-D deck that exercises most sections (200 points)."""
    return {
        "name": "unit",
        "description": "a valid deck to mutate",
        "geometry": {"type": "rectangle", "size": [0.01, 0.005], "thickness": 1.0e-3},
        "discretisation": {"spacing": 5.0e-4, "horizon_factor": 3.015},
        "material": {"youngs_modulus": 70.0e9, "density": 2700.0},
        "damage": {"critical_stretch": 0.01, "no_fail": ["bottom"]},
        "node_sets": {
            "top": {"box": {"min": [-math.inf, 0.00475], "max": [math.inf, math.inf]}},
            "bottom": {"box": {"min": [-math.inf, -math.inf], "max": [math.inf, 0.00025]}},
            "gauge": {"point": [0.005, 0.0025]},
        },
        "precracks": [{"points": [[0.0, 0.0025], [0.004, 0.0025]]}],
        "boundary_conditions": [
            {"type": "fixed", "set": "bottom"},
            {
                "type": "traction",
                "set": "top",
                "value": [0.0, 1.0e6],
                "time_function": {"type": "ramp", "end": 1.0e-6},
            },
        ],
        "solver": {"end_time": 2.0e-6},
        "output": {
            "history_every": 5,
            "probes": [
                {"name": "top_uy", "quantity": "displacement", "set": "top", "component": "y"}
            ],
            "crack_tip": {"origin": [0.004, 0.0025], "direction": [1.0, 0.0]},
        },
    }


def base_deck_3d() -> dict[str, Any]:
    """A small valid 3-D deck."""
    return {
        "name": "unit3d",
        "geometry": {"type": "box", "size": [0.004, 0.004, 0.004]},
        "discretisation": {"spacing": 1.0e-3, "horizon_factor": 3.015},
        "material": {"youngs_modulus": 70.0e9, "density": 2700.0},
        "node_sets": {
            "core": {
                "cylinder": {
                    "base": [0.002, 0.002, 0.0],
                    "axis": [0.0, 0.0, 1.0],
                    "radius": 0.001,
                    "length": 0.004,
                }
            }
        },
        "solver": {"steps": 2},
    }


def _walk(d: Any, path: str) -> tuple[Any, Any]:
    *parents, last = path.split(".")
    for p in parents:
        d = d[int(p)] if isinstance(d, list) else d[p]
    return d, (int(last) if isinstance(d, list) else last)


def setp(path: str, value: Any) -> Callable[[dict], None]:
    """A mutation: set (or with DELETE remove) the value at a dotted key path."""

    def mutate(deck: dict) -> None:
        parent, key = _walk(deck, path)
        if value is DELETE:
            del parent[key]
        else:
            parent[key] = copy.deepcopy(value)

    return mutate


def chain(*mutations: Callable[[dict], None]) -> Callable[[dict], None]:
    """Several mutations applied in order."""

    def mutate(deck: dict) -> None:
        for m in mutations:
            m(deck)

    return mutate


def append(path: str, value: Any) -> Callable[[dict], None]:
    """A mutation: append to the list at a dotted key path."""

    def mutate(deck: dict) -> None:
        parent, key = _walk(deck, path)
        parent[key].append(copy.deepcopy(value))

    return mutate


def _bc(**kw: Any) -> dict:
    return {"set": "top", **kw}


def _tf(**kw: Any) -> Callable[[dict], None]:
    return setp("boundary_conditions.1.time_function", kw)


NAN, INF = math.nan, math.inf

# (id, mutation, expected key path, hint of what is allowed)
MALFORMED = [
    # -- unknown keys at several depths
    (
        "unknown-top-level-key",
        setp("solver_options", {"steps": 3}),
        "solver_options",
        "unknown key",
    ),
    ("unknown-geometry-key", setp("geometry.thikness", 1.0e-3), "geometry.thikness", "unknown key"),
    (
        "unknown-region-key",
        setp("node_sets.top.box.centre", [0.0, 0.0]),
        "node_sets.top.box.centre",
        "unknown key",
    ),
    (
        "unknown-region-kind",
        setp("node_sets.gauge", {"dot": [0.0, 0.0]}),
        "node_sets.gauge.dot",
        "unknown key",
    ),
    (
        "unknown-bc-key",
        setp("boundary_conditions.1.valu", [0.0, 1.0]),
        "boundary_conditions.1.valu",
        "unknown key",
    ),
    (
        "unknown-time-function-key",
        setp("boundary_conditions.1.time_function.stop", 1.0),
        "boundary_conditions.1.time_function.stop",
        "unknown key",
    ),
    ("unknown-probe-key", setp("output.probes.0.comp", "y"), "output.probes.0.comp", "unknown key"),
    ("key-of-other-geometry-type", setp("geometry.length", 0.01), "geometry.length", "unknown key"),
    # -- wrong types
    (
        "E-not-a-number",
        setp("material.youngs_modulus", "stiff"),
        "material.youngs_modulus",
        "valid number",
    ),
    (
        "steps-fractional",
        chain(setp("solver.end_time", DELETE), setp("solver.steps", 2.5)),
        "solver.steps",
        "valid integer",
    ),
    ("section-is-scalar", setp("material", 5), "material", "valid dictionary"),
    (
        "bool-not-boolean",
        setp("discretisation.surface_correction", "maybe"),
        "discretisation.surface_correction",
        "valid boolean",
    ),
    ("name-not-string", setp("name", 5), "name", "valid string"),
    (
        "bcs-not-a-list",
        setp("boundary_conditions", {"type": "fixed", "set": "top"}),
        "boundary_conditions",
        "valid list",
    ),
    # -- material ranges
    ("E-zero", setp("material.youngs_modulus", 0.0), "material.youngs_modulus", "greater than 0"),
    (
        "E-negative",
        setp("material.youngs_modulus", -70.0e9),
        "material.youngs_modulus",
        "greater than 0",
    ),
    ("density-zero", setp("material.density", 0.0), "material.density", "greater than 0"),
    ("density-negative", setp("material.density", -1.0), "material.density", "greater than 0"),
    (
        "nu-plane-stress",
        setp("material.poisson_ratio", 0.25),
        "material.poisson_ratio",
        "nu = 0.333333",
    ),
    (
        "nu-plane-strain",
        chain(setp("geometry.plane", "strain"), setp("material.poisson_ratio", 1.0 / 3.0)),
        "material.poisson_ratio",
        "nu = 0.25",
    ),
    (
        "nu-out-of-range",
        setp("material.poisson_ratio", 0.5),
        "material.poisson_ratio",
        "less than 0.5",
    ),
    ("material-model", setp("material.model", "elastoplastic"), "material.model", "lps"),
    # -- discretisation
    (
        "horizon-below-spacing",
        setp("discretisation", {"spacing": 1.0e-3, "horizon": 5.0e-4}),
        "discretisation.horizon",
        "horizon >= spacing",
    ),
    (
        "horizon-and-factor",
        setp("discretisation.horizon", 1.5e-3),
        "discretisation.horizon",
        "exactly one of horizon",
    ),
    (
        "horizon-missing",
        setp("discretisation.horizon_factor", DELETE),
        "discretisation.horizon",
        "exactly one of horizon",
    ),
    (
        "horizon-factor-below-1",
        setp("discretisation.horizon_factor", 0.5),
        "discretisation.horizon_factor",
        "greater than or equal to 1",
    ),
    (
        "spacing-zero",
        setp("discretisation.spacing", 0.0),
        "discretisation.spacing",
        "greater than 0",
    ),
    (
        "partial-volume",
        setp("discretisation.partial_volume", "full"),
        "discretisation.partial_volume",
        "'truncated', 'extended' or 'none'",
    ),
    # -- solver
    ("end-time-zero", setp("solver.end_time", 0.0), "solver.end_time", "greater than 0"),
    ("end-time-negative", setp("solver.end_time", -1.0e-6), "solver.end_time", "greater than 0"),
    ("time-step-negative", setp("solver.time_step", -1.0e-9), "solver.time_step", "greater than 0"),
    ("end-time-and-steps", setp("solver.steps", 10), "solver.end_time", "exactly one of end_time"),
    (
        "neither-end-time-nor-steps",
        setp("solver.end_time", DELETE),
        "solver.end_time",
        "exactly one of end_time",
    ),
    (
        "safety-factor-above-1",
        setp("solver.safety_factor", 1.5),
        "solver.safety_factor",
        "less than or equal to 1",
    ),
    (
        "integrator",
        setp("solver.integrator", "rk4"),
        "solver.integrator",
        "'velocity_verlet' or 'central_difference'",
    ),
    # -- time functions
    (
        "ramp-start-negative",
        _tf(type="ramp", start=-1.0e-6, end=1.0e-6),
        "boundary_conditions.1.time_function.start",
        "greater than or equal to 0",
    ),
    (
        "ramp-end-before-start",
        _tf(type="ramp", start=2.0e-6, end=1.0e-6),
        "boundary_conditions.1.time_function.end",
        "must be > start",
    ),
    (
        "ramp-end-equals-start",
        _tf(type="ramp", start=1.0e-6, end=1.0e-6),
        "boundary_conditions.1.time_function.end",
        "must be > start",
    ),
    (
        "ramp-end-missing",
        _tf(type="ramp"),
        "boundary_conditions.1.time_function.end",
        "required key is missing",
    ),
    (
        "pulse-rise-equals-duration",
        _tf(type="triangular_pulse", rise_time=2.0e-6, duration=2.0e-6),
        "boundary_conditions.1.time_function.rise_time",
        "must be < duration",
    ),
    (
        "pulse-rise-after-duration",
        _tf(type="triangular_pulse", rise_time=3.0e-6, duration=2.0e-6),
        "boundary_conditions.1.time_function.rise_time",
        "must be < duration",
    ),
    (
        "table-times-not-increasing",
        _tf(type="table", times=[0.0, 2.0e-6, 1.0e-6], values=[0.0, 1.0, 0.5]),
        "boundary_conditions.1.time_function.times",
        "increase strictly",
    ),
    (
        "table-times-repeated",
        _tf(type="table", times=[0.0, 1.0e-6, 1.0e-6], values=[0.0, 1.0, 0.5]),
        "boundary_conditions.1.time_function.times",
        "increase strictly",
    ),
    (
        "table-lengths-differ",
        _tf(type="table", times=[0.0, 1.0e-6, 2.0e-6], values=[0.0, 1.0]),
        "boundary_conditions.1.time_function.values",
        "same length",
    ),
    (
        "time-function-type",
        _tf(type="sine"),
        "boundary_conditions.1.time_function.type",
        "constant, ramp, table, triangular_pulse",
    ),
    # -- missing required keys
    ("missing-name", setp("name", DELETE), "name", "required key is missing"),
    ("missing-geometry", setp("geometry", DELETE), "geometry", "required key is missing"),
    ("missing-solver", setp("solver", DELETE), "solver", "required key is missing"),
    (
        "missing-E",
        setp("material.youngs_modulus", DELETE),
        "material.youngs_modulus",
        "required key is missing",
    ),
    ("missing-size", setp("geometry.size", DELETE), "geometry.size", "required key is missing"),
    (
        "missing-bc-set",
        setp("boundary_conditions.0.set", DELETE),
        "boundary_conditions.0.set",
        "required key is missing",
    ),
    (
        "missing-probe-quantity",
        setp("output.probes.0.quantity", DELETE),
        "output.probes.0.quantity",
        "required key is missing",
    ),
    (
        "missing-pressure-normal",
        setp("boundary_conditions.1", _bc(type="pressure", value=1.0e6)),
        "boundary_conditions.1.normal",
        "give exactly one of normal",
    ),
    (
        "pressure-normal-and-center",
        setp(
            "boundary_conditions.1",
            _bc(type="pressure", value=1.0e6, normal=[1.0, 0.0], center=[0.0, 0.0]),
        ),
        "boundary_conditions.1.normal",
        "give exactly one of normal",
    ),
    (
        "pressure-without-value",
        setp("boundary_conditions.1", _bc(type="pressure", normal=[1.0, 0.0])),
        "boundary_conditions.1.value",
        "required unless the time function is a blast",
    ),
    (
        "negative-viscosity",
        setp("material.viscosity", {"linear": -0.5}),
        "material.viscosity.linear",
        "greater than or equal to 0",
    ),
    (
        "blast-negative-charge",
        setp(
            "boundary_conditions.1",
            _bc(
                type="pressure",
                normal=[1.0, 0.0],
                time_function={"type": "blast", "charge_kg": -1.0, "standoff_m": 0.5},
            ),
        ),
        "boundary_conditions.1.time_function.blast.charge_kg",
        "greater than 0",
    ),
    # -- unknown node-set references
    (
        "bc-unknown-set",
        setp("boundary_conditions.0.set", "bottm"),
        "boundary_conditions.0.set",
        "known: ['all', 'bottom', 'gauge', 'top']",
    ),
    (
        "probe-unknown-set",
        setp("output.probes.0.set", "nowhere"),
        "output.probes.0.set",
        "unknown node set 'nowhere'",
    ),
    (
        "no-fail-unknown-set",
        setp("damage.no_fail", ["bottom", "edges"]),
        "damage.no_fail.1",
        "unknown node set 'edges'",
    ),
    (
        "region-unknown-set",
        setp("node_sets.both", {"any_of": [{"set": "top"}, {"set": "btm"}]}),
        "node_sets.both.any_of.1.set",
        "unknown node set 'btm'",
    ),
    (
        "region-refers-to-itself",
        setp("node_sets.loop", {"not": {"set": "loop"}}),
        "node_sets.loop.not.set",
        "unknown node set 'loop'",
    ),
    (
        "node-set-named-all",
        setp("node_sets.all", {"everywhere": True}),
        "node_sets.all",
        "built in",
    ),
    # -- vector lengths and components against the dimension
    (
        "bc-value-3-components",
        setp("boundary_conditions.1.value", [0.0, 1.0e6, 0.0]),
        "boundary_conditions.1.value",
        "needs 2 components for a 2-D model",
    ),
    (
        "initial-velocity-1-component",
        append("boundary_conditions", _bc(type="initial_velocity", value=[1.0])),
        "boundary_conditions.2.value",
        "needs 2 components",
    ),
    (
        "box-3-components",
        setp("node_sets.top.box", {"min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 1.0]}),
        "node_sets.top.box.min",
        "needs 2 components",
    ),
    (
        "box-min-max-lengths-differ",
        setp("node_sets.top.box.min", [0.0, 0.0, 0.0]),
        "node_sets.top.box.max",
        "same number of components",
    ),
    (
        "point-1-component",
        setp("node_sets.gauge.point", [0.005]),
        "node_sets.gauge.point",
        "needs 2 components",
    ),
    (
        "crack-point-3-components",
        setp("precracks.0.points.1", [0.004, 0.0025, 0.0]),
        "precracks.0.points.1",
        "needs 2 components",
    ),
    (
        "crack-tip-origin-length",
        setp("output.crack_tip.origin", [0.004]),
        "output.crack_tip.origin",
        "needs 2 components",
    ),
    (
        "hole-center-length",
        setp("geometry.holes", [{"circle": {"center": [0.0, 0.0, 0.0], "radius": 1.0e-3}}]),
        "geometry.holes.0.circle.center",
        "needs 2 components",
    ),
    (
        "displacement-z-in-2d",
        append("boundary_conditions", _bc(type="displacement", components={"z": 1.0e-6})),
        "boundary_conditions.2.components.z",
        "'z' does not exist in 2-D",
    ),
    (
        "fixed-z-in-2d",
        setp("boundary_conditions.0.components", ["x", "z"]),
        "boundary_conditions.0.components.z",
        "does not exist in 2-D",
    ),
    (
        "velocity-component-w",
        append("boundary_conditions", _bc(type="velocity", components={"w": 1.0})),
        "boundary_conditions.2.components.w",
        "'x', 'y' or 'z'",
    ),
    (
        "probe-component-z-in-2d",
        setp("output.probes.0.component", "z"),
        "output.probes.0.component",
        "does not exist in 2-D",
    ),
    (
        "cylinder-region-in-2d",
        setp(
            "node_sets.gauge",
            {
                "cylinder": {
                    "base": [0.0, 0.0, 0.0],
                    "axis": [0.0, 0.0, 1.0],
                    "radius": 1.0e-3,
                    "length": 1.0e-3,
                }
            },
        ),
        "node_sets.gauge.cylinder",
        "cylinder regions are 3-D",
    ),
    # -- damage
    (
        "critical-stretch-and-fracture-energy",
        setp("damage.fracture_energy", 204.0),
        "damage.critical_stretch",
        "exactly one of critical_stretch (s0) or fracture_energy",
    ),
    (
        "neither-critical-stretch-nor-energy",
        setp("damage.critical_stretch", DELETE),
        "damage.critical_stretch",
        "exactly one of critical_stretch (s0) or fracture_energy",
    ),
    (
        "critical-stretch-negative",
        setp("damage.critical_stretch", -0.01),
        "damage.critical_stretch",
        "greater than 0",
    ),
    (
        "model-none-with-stretch",
        setp("damage.model", "none"),
        "damage.model",
        "takes neither critical_stretch nor fracture_energy",
    ),
    # -- regions
    (
        "region-with-two-kinds",
        setp("node_sets.gauge.ball", {"center": [0.0, 0.0], "radius": 1.0e-3}),
        "node_sets.gauge",
        "exactly one of: box, ball, circle",
    ),
    ("region-with-no-kind", setp("node_sets.gauge", {}), "node_sets.gauge", "got none"),
    (
        "box-min-above-max",
        setp("node_sets.top.box", {"min": [0.0, 0.004], "max": [0.01, 0.003]}),
        "node_sets.top.box.max",
        "must be <= max",
    ),
    (
        "ball-radius-zero",
        setp("node_sets.gauge", {"ball": {"center": [0.0, 0.0], "radius": 0.0}}),
        "node_sets.gauge.ball.radius",
        "greater than 0",
    ),
    (
        "polygon-two-vertices",
        setp("node_sets.gauge", {"polygon": {"vertices": [[0, 0], [1, 1]]}}),
        "node_sets.gauge.polygon.vertices",
        "at least 3 items",
    ),
    (
        "half-space-zero-normal",
        setp("node_sets.gauge", {"half_space": {"point": [0.0, 0.0], "normal": [0.0, 0.0]}}),
        "node_sets.gauge.half_space.normal",
        "non-zero",
    ),
    (
        "everywhere-false",
        setp("node_sets.gauge", {"everywhere": False}),
        "node_sets.gauge.everywhere",
        "should be True",
    ),
    (
        "all-of-empty",
        setp("node_sets.gauge", {"all_of": []}),
        "node_sets.gauge.all_of",
        "at least 1 item",
    ),
    # -- geometry
    (
        "geometry-type-sphere",
        setp("geometry.type", "sphere"),
        "geometry.type",
        "bar, rectangle, box, cylinder, mesh",
    ),
    (
        "geometry-size-3-items",
        setp("geometry.size", [0.01, 0.005, 0.001]),
        "geometry.size",
        "at most 2 items",
    ),
    (
        "geometry-size-negative",
        setp("geometry.size.1", -0.005),
        "geometry.size.1",
        "greater than 0",
    ),
    (
        "geometry-plane",
        setp("geometry.plane", "axisymmetric"),
        "geometry.plane",
        "'stress' or 'strain'",
    ),
    # -- pre-cracks
    (
        "precrack-3-points-in-2d",
        append("precracks.0.points", [0.004, 0.003]),
        "precracks.0.points",
        "a 2-D crack is 2 points",
    ),
    (
        "precrack-1-point",
        setp("precracks.0.points", [[0.0, 0.0025]]),
        "precracks.0.points",
        "at least 2 items",
    ),
    (
        "precrack-4-points",
        setp("precracks.0.points", [[0, 0], [1, 0], [1, 1], [0, 1]]),
        "precracks.0.points",
        "at most 3 items",
    ),
    (
        "precrack-in-1d",
        chain(
            setp("geometry", {"type": "bar", "length": 0.01}),
            setp("node_sets", {}),
            setp("damage.no_fail", []),
            setp("boundary_conditions", []),
            setp("output", {}),
            setp("precracks", [{"points": [[0.0], [0.005]]}]),
        ),
        "precracks.0",
        "need a 2-D or 3-D model",
    ),
    # -- boundary conditions and output
    (
        "bc-type",
        setp("boundary_conditions.0.type", "spring"),
        "boundary_conditions.0.type",
        "displacement, velocity, fixed, initial_velocity, body_force",
    ),
    (
        "displacement-no-components",
        append("boundary_conditions", _bc(type="displacement", components={})),
        "boundary_conditions.2.components",
        "at least 1 item",
    ),
    (
        "zero-traction-without-normal",
        setp("boundary_conditions.1.value", [0.0, 0.0]),
        "boundary_conditions.1.normal",
        "give a normal",
    ),
    (
        "layer-thickness-zero",
        setp("boundary_conditions.1.layer_thickness", 0.0),
        "boundary_conditions.1.layer_thickness",
        "greater than 0",
    ),
    (
        "duplicate-probe-names",
        append("output.probes", {"name": "top_uy", "quantity": "damage", "set": "all"}),
        "output.probes",
        "probe names must be unique; repeated: ['top_uy']",
    ),
    (
        "probe-quantity",
        setp("output.probes.0.quantity", "vorticity"),
        "output.probes.0.quantity",
        "'displacement', 'velocity', 'force_density', 'reaction_force'",
    ),
    (
        "probe-empty-name",
        setp("output.probes.0.name", ""),
        "output.probes.0.name",
        "at least 1 character",
    ),
    (
        "history-every-zero",
        setp("output.history_every", 0),
        "output.history_every",
        "greater than 0",
    ),
    (
        "vtk-every-negative",
        setp("output.vtk_every", -1),
        "output.vtk_every",
        "greater than or equal to 0",
    ),
    (
        "output-field",
        setp("output.fields", ["damage", "vorticity"]),
        "output.fields.1",
        "'principal_direction' or 'temperature'",
    ),
    (
        "crack-tip-threshold-1",
        setp("output.crack_tip.damage_threshold", 1.0),
        "output.crack_tip.damage_threshold",
        "less than 1",
    ),
    (
        "plot-kind",
        setp("output.plot", "contour"),
        "output.plot",
        "'auto', 'none', one of 'damage', 'deformed', 'probes'",
    ),
    # -- NaN / inf in finite fields
    ("E-nan", setp("material.youngs_modulus", NAN), "material.youngs_modulus", "finite number"),
    ("E-inf", setp("material.youngs_modulus", INF), "material.youngs_modulus", "finite number"),
    ("density-inf", setp("material.density", INF), "material.density", "finite number"),
    ("spacing-inf", setp("discretisation.spacing", INF), "discretisation.spacing", "finite number"),
    ("origin-inf", setp("geometry.origin", [-INF, 0.0]), "geometry.origin.0", "finite number"),
    (
        "bc-value-nan",
        setp("boundary_conditions.1.value", [0.0, NAN]),
        "boundary_conditions.1.value.1",
        "finite number",
    ),
    (
        "ramp-end-inf",
        _tf(type="ramp", end=INF),
        "boundary_conditions.1.time_function.end",
        "finite number",
    ),
    (
        "box-nan",
        setp("node_sets.top.box.max", [NAN, INF]),
        "node_sets.top.box",
        "NaN is not allowed",
    ),
    (
        "point-nan",
        setp("node_sets.gauge.point", [NAN, 0.0]),
        "node_sets.gauge.point.0",
        "finite number",
    ),
    (
        "crack-point-inf",
        setp("precracks.0.points.0", [0.0, INF]),
        "precracks.0.points.0.1",
        "finite number",
    ),
]


@pytest.mark.parametrize(
    ("mutate", "path", "hint"), [pytest.param(m, p, h, id=i) for i, m, p, h in MALFORMED]
)
def test_malformed_deck_names_key_path(
    mutate: Callable[[dict], None], path: str, hint: str
) -> None:
    data = base_deck()
    mutate(data)
    with pytest.raises(DeckError) as info:
        parse_deck(data)
    text = str(info.value)
    assert text.startswith("invalid deck:")
    assert f"\n  {path}: " in text, f"expected key path {path!r} in:\n{text}"
    messages = [msg for p, msg in info.value.errors if p == path]
    assert any(hint in msg for msg in messages), f"expected hint {hint!r} in {messages}"


def test_enough_malformed_cases() -> None:
    ids = [case[0] for case in MALFORMED]
    assert len(ids) == len(set(ids)) >= 35


# ------------------------------------------------------------------------- valid decks
def test_base_deck_is_valid() -> None:
    deck = parse_deck(base_deck())
    assert isinstance(deck, Deck)
    assert deck.dim == 2
    assert deck.discretisation.delta == pytest.approx(3.015 * 5.0e-4)
    assert deck.damage.model == "critical_stretch"
    assert deck.boundary_conditions[1].time_function.type == "ramp"


def test_base_3d_deck_is_valid() -> None:
    deck = parse_deck(base_deck_3d())
    assert deck.dim == 3
    assert deck.node_sets["core"].kind() == "cylinder"


def test_defaults() -> None:
    data = base_deck()
    for key in ("description", "damage", "node_sets", "precracks", "boundary_conditions", "output"):
        del data[key]
    deck = parse_deck(data)
    assert deck.description == ""
    assert deck.damage.model == "none"
    assert deck.node_sets == {} and deck.precracks == [] and deck.boundary_conditions == []
    assert (
        deck.output.vtk_every == 0 and deck.output.history_every is None
    )  # 10 (dynamics), 1 (static)
    assert deck.output.plot == "auto" and deck.output.probes == []
    assert deck.discretisation.partial_volume == "truncated"
    assert deck.material.model == "pmb" and deck.material.micromodulus_profile == "constant"
    assert deck.solver.integrator == "velocity_verlet" and deck.solver.safety_factor == 0.8


@pytest.mark.parametrize(
    "geometry",
    [
        pytest.param({"type": "bar", "length": 0.01, "area": 1.0e-4}, id="bar"),
        pytest.param({"type": "box", "size": [0.004, 0.002, 0.002]}, id="box"),
        pytest.param({"type": "cylinder", "radius": 0.002, "length": 0.004}, id="cylinder"),
        pytest.param({"type": "mesh", "file": "plate.msh", "dim": 3}, id="mesh"),
    ],
)
def test_other_geometries_parse(geometry: dict) -> None:
    data = {
        "name": "g",
        "geometry": geometry,
        "material": base_deck()["material"],
        "discretisation": {"spacing": 5.0e-4, "horizon": 1.5e-3},
        "solver": {"steps": 1},
    }
    deck = parse_deck(data)  # no base_dir: the mesh file is not looked up
    assert deck.geometry.type == geometry["type"]


@pytest.mark.parametrize(
    "time_function",
    [
        {"type": "constant", "value": 0.5},
        {"type": "ramp", "start": 1.0e-6, "end": 2.0e-6},
        {"type": "table", "times": [0.0, 1.0e-6, 2.0e-6], "values": [0.0, 1.0, 0.0]},
        {"type": "triangular_pulse", "peak": 2.0, "rise_time": 1.0e-6, "duration": 3.0e-6},
    ],
    ids=lambda tf: tf["type"],
)
def test_time_functions_parse(time_function: dict) -> None:
    data = base_deck()
    data["boundary_conditions"][1]["time_function"] = time_function
    assert parse_deck(data).boundary_conditions[1].time_function.type == time_function["type"]


def test_fixed_poisson_ratio_is_accepted() -> None:
    data = base_deck()
    data["material"]["poisson_ratio"] = 1.0 / 3.0
    assert parse_deck(data).material.poisson_ratio == pytest.approx(1.0 / 3.0)
    data = base_deck_3d()
    data["material"]["poisson_ratio"] = 0.25
    assert parse_deck(data).material.poisson_ratio == 0.25


def test_all_problems_of_a_pass_are_listed() -> None:
    data = base_deck()
    data["material"]["youngs_modulus"] = -1.0
    data["geometry"]["thikness"] = 1.0
    data["solver"]["steps"] = 3
    with pytest.raises(DeckError) as info:
        parse_deck(data)
    paths = {p for p, _ in info.value.errors}
    assert paths == {"material.youngs_modulus", "geometry.thikness", "solver.end_time"}


def test_not_a_mapping() -> None:
    with pytest.raises(DeckError, match="a deck is a YAML mapping"):
        parse_deck([1, 2, 3])


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.parent.name)
def test_examples_load(path: Path) -> None:
    deck = load_deck(path)
    assert deck.name == path.parent.name


def test_all_three_examples_exist() -> None:
    assert {p.parent.name for p in EXAMPLES} >= {
        "crack_branching_2d",
        "bar_wave_1d",
        "plate_tension_2d",
    }


# -------------------------------------------------------------------------- overrides
def test_apply_overrides_values() -> None:
    data = apply_overrides(
        base_deck(),
        [
            "solver.end_time=null",
            "solver.steps=7",
            "boundary_conditions.1.value=[0,1e6]",  # 1e6 is a YAML string
            "material.youngs_modulus=72.0e9",
            "node_sets.gauge={ball: {center: [0.005, 0.0025], radius: 0.001}}",
            "output.crack_tip.damage_threshold=0.5",
        ],
    )
    deck = parse_deck(data)
    assert deck.solver.steps == 7 and deck.solver.end_time is None
    assert deck.boundary_conditions[1].value == [0.0, 1.0e6]
    assert deck.material.youngs_modulus == 72.0e9
    assert deck.node_sets["gauge"].kind() == "ball"
    assert deck.output.crack_tip.damage_threshold == 0.5


def test_apply_overrides_creates_sections() -> None:
    data = base_deck()
    del data["output"]["crack_tip"]
    data = apply_overrides(data, ["output.crack_tip.origin=[0.0, 0.0025]"])
    assert parse_deck(data).output.crack_tip.origin == [0.0, 0.0025]


@pytest.mark.parametrize(
    ("override", "path", "hint"),
    [
        ("solver.steps", "solver.steps", "an override is key.path=value"),
        ("boundary_conditions.5.value=[0, 1]", "boundary_conditions.5.value", "no list item '5'"),
        ("boundary_conditions.first.set=top", "boundary_conditions.first.set", "no list item"),
        ("name.first=x", "name.first", "name is not a section"),
    ],
)
def test_bad_override(override: str, path: str, hint: str) -> None:
    with pytest.raises(DeckError) as info:
        apply_overrides(base_deck(), [override])
    assert info.value.errors == [(path, hint)] or (
        info.value.errors[0][0] == path and hint in info.value.errors[0][1]
    )


@pytest.mark.parametrize(
    ("override", "path"),
    [
        ("material.density=-1", "material.density"),
        ("solver.steps=10", "solver.end_time"),
        ("geometry.thikness=1.0", "geometry.thikness"),
        ("boundary_conditions.0.set=nowhere", "boundary_conditions.0.set"),
    ],
)
def test_override_values_are_validated(override: str, path: str) -> None:
    with pytest.raises(DeckError, match=f"\n  {path}: "):
        parse_deck(apply_overrides(base_deck(), [override]))


def test_load_deck_with_overrides(tmp_path: Path) -> None:
    deck = load_deck(
        ROOT / "examples" / "bar_wave_1d" / "deck.yaml",
        overrides=[
            "solver.end_time=1.0e-4",
            "boundary_conditions.0.value=[1.0e6]",
            "output.probes.1.component=magnitude",
        ],
    )
    assert deck.solver.end_time == 1.0e-4
    assert deck.boundary_conditions[0].value == [1.0e6]
    assert deck.output.probes[1].component == "magnitude"
    with pytest.raises(DeckError, match="\n  material.density: "):
        load_deck(ROOT / "examples" / "bar_wave_1d" / "deck.yaml", overrides=["material.density=0"])
    with pytest.raises(DeckError, match="no list item '3'"):
        load_deck(
            ROOT / "examples" / "bar_wave_1d" / "deck.yaml",
            overrides=["boundary_conditions.3.set=gauge"],
        )


def test_load_deck_file_errors(tmp_path: Path) -> None:
    with pytest.raises(DeckError, match="cannot read deck"):
        load_deck(tmp_path / "missing.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: [unclosed\n")
    with pytest.raises(DeckError, match="not valid YAML"):
        load_deck(bad)
    mesh = tmp_path / "mesh.yaml"
    data = base_deck()
    data["geometry"] = {"type": "mesh", "file": "nowhere.msh"}
    mesh.write_text(yaml.safe_dump(data))
    with pytest.raises(DeckError, match="\n  geometry.file: mesh file .* does not exist"):
        load_deck(mesh)


# ------------------------------------------------------------- set-up (runner) errors
def test_build_cloud_makes_node_sets() -> None:
    deck = parse_deck(base_deck())
    cloud = build_cloud(deck)
    assert cloud.n_points == 20 * 10
    assert len(cloud.node_set("all")) == cloud.n_points
    assert len(cloud.node_set("top")) == 20 and len(cloud.node_set("bottom")) == 20
    assert len(cloud.node_set("gauge")) == 1


@pytest.mark.parametrize(
    "region",
    [
        pytest.param({"box": {"min": [0.02, 0.02], "max": [0.03, 0.03]}}, id="box-outside"),
        pytest.param({"ball": {"center": [0.005, 0.0025], "radius": 1.0e-4}}, id="ball-between"),
        pytest.param({"all_of": [{"set": "top"}, {"set": "bottom"}]}, id="disjoint-all-of"),
        pytest.param({"not": {"everywhere": True}}, id="not-everywhere"),
    ],
)
def test_empty_node_set_is_a_setup_error(region: dict) -> None:
    data = base_deck()
    data["node_sets"]["empty"] = region
    deck = parse_deck(data)
    with pytest.raises(SetupError) as info:
        build_cloud(deck)
    assert info.value.path == "node_sets.empty"
    assert str(info.value).startswith("node_sets.empty: selects no point")


def test_node_set_cycle_is_a_setup_error() -> None:
    data = base_deck()
    data["node_sets"]["a"] = {"set": "b"}
    data["node_sets"]["b"] = {"not": {"set": "a"}}
    deck = parse_deck(data)
    with pytest.raises(SetupError, match="cycle") as info:
        build_cloud(deck)
    assert info.value.path in ("node_sets.a", "node_sets.b")


def test_size_not_multiple_of_spacing_is_fitted_and_below_it_is_a_setup_error() -> None:
    from peridynamics.geometry import GeometryFitWarning

    data = base_deck()
    data["geometry"]["size"] = [0.0103, 0.005]
    with pytest.warns(GeometryFitWarning, match="not a whole multiple of the spacing"):
        cloud = build_cloud(parse_deck(data))
    assert cloud.n_points == 20 * 10 and cloud.grid_fit[0].key == "size[0]"
    data["geometry"]["size"] = [0.0103, 0.0004]
    with pytest.raises(SetupError, match="shorter than the spacing") as info:
        build_cloud(parse_deck(data))
    assert info.value.path == "geometry"


# ------------------------------------------- gaps found in review, now closed
def test_mesh_dim_defaults_to_mesh_dimension(tmp_path: Path) -> None:
    import meshio
    import numpy as np

    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], float) * 1e-3
    meshio.write(
        tmp_path / "tets.vtu", meshio.Mesh(pts, [("tetra", np.array([[0, 1, 2, 3], [1, 2, 3, 4]]))])
    )
    data = base_deck_3d()
    data["geometry"] = {"type": "mesh", "file": "tets.vtu"}
    data["node_sets"] = {}
    (tmp_path / "deck.yaml").write_text(yaml.safe_dump(data))
    deck = load_deck(tmp_path / "deck.yaml")
    assert build_cloud(deck).dim == deck.dim


def test_pressure_zero_normal_rejected() -> None:
    data = base_deck()
    data["boundary_conditions"][1] = _bc(type="pressure", value=1.0e6, normal=[0.0, 0.0])
    with pytest.raises(DeckError, match="\n  boundary_conditions.1.normal: "):
        parse_deck(data)


def test_traction_zero_normal_rejected() -> None:
    data = base_deck()
    data["boundary_conditions"][1]["normal"] = [0.0, 0.0]
    with pytest.raises(DeckError, match="\n  boundary_conditions.1.normal: "):
        parse_deck(data)


def test_cylinder_region_zero_axis_rejected() -> None:
    data = base_deck_3d()
    data["node_sets"]["core"]["cylinder"]["axis"] = [0.0, 0.0, 0.0]
    with pytest.raises(DeckError, match="\n  node_sets.core.cylinder.axis: "):
        parse_deck(data)


def test_crack_tip_zero_direction_rejected() -> None:
    data = base_deck()
    data["output"]["crack_tip"]["direction"] = [0.0, 0.0]
    with pytest.raises(DeckError, match="\n  output.crack_tip.direction: "):
        parse_deck(data)


def test_skew_3d_precrack_names_precracks() -> None:
    data = base_deck_3d()
    data["precracks"] = [
        {"points": [[0.0, 0.002, 0.0], [0.002, 0.002, 0.0], [0.001, 0.002, 0.004]]}
    ]
    with pytest.raises(DeckError, match="\n  precracks.0.points: .*perpendicular"):
        parse_deck(data)


def test_missing_bc_type_lists_allowed_types() -> None:
    data = base_deck()
    del data["boundary_conditions"][0]["type"]
    with pytest.raises(DeckError) as info:
        parse_deck(data)
    assert "fixed" in str(info.value)


def test_reserved_node_set_name_path() -> None:
    data = base_deck()
    data["node_sets"]["all"] = {"everywhere": True}
    with pytest.raises(DeckError, match="\n  node_sets.all: "):
        parse_deck(data)


def test_boolean_is_not_a_number() -> None:
    data = base_deck()
    data["discretisation"]["spacing"] = True
    with pytest.raises(DeckError, match="\n  discretisation.spacing: "):
        parse_deck(data)
