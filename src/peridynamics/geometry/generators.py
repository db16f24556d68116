"""Grid generators for 1-D bars, 2-D plates and discs, 3-D boxes and cylinders.

Points sit at cell centres of a uniform grid of spacing ``dx`` unless
``nodes_on_boundary=True`` (1-D), where they sit on ``x_i = i dx`` as in Lu & Wang (2016).

Lengths that are not whole multiples of ``dx`` (:func:`fit_cells`): a length L that is a
multiple to a relative 1e-6 gets ``round(L / dx)`` cells starting at the origin, exactly
as before. Any other L gets the ``n = floor(L / dx)`` whole cells that fit, centred in L
(a margin of ``(L - n dx) / 2`` at both ends): the spacing stays ``dx`` and every point
keeps its cell volume, so the discrete body is ``n dx`` long (the nominal length is not
stretched). Each such length issues a :class:`GeometryFitWarning` and is recorded in
``PointCloud.grid_fit``; ``L < dx`` is an error. The radius of a disc or a cylinder need
not be a multiple: their grid has a cell corner on the centre (axis) and keeps the
points inside the circle.

Jittered grids (``jitter > 0``; rectangle, box, cylinder): every point of the full grid
moves by an offset drawn uniformly from ``[-jitter dx, jitter dx]^dim`` by
``numpy.random.default_rng(seed)`` in grid-point order (one ``(n_grid, dim)`` draw),
*before* the shape is cut: holes and the cylinder's outline are applied to the jittered
positions, so no point lies in a hole or outside the body, and the draw of a point does
not depend on the holes. As ``jitter < 1/2`` every point stays strictly inside its own
grid cell, hence inside the bounding box (no clipping needed). ``jitter = 0`` is the
regular grid, bit for bit (no random number is drawn).

Nodal volumes of a jittered grid (``volumes``):

* ``"voronoi"`` (default): the volume of the point's Voronoi cell among all points of
  the full jittered grid, clipped to the grid's bounding box (exact, by mirroring the
  points near each face). Cells of removed points (holes, outside the cylinder) are not
  given to their neighbours, so the volumes sum to the box minus the removed cells, as
  the ``dx^dim`` cells of a regular grid do. The diagram is made in fixed blocks of
  slabs of the first axis, each with a margin
  (:func:`~peridynamics.geometry.jitter.block_volumes`), so a decomposed run's ranks
  get the same volumes without the whole cloud.
* ``"cell"``: ``dx^dim`` (times the thickness in 2-D), the volume of the grid cell the
  point came from (it contains the point): exact in the mean.

Measured (docs/theory_bond_based.md, "Irregular point clouds"): the Voronoi volumes
halve the modulus deficit of a jittered plate in tension (PMB with the moment
correction: E -0.8 % instead of -1.6 % at jitter 0.25, -1.0 % instead of -2.6 % at 0.4).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from peridynamics.geometry.cloud import GeometryFitWarning, GridFit, Plane, PointCloud
from peridynamics.geometry.jittered_lattice import jittered_lattice
from peridynamics.geometry.lattice import (
    Lattice,
    box_lattice,
    cylinder_lattice,
    disc_lattice,
    fit_cells,
    rectangle_lattice,
)
from peridynamics.geometry.regions import Region

__all__ = ["bar", "box", "cylinder", "disc", "fit_cells", "rectangle"]

NodalVolumes = Literal["voronoi", "cell"]


def _warn(fits: Sequence[GridFit], level: int = 4) -> None:
    """One :class:`GeometryFitWarning` per fitted length, attributed ``level`` frames up
    (the caller of the public generator)."""
    for fit in fits:
        warnings.warn(fit.message(), GeometryFitWarning, stacklevel=level)


def bar(
    length: float,
    dx: float,
    area: float = 1.0,
    origin: float = 0.0,
    nodes_on_boundary: bool = False,
) -> PointCloud:
    """1-D bar of cross-section ``area`` (m^2) from ``origin`` over ``length`` (m).

    ``nodes_on_boundary=True`` puts ``n + 1`` nodes at ``origin + i*dx`` (the end nodes
    get the full volume ``area*dx``, as in Lu & Wang (2016), section 3); otherwise ``n``
    nodes sit at cell centres ``origin + (i + 1/2) dx``. ``n = length / dx`` when the
    length is a whole multiple of ``dx`` (relative tolerance 1e-6); otherwise
    ``n = floor(length / dx)`` and the nodes are centred in the nominal length (a margin
    of ``(length - n dx) / 2`` at both ends), each node keeping the volume ``area*dx``
    (the discrete bar is ``n dx`` long), with a :class:`GeometryFitWarning` and the fit in
    ``cloud.grid_fit``. A length below ``dx`` is a ``ValueError``.
    """
    n, fit = fit_cells(length, dx, "length")
    fits = () if fit is None else (fit,)
    _warn(fits, level=3)
    start = origin if fit is None else origin + fit.margin
    if nodes_on_boundary:
        x = np.asarray(start + np.arange(n + 1) * dx, dtype=np.float64)
    else:
        x = np.asarray(start + (np.arange(n) + 0.5) * dx, dtype=np.float64)
    return PointCloud(
        x=x[:, None],
        volume=np.full(len(x), area * dx),
        spacing=dx,
        cross_section=area,
        grid_fit=fits,
    )


def rectangle(
    size: Sequence[float],
    dx: float,
    thickness: float = 1.0,
    origin: Sequence[float] = (0.0, 0.0),
    plane: Plane = "stress",
    holes: Sequence[Region] = (),
    jitter: float = 0.0,
    seed: int = 0,
    volumes: NodalVolumes = "voronoi",
) -> PointCloud:
    """2-D rectangle of optionally jittered points with optional holes.

    Parameters
    ----------
    size : (Lx, Ly)
        Side lengths (m). A side that is a whole multiple of ``dx`` (relative tolerance
        1e-6) gets ``L / dx`` cells from the origin. Otherwise it gets the
        ``n = floor(L / dx)`` whole cells that fit, centred in ``L`` (a margin of
        ``(L - n dx) / 2`` at both ends); the spacing stays ``dx``, every point keeps the
        volume of its cell (the discrete side is ``n dx``), a
        :class:`GeometryFitWarning` is issued and the fit is kept in ``cloud.grid_fit``.
        A side below ``dx`` is a ``ValueError``.
    dx : float
        Grid spacing (m).
    thickness : float
        Plate thickness h (m); the nodal volume is area * h (m^3).
    origin : (x0, y0)
        Lower-left corner (m).
    plane : {"stress", "strain"}
    holes : sequence of Region
        Cut-outs, applied to the (jittered) positions.
    jitter : float
        Largest offset of a point along each axis as a fraction of ``dx``, 0 <= jitter
        < 0.5 (module docstring); 0 is the regular grid.
    seed : int
        Seed of ``numpy.random.default_rng`` for the offsets (>= 0).
    volumes : {"voronoi", "cell"}
        Nodal volumes of a jittered grid (module docstring); ignored at ``jitter = 0``.
    """
    lattice = rectangle_lattice(size, dx, thickness, origin, plane, holes)
    _warn(lattice.grid_fit, level=3)
    return _jittered_cloud(lattice, jitter, seed, volumes, thickness)


def box(
    size: Sequence[float],
    dx: float,
    origin: Sequence[float] = (0.0, 0.0, 0.0),
    holes: Sequence[Region] = (),
    jitter: float = 0.0,
    seed: int = 0,
    volumes: NodalVolumes = "voronoi",
) -> PointCloud:
    """3-D box ``size = (Lx, Ly, Lz)`` (m) of optionally jittered points, with cut-outs.

    ``origin`` is the lowest corner (m); a side that is not a whole multiple of ``dx``
    is fitted as in :func:`rectangle` (whole cells, centred, volume ``dx^3`` each);
    ``holes``, ``jitter``, ``seed`` and ``volumes`` as in :func:`rectangle` (nodal
    volumes in m^3).
    """
    lattice = box_lattice(size, dx, origin, holes)
    _warn(lattice.grid_fit, level=3)
    return _jittered_cloud(lattice, jitter, seed, volumes)


def cylinder(
    radius: float,
    length: float,
    dx: float,
    origin: ArrayLike = (0.0, 0.0, 0.0),
    holes: Sequence[Region] = (),
    jitter: float = 0.0,
    seed: int = 0,
    volumes: NodalVolumes = "voronoi",
) -> PointCloud:
    """3-D solid cylinder with axis along z from ``origin`` (m): a cubic grid, jittered
    over its bounding box, then cut to the cylinder (``radius``, ``length`` in m).

    Radially the grid has a cell corner on the axis (``ceil(radius / dx)`` cells each
    side) and keeps the points inside the circle, so the radius need not be a multiple
    of ``dx``. Along z a ``length`` that is not a whole multiple of ``dx`` is fitted as
    in :func:`rectangle` (``floor(length / dx)`` cells centred in the length, volume
    ``dx^3`` each, a :class:`GeometryFitWarning`). ``holes``, ``jitter``, ``seed`` and
    ``volumes`` as in :func:`rectangle`.
    """
    lattice = cylinder_lattice(radius, length, dx, origin, holes)
    _warn(lattice.grid_fit, level=3)
    return _jittered_cloud(lattice, jitter, seed, volumes)


def disc(
    radius: float,
    dx: float,
    center: ArrayLike = (0.0, 0.0),
    thickness: float = 1.0,
    plane: Plane = "stress",
    holes: Sequence[Region] = (),
    jitter: float = 0.0,
    seed: int = 0,
    volumes: NodalVolumes = "voronoi",
) -> PointCloud:
    """2-D disc: the points of a square grid centred on the disc that lie inside it.

    The grid has a cell *corner* at the centre: points at ``center + (i + 1/2) dx`` for
    ``i = -N .. N - 1`` along both axes, ``N = ceil(radius / dx)``, so the cloud is
    symmetric about both axes through the centre and under a quarter turn, a diameter
    along x or y runs between two rows of points (a splitting crack along it is not
    biased to either side), and a disc of radius ``R`` with ``2R / dx`` whole is the
    ``rectangle`` of side ``2R`` around it minus the outside of the circle, the way
    discs were built before. Points inside the circle (boundary included) are kept, each
    with the volume ``dx^2 * thickness``; the discrete area ``n dx^2`` approximates
    ``pi R^2`` (docs/deck.md gives measured ratios).

    Parameters
    ----------
    radius : float
        Disc radius R (m), at least ``dx / sqrt(2)`` (else no grid point lies inside).
    dx : float
        Grid spacing (m).
    center : (xc, yc)
        Disc centre (m).
    thickness, plane, holes, jitter, seed, volumes
        As in :func:`rectangle`. With ``jitter > 0`` the full square grid is jittered
        and its Voronoi cells clipped to the square, then the circle is cut (as for the
        cylinder): the volumes of points near the rim are their square-clipped cells,
        not clipped to the circle.

    Returns
    -------
    PointCloud
        Points (n, 2) in m, volumes (n,) in m^3.
    """
    lattice = disc_lattice(radius, dx, center, thickness, plane, holes)
    return _jittered_cloud(lattice, jitter, seed, volumes, thickness)


def _jittered_cloud(
    lattice: Lattice, jitter: float, seed: int, volumes: NodalVolumes, thickness: float = 1.0
) -> PointCloud:
    """The points of a lattice, jittered over its whole grid before the cuts: the
    :class:`~peridynamics.geometry.jittered_lattice.JitteredLattice`'s cloud, whose windows
    a decomposed run makes without the whole cloud (``jitter = 0``: the grid's cell
    centres, each with the volume ``dx^dim``, times ``thickness`` in 2-D)."""
    return jittered_lattice(lattice, jitter, seed, volumes, thickness).cloud()
