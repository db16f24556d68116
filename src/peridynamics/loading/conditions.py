"""Boundary and initial conditions, each acting on a named node set.

Kinematic conditions (``PrescribedDisplacement``, ``PrescribedVelocity``, ``Fixed``)
are enforced by the solver after each update; force-like conditions (``BodyForce``,
``Traction``) add to the external force density the model evaluates;
``InitialVelocity`` is applied once at t = 0.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from peridynamics.loading.time_functions import Constant, TimeFunction

COMPONENTS = {"x": 0, "y": 1, "z": 2}


def _components(values: Mapping[str, float], dim: int, what: str) -> list[tuple[int, float]]:
    out = []
    for name, val in values.items():
        if name not in COMPONENTS or COMPONENTS[name] >= dim:
            allowed = ", ".join(list(COMPONENTS)[:dim])
            raise ValueError(f"{what}: component {name!r} is not one of {allowed}")
        out.append((COMPONENTS[name], float(val)))
    return out


@dataclass(frozen=True)
class PrescribedDisplacement:
    """u_c(t) = value_c * f(t) on ``nodes`` for each given component (m)."""

    nodes: NDArray[np.intp]
    values: Mapping[str, float]
    function: TimeFunction = field(default_factory=Constant)

    def apply(self, u: NDArray, v: NDArray, t: float, dt: float) -> None:
        """Set u at time ``t`` and v to the secant rate over the last step."""
        f_now, f_old = self.function(t), self.function(t - dt)
        for c, val in _components(self.values, u.shape[1], "displacement"):
            u[self.nodes, c] = val * f_now
            v[self.nodes, c] = val * (f_now - f_old) / dt


@dataclass(frozen=True)
class Fixed:
    """u = v = 0 on ``nodes`` for the listed components (all when ``None``)."""

    nodes: NDArray[np.intp]
    components: tuple[str, ...] | None = None

    def apply(self, u: NDArray, v: NDArray, t: float, dt: float) -> None:
        names = self.components or tuple(COMPONENTS)[: u.shape[1]]
        for c, _ in _components(dict.fromkeys(names, 0.0), u.shape[1], "fixed"):
            u[self.nodes, c] = 0.0
            v[self.nodes, c] = 0.0


@dataclass(frozen=True)
class PrescribedVelocity:
    """v_c(t) = value_c * f(t) on ``nodes`` (m/s); u follows by integration."""

    nodes: NDArray[np.intp]
    values: Mapping[str, float]
    function: TimeFunction = field(default_factory=Constant)

    def apply(self, u: NDArray, v: NDArray, t: float, dt: float) -> None:
        """Replace the last step's drift by the prescribed mid-step velocity."""
        mid = self.function(t - 0.5 * dt)
        now = self.function(t)
        for c, val in _components(self.values, u.shape[1], "velocity"):
            u[self.nodes, c] += dt * (val * mid - v[self.nodes, c])
            v[self.nodes, c] = val * now

    def set_velocity(self, v: NDArray, t: float) -> None:
        """Set v at time ``t`` (after the second velocity-Verlet kick)."""
        for c, val in _components(self.values, v.shape[1], "velocity"):
            v[self.nodes, c] = val * self.function(t)


@dataclass(frozen=True)
class InitialVelocity:
    """v(0) = value on ``nodes`` (m/s)."""

    nodes: NDArray[np.intp]
    value: tuple[float, ...]

    def apply_initial(self, v: NDArray) -> None:
        val = np.asarray(self.value, dtype=float)
        if val.shape != (v.shape[1],):
            raise ValueError(f"initial velocity needs {v.shape[1]} components, got {len(val)}")
        v[self.nodes] = val


@dataclass(frozen=True)
class BodyForce:
    """b(t) = value * f(t) on ``nodes`` (N/m^3); ``value`` is one vector (dim,) for every
    node or one per node (len(nodes), dim)."""

    nodes: NDArray[np.intp]
    value: tuple[float, ...] | NDArray[np.float64]
    function: TimeFunction = field(default_factory=Constant)

    def add_to(self, b: NDArray, t: float) -> None:
        val = np.asarray(self.value, dtype=float)
        if val.shape not in ((b.shape[1],), (len(self.nodes), b.shape[1])):
            raise ValueError(
                f"body force needs {b.shape[1]} components (one vector, or one per node), "
                f"got shape {val.shape}"
            )
        b[self.nodes] += val * self.function(t)


def traction_as_body_force(
    nodes: NDArray[np.intp],
    traction: NDArray[np.float64],
    x: NDArray[np.float64],
    spacing: float,
    normal: NDArray[np.float64] | None = None,
    layer_thickness: float | None = None,
    function: TimeFunction | None = None,
) -> BodyForce:
    """A surface traction t (Pa) spread as a body force t / l over a boundary layer.

    ``l`` is ``layer_thickness`` if given; else the extent of the node set along the
    surface ``normal`` plus one spacing (one grid row -> dx, k rows -> k dx); without a
    normal, the smallest extent of the set along a coordinate axis plus one spacing (the
    thin direction of an axis-aligned layer, whatever the direction of the traction).
    The total force is then traction x loaded area for grid layers.
    """
    traction = np.asarray(traction, dtype=float)
    if layer_thickness is None:
        pts = x[nodes]
        if normal is None:
            layer_thickness = float(np.min(np.ptp(pts, axis=0))) + spacing
        else:
            n = np.asarray(normal, dtype=float)
            norm = float(np.linalg.norm(n))
            if norm == 0:
                raise ValueError("traction: the normal must be a non-zero vector")
            layer_thickness = float(np.ptp(pts @ (n / norm))) + spacing
    if not layer_thickness > 0:
        raise ValueError("traction layer_thickness must be > 0 m")
    return BodyForce(
        nodes=nodes, value=tuple(traction / layer_thickness), function=function or Constant()
    )


def cavity_pressure_as_body_force(
    nodes: NDArray[np.intp],
    pressure: float,
    x: NDArray[np.float64],
    volume: NDArray[np.float64],
    center: NDArray[np.float64],
    spacing: float,
    thickness: float = 1.0,
    layer_thickness: float | None = None,
    function: TimeFunction | None = None,
) -> BodyForce:
    """A pressure p (Pa) on the wall of a cavity around ``center`` (a circular hole in
    2-D, a spherical one in 3-D), as a radial body force p / l pushing each node of the
    layer away from the centre.

    Without ``layer_thickness`` the body force is scaled so that the total radial force
    is p times the wall area: l = sum(V_layer) / A_wall with the wall radius R taken as
    the distance of the closest layer node (A_wall = 2 pi R ``thickness`` in 2-D,
    4 pi R^2 in 3-D). In 1-D the two-sided push uses l = extent of the set + spacing.
    """
    rel = x[nodes] - np.asarray(center, dtype=float)
    r = np.linalg.norm(rel, axis=1)
    if np.any(r == 0):
        raise ValueError("cavity pressure: a loaded node sits on the centre; move the centre")
    if layer_thickness is None:
        dim = x.shape[1]
        radius = float(r.min())
        if dim == 1:
            layer_thickness = float(np.ptp(r)) + spacing
        else:
            wall = 2 * np.pi * radius * thickness if dim == 2 else 4 * np.pi * radius**2
            layer_thickness = float(np.sum(volume[nodes])) / wall
    if not layer_thickness > 0:
        raise ValueError("pressure layer_thickness must be > 0 m")
    value = (pressure / layer_thickness) * rel / r[:, None]
    return BodyForce(nodes=nodes, value=value, function=function or Constant())


Kinematic = PrescribedDisplacement | PrescribedVelocity | Fixed
