"""Thermal boundary conditions on node sets: prescribed temperature, prescribed heat
flux and convection (docs/theory_thermal.md).

A heat flux ``q`` (W/m^2) and a convective film ``h (T_inf(t) - T)`` act on a
boundary layer of thickness ``l`` as a volumetric source ``q / l`` (W/m^3), the same
conversion as a mechanical traction
(:func:`peridynamics.loading.conditions.traction_as_body_force`, whose layer rule is
reused: the extent of the set along the normal plus one spacing), so that the heat
that enters a grid layer is ``q`` times its face area.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from peridynamics.loading.conditions import traction_as_body_force
from peridynamics.loading.time_functions import Constant, TimeFunction


@dataclass(frozen=True)
class PrescribedTemperature:
    """T = value * f(t) (K) on ``nodes``, held at every step (a Dirichlet condition)."""

    nodes: NDArray[np.intp]
    value: float
    function: TimeFunction = field(default_factory=Constant)

    def temperature(self, t: float) -> float:
        """The prescribed temperature at time ``t`` (s), K."""
        return float(self.value * self.function(t))

    def apply(self, temperature: NDArray[np.float64], t: float) -> None:
        """Set ``temperature`` (n,) (K) on the nodes at time ``t`` (s)."""
        temperature[self.nodes] = self.temperature(t)


@dataclass(frozen=True)
class MirroredTemperature:
    """A fictitious layer that mirrors the body across a boundary plane held at
    T_b = value * f(t): ``T_i = 2 T_b(t) - T_m(i)`` on ``nodes`` with ``mirror`` the
    point at the reflection of each (a point on the plane takes T_b). It extends the
    solution oddly about T_b, the smooth extension of a solution with T = T_b on the
    plane (the fictitious boundary layer of Oterkus, Madenci & Agwai (2014)), which a
    constant layer is not: the error against the local solution falls like delta^2
    instead of delta (docs/theory_thermal.md)."""

    nodes: NDArray[np.intp]
    mirror: NDArray[np.intp]
    value: float
    function: TimeFunction = field(default_factory=Constant)

    def temperature(self, t: float) -> float:
        """The boundary temperature at time ``t`` (s), K."""
        return float(self.value * self.function(t))

    def apply(self, temperature: NDArray[np.float64], t: float) -> None:
        """Set ``temperature`` (n,) (K) on the layer from its mirror points."""
        tb = self.temperature(t)
        new = 2.0 * tb - temperature[self.mirror]
        new[self.mirror == self.nodes] = tb
        temperature[self.nodes] = new


def mirror_points(
    nodes: NDArray[np.intp],
    x: NDArray[np.float64],
    spacing: float,
    point: NDArray[np.float64],
    normal: NDArray[np.float64],
) -> NDArray[np.intp]:
    """The point at the reflection of each of ``nodes`` across the plane through
    ``point`` with ``normal`` (m); ValueError when a reflection is not within 1e-6
    spacing of a point (the plane must lie on a symmetry plane of the grid)."""
    from scipy.spatial import cKDTree

    n = np.asarray(normal, dtype=float)
    norm = float(np.linalg.norm(n))
    if norm == 0:
        raise ValueError("mirror: the normal must be a non-zero vector")
    n = n / norm
    p = x[nodes]
    refl = p - 2.0 * ((p - np.asarray(point, dtype=float)) @ n)[:, None] * n
    dist, idx = cKDTree(x).query(refl)
    bad = np.flatnonzero(dist > 1e-6 * spacing)
    if len(bad):
        where = [float(c) for c in p[bad[0]]]
        raise ValueError(
            f"mirror: the reflection of the point at {where} is not a point of the body; "
            "put the plane half-way between grid rows or on one"
        )
    return np.asarray(idx, dtype=np.intp)


@dataclass(frozen=True)
class HeatSource:
    """A volumetric heat source s(t) = value * f(t) (W/m^3) on ``nodes``: a prescribed
    flux q (W/m^2) over its boundary layer of thickness l is ``value = q / l``."""

    nodes: NDArray[np.intp]
    value: float
    function: TimeFunction = field(default_factory=Constant)

    def add_to(self, source: NDArray[np.float64], t: float) -> None:
        """Add the source at time ``t`` (s) to ``source`` (n,) (W/m^3)."""
        source[self.nodes] += self.value * self.function(t)


@dataclass(frozen=True)
class Convection:
    """Newton cooling on a boundary layer: s_i = (h / l) (T_inf(t) - T_i) (W/m^3) with
    the film coefficient ``film`` h (W/(m^2 K)), the layer thickness ``layer`` l (m)
    and the ambient temperature ``ambient`` * f(t) (K)."""

    nodes: NDArray[np.intp]
    film: float
    layer: float
    ambient: float
    function: TimeFunction = field(default_factory=Constant)

    @property
    def coefficient(self) -> float:
        """h / l (W/(m^3 K)): what the condition adds to the diagonal of the operator."""
        return self.film / self.layer

    def ambient_at(self, t: float) -> float:
        """The ambient temperature at time ``t`` (s), K."""
        return float(self.ambient * self.function(t))

    def add_to(
        self, source: NDArray[np.float64], temperature: NDArray[np.float64], t: float
    ) -> None:
        """Add (h / l)(T_inf(t) - T_i) (W/m^3) on the nodes to ``source`` (n,)."""
        source[self.nodes] += self.coefficient * (self.ambient_at(t) - temperature[self.nodes])


def _layer(
    nodes: NDArray[np.intp],
    x: NDArray[np.float64],
    spacing: float,
    normal: NDArray[np.float64] | None,
    layer_thickness: float | None,
) -> float:
    """The boundary layer's thickness (m) by the rule of a mechanical traction."""
    probe = traction_as_body_force(
        nodes, np.ones(1), x, spacing, normal=normal, layer_thickness=layer_thickness
    )
    return 1.0 / float(np.asarray(probe.value)[0])


def flux_as_source(
    nodes: NDArray[np.intp],
    flux: float,
    x: NDArray[np.float64],
    spacing: float,
    normal: NDArray[np.float64] | None = None,
    layer_thickness: float | None = None,
    function: TimeFunction | None = None,
) -> HeatSource:
    """A heat flux into the body ``flux`` * f(t) (W/m^2, positive in) spread as a
    volumetric source q / l over the boundary layer ``nodes`` of thickness l (m).

    Parameters
    ----------
    nodes : (m,) int, the layer's points.
    flux : float, W/m^2.
    x : (n, dim) reference positions (m).
    spacing : float, the grid spacing (m).
    normal : (dim,) float, optional; the surface normal (its sign does not matter).
    layer_thickness : float, optional; l (m), else the set's extent along the normal
        (or its thinnest axis) plus one spacing.
    function : TimeFunction, optional; f(t), 1 by default.
    """
    layer = _layer(nodes, x, spacing, normal, layer_thickness)
    return HeatSource(nodes, flux / layer, function or Constant())


def convection_on_layer(
    nodes: NDArray[np.intp],
    film: float,
    ambient: float,
    x: NDArray[np.float64],
    spacing: float,
    normal: NDArray[np.float64] | None = None,
    layer_thickness: float | None = None,
    function: TimeFunction | None = None,
) -> Convection:
    """Convection to an ambient ``ambient`` * f(t) (K) with film coefficient ``film``
    (W/(m^2 K)) on the boundary layer ``nodes`` (thickness as :func:`flux_as_source`)."""
    if not film >= 0:
        raise ValueError("convection: the film coefficient must be >= 0 W/(m^2 K)")
    layer = _layer(nodes, x, spacing, normal, layer_thickness)
    return Convection(nodes, float(film), layer, float(ambient), function or Constant())
