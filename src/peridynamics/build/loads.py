"""Boundary and initial conditions and time functions from the deck (registries
:data:`TIME_FUNCTIONS` keyed by a time function's ``type``, :data:`CONDITIONS` keyed
by a boundary condition's ``type``)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics import deck as dk
from peridynamics.build.errors import SetupError
from peridynamics.geometry import PointCloud
from peridynamics.loading import conditions as bc
from peridynamics.loading import initial_fields
from peridynamics.loading import time_functions as tf

COMP = {"x": 0, "y": 1, "z": 2}


def _blast(spec: Any) -> tf.TimeFunction:
    from peridynamics.loading.blast import BlastPulse

    return BlastPulse(spec.charge_kg, spec.standoff_m, spec.shape, spec.delay)


#: time function ``type`` -> builder(section) -> TimeFunction
TIME_FUNCTIONS: dict[str, Callable[[Any], tf.TimeFunction]] = {
    "constant": lambda spec: tf.Constant(spec.value),
    "ramp": lambda spec: tf.Ramp(end=spec.end, start=spec.start),
    "table": lambda spec: tf.Table(tuple(spec.times), tuple(spec.values)),
    "sine_pulse": lambda spec: tf.SinePulse(spec.duration),
    "square_pulse": lambda spec: tf.SquarePulse(spec.duration),
    "blast": _blast,
    "triangular_pulse": lambda spec: tf.TriangularPulse(spec.peak, spec.rise_time, spec.duration),
}


def time_function(spec: Any) -> tf.TimeFunction:
    """Deck time function -> object."""
    return TIME_FUNCTIONS[spec.type](spec)


def _kinematic_components(spec: Any, dim: int) -> list[int]:
    """Components a displacement / velocity / fixed condition prescribes ([] otherwise)."""
    if spec.type in ("displacement", "velocity"):
        return [COMP[c] for c in spec.components]
    if spec.type == "fixed":
        if spec.components:
            return [COMP[c] for c in spec.components if c != "rotation"]
        return list(range(dim))
    return []


# A condition builder: (spec, its index, its nodes, the cloud) -> (group, object) where
# group is "body" (body forces), "kin" (kinematic constraints) or "init" (initial values)
Condition = Callable[[Any, int, NDArray[np.intp], PointCloud], tuple[str, Any]]


def _prescribed(spec: Any, ibc: int, nodes: NDArray[np.intp], cloud: PointCloud) -> tuple[str, Any]:
    kind = bc.PrescribedDisplacement if spec.type == "displacement" else bc.PrescribedVelocity
    values = {str(k): v for k, v in spec.components.items()}
    return "kin", kind(nodes, values, time_function(spec.time_function))


def _fixed(spec: Any, ibc: int, nodes: NDArray[np.intp], cloud: PointCloud) -> tuple[str, Any]:
    return "kin", bc.Fixed(nodes, tuple(spec.components) if spec.components else None)


def _initial(spec: Any, ibc: int, nodes: NDArray[np.intp], cloud: PointCloud) -> tuple[str, Any]:
    return "init", bc.InitialVelocity(nodes, _initial_field(spec, ibc, nodes, cloud))


def _body_force(spec: Any, ibc: int, nodes: NDArray[np.intp], cloud: PointCloud) -> tuple[str, Any]:
    return "body", bc.BodyForce(nodes, tuple(spec.value), time_function(spec.time_function))


def _surface(spec: Any, ibc: int, nodes: NDArray[np.intp], cloud: PointCloud) -> tuple[str, Any]:
    """A traction, or a pressure on a flat face (``normal``) or a cavity (``center``)."""
    if spec.type == "pressure" and spec.center is not None:
        return "body", bc.cavity_pressure_as_body_force(
            nodes,
            spec.scale,
            cloud.x,
            cloud.volume,
            np.asarray(spec.center, dtype=float),
            cloud.spacing,
            thickness=cloud.cross_section,
            layer_thickness=spec.layer_thickness,
            function=time_function(spec.time_function),
        )
    normal: NDArray[np.float64] | None
    if spec.type == "pressure":
        assert spec.normal is not None
        n = np.asarray(spec.normal, dtype=float)
        traction = -spec.scale * n / np.linalg.norm(n)
        normal = n
    else:
        traction = np.asarray(spec.value, dtype=float)
        normal = None if spec.normal is None else np.asarray(spec.normal, dtype=float)
    return "body", bc.traction_as_body_force(
        nodes,
        traction,
        cloud.x,
        cloud.spacing,
        normal=normal,
        layer_thickness=spec.layer_thickness,
        function=time_function(spec.time_function),
        jittered=cloud.irregular,
        volume=cloud.volume,
        cross_section=cloud.cross_section,
    )


#: boundary condition ``type`` -> builder (a ``Condition``)
CONDITIONS: dict[str, Condition] = {
    "displacement": _prescribed,
    "velocity": _prescribed,
    "fixed": _fixed,
    "initial_velocity": _initial,
    "body_force": _body_force,
    "traction": _surface,
    "pressure": _surface,
}


def build_conditions(
    deck: dk.Deck,
    cloud: PointCloud,
    on: Callable[[Any], tuple[PointCloud, Callable[[Any], Any]] | None] | None = None,
) -> tuple[list, list, list]:
    """(body forces, kinematic constraints, initial velocities).

    ``on(spec)``, when given, may build a condition on another cloud than ``cloud``
    (a set gathered from every rank): it returns that cloud and what to do with the
    condition built there (make it local), or ``None`` for ``cloud`` itself."""
    groups: dict[str, list[Any]] = {"body": [], "kin": [], "init": []}
    owner = np.full((cloud.n_points, cloud.dim), -1)  # which kinematic BC holds a dof
    for ibc, spec in enumerate(deck.boundary_conditions):
        nodes = cloud.node_set(spec.set)
        comps = np.asarray(_kinematic_components(spec, cloud.dim), dtype=np.intp)
        if comps.size:
            taken = owner[np.ix_(nodes, comps)]
            if np.any(taken >= 0):
                other = int(taken[taken >= 0][0])
                raise SetupError(
                    f"boundary_conditions.{ibc}",
                    f"prescribes the same node and component as boundary_conditions.{other} "
                    f"(sets {spec.set!r} and {deck.boundary_conditions[other].set!r} "
                    "overlap); a degree of freedom can have one kinematic condition only",
                )
            owner[np.ix_(nodes, comps)] = ibc
        elsewhere = on(spec) if on is not None else None
        if elsewhere is None:
            group, item = CONDITIONS[spec.type](spec, ibc, nodes, cloud)
        else:
            where, back = elsewhere
            group, item = CONDITIONS[spec.type](spec, ibc, where.node_set(spec.set), where)
            item = back(item)
        groups[group].append(item)
    return groups["body"], groups["kin"], groups["init"]


def _initial_field(
    spec: dk.InitialVelocityBC, ibc: int, nodes: NDArray[np.intp], cloud: PointCloud
) -> tuple[float, ...] | NDArray[np.float64]:
    """The value of an initial condition on ``nodes``: one vector when every component
    is a number, else one row per node (expressions of x, y, z evaluated at the nodes'
    reference positions, or the rows of the file). Raises SetupError naming the key."""
    path = f"boundary_conditions.{ibc}"
    if spec.file is not None:
        try:
            values = initial_fields.read_point_values(spec.file, cloud.dim)
            return initial_fields.point_rows(values, nodes, cloud.n_points, Path(spec.file).name)
        except ValueError as exc:
            raise SetupError(f"{path}.file", str(exc)) from None
    assert spec.value is not None
    if all(not isinstance(c, str) for c in spec.value):
        return tuple(float(c) for c in spec.value)
    x = cloud.x[nodes]
    out = np.empty((len(nodes), len(spec.value)))
    for k, comp in enumerate(spec.value):
        if not isinstance(comp, str):
            out[:, k] = float(comp)
            continue
        try:
            out[:, k] = initial_fields.FieldExpression(comp)(x)
        except ValueError as exc:
            raise SetupError(f"{path}.value.{k}", str(exc)) from None
        bad = ~np.isfinite(out[:, k])
        if np.any(bad):
            first = x[np.flatnonzero(bad)[0]].tolist()
            raise SetupError(
                f"{path}.value.{k}",
                f"{comp!r} is not finite at {int(bad.sum())} of the {len(nodes)} points of "
                f"set {spec.set!r} (first at x = {first} m)",
            )
    return out
