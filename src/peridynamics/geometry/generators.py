"""Regular-grid generators for 1-D bars, 2-D plates and 3-D boxes and cylinders.

Points sit at cell centres of a uniform grid of spacing ``dx`` unless
``nodes_on_boundary=True`` (1-D), where they sit on ``x_i = i dx`` as in Lu & Wang (2016).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from peridynamics.geometry.cloud import Plane, PointCloud
from peridynamics.geometry.regions import CylinderRegion, Region


def _count(length: float, dx: float, what: str) -> int:
    if not length > 0:
        raise ValueError(f"{what} must be > 0, got {length}")
    if not dx > 0:
        raise ValueError(f"spacing must be > 0, got {dx}")
    n = int(round(length / dx))
    if n < 1 or abs(n * dx - length) > 1e-6 * length:
        raise ValueError(
            f"{what} = {length} m is not a whole multiple of spacing {dx} m "
            f"({length / dx:.6g} cells); choose a spacing that divides it"
        )
    return n


def _centres(lo: float, length: float, dx: float, what: str) -> NDArray[np.float64]:
    n = _count(length, dx, what)
    return np.asarray(lo + (np.arange(n) + 0.5) * dx, dtype=np.float64)


def bar(
    length: float,
    dx: float,
    area: float = 1.0,
    origin: float = 0.0,
    nodes_on_boundary: bool = False,
) -> PointCloud:
    """1-D bar of cross-section ``area`` (m^2).

    ``nodes_on_boundary=True`` puts ``length/dx + 1`` nodes at ``origin + i*dx`` (the end
    nodes get the full volume ``area*dx``, as in Lu & Wang (2016), section 3); otherwise
    ``length/dx`` nodes sit at cell centres.
    """
    if nodes_on_boundary:
        n = _count(length, dx, "length")
        x = np.asarray(origin + np.arange(n + 1) * dx, dtype=np.float64)
    else:
        x = _centres(origin, length, dx, "length")
    return PointCloud(
        x=x[:, None], volume=np.full(len(x), area * dx), spacing=dx, cross_section=area
    )


def rectangle(
    size: Sequence[float],
    dx: float,
    thickness: float = 1.0,
    origin: Sequence[float] = (0.0, 0.0),
    plane: Plane = "stress",
    holes: Sequence[Region] = (),
) -> PointCloud:
    """2-D rectangle ``size = (Lx, Ly)`` of ``thickness`` (m) with optional holes."""
    xs = _centres(origin[0], size[0], dx, "size[0]")
    ys = _centres(origin[1], size[1], dx, "size[1]")
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    x = np.column_stack([gx.ravel(), gy.ravel()])
    cloud = PointCloud(
        x=x,
        volume=np.full(len(x), dx * dx * thickness),
        spacing=dx,
        cross_section=thickness,
        plane=plane,
    )
    return _cut(cloud, holes)


def box(
    size: Sequence[float],
    dx: float,
    origin: Sequence[float] = (0.0, 0.0, 0.0),
    holes: Sequence[Region] = (),
) -> PointCloud:
    """3-D box ``size = (Lx, Ly, Lz)`` with optional cut-outs."""
    axes = [_centres(origin[k], size[k], dx, f"size[{k}]") for k in range(3)]
    g = np.meshgrid(*axes, indexing="ij")
    x = np.column_stack([a.ravel() for a in g])
    cloud = PointCloud(x=x, volume=np.full(len(x), dx**3), spacing=dx)
    return _cut(cloud, holes)


def cylinder(
    radius: float,
    length: float,
    dx: float,
    origin: ArrayLike = (0.0, 0.0, 0.0),
    holes: Sequence[Region] = (),
) -> PointCloud:
    """3-D solid cylinder with axis along z from ``origin`` (a cubic grid cut to shape)."""
    if not radius > 0:
        raise ValueError("radius must be > 0")
    o = np.asarray(origin, dtype=float)
    n_r = int(np.ceil(radius / dx))
    span = 2 * n_r * dx
    cloud = box((span, span, length), dx, origin=(o[0] - n_r * dx, o[1] - n_r * dx, o[2]))
    inside = CylinderRegion(base=o, axis=(0, 0, 1), radius=radius, length=length)
    return _cut(cloud, [~inside, *holes])


def _cut(cloud: PointCloud, holes: Sequence[Region]) -> PointCloud:
    for hole in holes:
        cloud = cloud.remove(hole)
    return cloud
