"""Boundary and initial conditions, each acting on a named node set.

Kinematic conditions (``PrescribedDisplacement``, ``PrescribedVelocity``, ``Fixed``)
are enforced by the solver after each update; force-like conditions (``BodyForce``,
``Traction``) add to the external force density the model evaluates;
``InitialVelocity`` is applied once at t = 0, a constant per set or a field
(:class:`~peridynamics.loading.initial_fields.FieldExpression` of the coordinates, or
point values from a file: :mod:`peridynamics.loading.initial_fields`).
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
    """u = v = 0 on ``nodes`` for the listed components (all when ``None``). For a model
    with rotations (micropolar), ``"rotation"`` fixes theta = omega = 0 too; ``None``
    (every component) clamps: displacements and rotation."""

    nodes: NDArray[np.intp]
    components: tuple[str, ...] | None = None

    @property
    def rotation(self) -> bool:
        """True when the condition fixes the rotation of a micropolar model."""
        return self.components is None or "rotation" in self.components

    def apply_rotation(self, theta: NDArray, omega: NDArray) -> None:
        """theta = omega = 0 on ``nodes`` when :attr:`rotation` (arrays (n, 1))."""
        if self.rotation:
            theta[self.nodes] = 0.0
            omega[self.nodes] = 0.0

    def indices(self, dim: int) -> list[int]:
        """The displacement components it fixes (0 = x, ...)."""
        names = (
            tuple(c for c in self.components if c != "rotation")
            if self.components
            else (tuple(COMPONENTS)[:dim])
        )
        return [c for c, _ in _components(dict.fromkeys(names, 0.0), dim, "fixed")]

    def apply(self, u: NDArray, v: NDArray, t: float, dt: float) -> None:
        for c in self.indices(u.shape[1]):
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
    """v(0) = value on ``nodes`` (m/s); ``value`` is one vector (dim,) for every node or
    one per node (len(nodes), dim), e.g. from
    :class:`~peridynamics.loading.initial_fields.FieldExpression` or
    :func:`~peridynamics.loading.initial_fields.read_point_values`."""

    nodes: NDArray[np.intp]
    value: tuple[float, ...] | NDArray[np.float64]

    def apply_initial(self, v: NDArray) -> None:
        val = np.asarray(self.value, dtype=float)
        if val.shape not in ((v.shape[1],), (len(self.nodes), v.shape[1])):
            raise ValueError(
                f"initial velocity needs {v.shape[1]} components (one vector, or one per "
                f"node), got shape {val.shape}"
            )
        v[self.nodes] = val


@dataclass(frozen=True)
class BodyForce:
    """b(t) = value * f(t) on ``nodes`` (N/m^3); ``value`` is one vector (dim,) for every
    node or one per node (len(nodes), dim)."""

    nodes: NDArray[np.intp]
    value: tuple[float, ...] | NDArray[np.float64]
    function: TimeFunction = field(default_factory=Constant)

    def checked_value(self, dim: int) -> NDArray[np.float64]:
        """``value`` as an array of shape (dim,) or (len(nodes), dim); ValueError else."""
        val = np.asarray(self.value, dtype=float)
        if val.shape not in ((dim,), (len(self.nodes), dim)):
            raise ValueError(
                f"body force needs {dim} components (one vector, or one per node), "
                f"got shape {val.shape}"
            )
        return val

    def add_to(self, b: NDArray, t: float) -> None:
        b[self.nodes] += self.checked_value(b.shape[1]) * self.function(t)


def traction_as_body_force(
    nodes: NDArray[np.intp],
    traction: NDArray[np.float64],
    x: NDArray[np.float64],
    spacing: float,
    normal: NDArray[np.float64] | None = None,
    layer_thickness: float | None = None,
    function: TimeFunction | None = None,
    jittered: bool = False,
    volume: NDArray[np.float64] | None = None,
    cross_section: float = 1.0,
) -> BodyForce:
    """A surface traction t (Pa) spread as a body force t / l over a boundary layer.

    ``l`` is ``layer_thickness`` if given; else the extent of the node set along the
    surface ``normal`` plus one spacing (one grid row -> dx, k rows -> k dx); without a
    normal, the smallest extent of the set along a coordinate axis plus one spacing (the
    thin direction of an axis-aligned layer, whatever the direction of the traction).
    The total force is then traction x loaded area for grid layers. On a ``jittered``
    grid (the layer's rows are not flat) ``l`` is the layer's volume (``volume`` of its
    points) over its face area: the extents of the set across the normal plus one
    spacing each (2-D: times ``cross_section``, the thickness), so the total force is
    traction x that area.
    """
    traction = np.asarray(traction, dtype=float)
    if layer_thickness is None:
        pts = x[nodes]
        dim = x.shape[1]
        if normal is None:
            axis = int(np.argmin(np.ptp(pts, axis=0)))
            n = np.eye(dim)[axis]
        else:
            n = np.asarray(normal, dtype=float)
            norm = float(np.linalg.norm(n))
            if norm == 0:
                raise ValueError("traction: the normal must be a non-zero vector")
            n = n / norm
        if jittered and volume is not None and dim > 1:
            # tangent directions: the rest of an orthonormal basis with n first
            q = np.linalg.qr(np.column_stack([n, np.eye(dim)]))[0][:, 1:dim]
            rows = np.round(np.ptp(pts @ q, axis=0) / spacing)  # rows across the face - 1
            area = float(np.prod((rows + 1.0) * spacing))
            area *= cross_section if dim == 2 else 1.0
            layer_thickness = float(np.sum(volume[nodes])) / area
        else:
            layer_thickness = float(np.ptp(pts @ n)) + spacing
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
