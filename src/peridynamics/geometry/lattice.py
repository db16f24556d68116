"""A grid body described without its points: the axes of a cell-centre grid and the
regions cut out of it, from which any window of points, with its global ids, is made
on demand.

The regular generators (:func:`~peridynamics.geometry.generators.rectangle`, ``box``,
``disc``, ``cylinder`` without jitter) are :meth:`Lattice.cloud` of the lattices made
here, so a window of a lattice is, bit for bit, the rows of the generator's cloud it
holds. Points are numbered in grid order (``"ij"``: the first axis slowest), skipping
the removed ones; the global id of a point is the number of kept points before it.
A decomposed run (:mod:`peridynamics.parallel.windowed`) makes only the window each
rank holds, a slab of the first axis at a time, so no rank holds the whole cloud:
:meth:`Lattice.slab_counts` numbers the slabs and :meth:`Lattice.window` makes the
points.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from peridynamics.geometry.cloud import GridFit, Plane, PointCloud
from peridynamics.geometry.regions import Ball, CylinderRegion, Region, is_pointwise


@dataclass(frozen=True)
class Lattice:
    """Cell centres of a grid minus removed regions.

    Attributes
    ----------
    axes : tuple of (n_k,) float64 arrays
        Cell-centre coordinates along each axis (m), one array per dimension.
    lo, hi : (dim,) float64
        Corners of the grid's box (m).
    spacing : float
        Grid spacing dx (m).
    cell_volume : float
        Volume of every point (m^3): ``dx**dim`` times the thickness in 2-D.
    removed : tuple of Region
        Regions whose points are not part of the body (holes, the outside of a disc or a
        cylinder, notches); each must be point-wise (:func:`is_pointwise`).
    cross_section, plane, grid_fit
        As in :class:`~peridynamics.geometry.cloud.PointCloud`.
    """

    axes: tuple[NDArray[np.float64], ...]
    lo: NDArray[np.float64]
    hi: NDArray[np.float64]
    spacing: float
    cell_volume: float
    removed: tuple[Region, ...] = ()
    cross_section: float = 1.0
    plane: Plane | None = None
    grid_fit: tuple[GridFit, ...] = ()

    def __post_init__(self) -> None:
        for r in self.removed:
            if not is_pointwise(r):
                raise ValueError(
                    "a lattice removes point-wise regions only (not an edge layer or a "
                    "nearest point, which depend on the whole body)"
                )

    @property
    def dim(self) -> int:
        """Spatial dimension."""
        return len(self.axes)

    @property
    def shape(self) -> tuple[int, ...]:
        """Cells along each axis."""
        return tuple(int(a.size) for a in self.axes)

    @property
    def irregular(self) -> bool:
        """False: the points are the cell centres of a regular grid."""
        return False

    def volumes_at(self, index: NDArray[np.intp]) -> NDArray[np.float64]:
        """Nodal volumes (m^3) of the grid points of indices ``index`` (n, dim): the
        cell volume of each."""
        return np.full(len(index), self.cell_volume)

    def with_removed(self, *regions: Region) -> Lattice:
        """The lattice with further regions removed (notches)."""
        return Lattice(
            self.axes, self.lo, self.hi, self.spacing, self.cell_volume,
            (*self.removed, *regions),
            self.cross_section, self.plane, self.grid_fit,
        )  # fmt: skip

    # -- points ----------------------------------------------------------------------------
    def grid(self, i0: int = 0, i1: int | None = None) -> NDArray[np.float64]:
        """Every cell centre of the slabs ``i0 <= i < i1`` of the first axis, grid order,
        shape (n, dim) (m), removed ones included."""
        first = self.axes[0][i0:i1]
        g = np.meshgrid(first, *self.axes[1:], indexing="ij")
        return np.column_stack([a.ravel() for a in g])

    def kept(self, x: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Which of the grid points ``x`` (n, dim) are not removed, shape (n,)."""
        keep = np.ones(x.shape[0], dtype=bool)
        for r in self.removed:
            keep &= ~r(x)
        return keep

    def cloud(self) -> PointCloud:
        """The whole body as a :class:`PointCloud` (without node sets)."""
        x = self.grid()
        x = x[self.kept(x)]
        return PointCloud(
            x=x,
            volume=np.full(x.shape[0], self.cell_volume),
            spacing=self.spacing,
            cross_section=self.cross_section,
            plane=self.plane,
            grid_fit=self.grid_fit,
        )

    def slab_counts(self, slabs: NDArray[np.intp]) -> NDArray[np.int64]:
        """Kept points in each of the given slabs of the first axis, shape (len(slabs),)."""
        out = np.zeros(len(slabs), dtype=np.int64)
        for k, i in enumerate(slabs):
            out[k] = int(self.kept(self.grid(int(i), int(i) + 1)).sum())
        return out

    def window(
        self, lo: Sequence[int], hi: Sequence[int], slab_start: NDArray[np.int64]
    ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.intp]]:
        """The kept points with grid index ``lo[k] <= index_k < hi[k]`` on every axis, in
        grid order, with their global ids and grid indices.

        Made a slab of the first axis at a time: memory is that of the window plus one
        slab.

        Parameters
        ----------
        lo, hi : grid index bounds (clipped to the grid).
        slab_start : (shape[0] + 1,) global id of the first kept point of every slab
            (the cumulative :meth:`slab_counts`).

        Returns
        -------
        x : (n, dim) positions (m); ids : (n,) int64 global ids, increasing;
        index : (n, dim) grid indices.
        """
        lo = [max(0, int(v)) for v in lo]
        hi = [min(n, int(v)) for v, n in zip(hi, self.shape, strict=True)]
        xs, ids, index = (
            [np.zeros((0, self.dim))],
            [np.zeros(0, np.int64)],
            [np.zeros((0, self.dim), np.intp)],
        )
        if all(h > lo_ for lo_, h in zip(lo, hi, strict=True)):
            rest = self.shape[1:]
            inner = np.zeros(rest, dtype=bool)
            inner[tuple(slice(a, b) for a, b in zip(lo[1:], hi[1:], strict=True))] = True
            inner_flat = inner.reshape(-1)
            rest_index = np.column_stack(np.unravel_index(np.arange(inner.size), rest))
            for i in range(lo[0], hi[0]):
                x = self.grid(i, i + 1)
                keep = self.kept(x)
                gid = slab_start[i] + np.cumsum(keep) - 1
                take = keep & inner_flat
                xs.append(x[take])
                ids.append(gid[take].astype(np.int64))
                row = np.empty((int(take.sum()), self.dim), dtype=np.intp)
                row[:, 0] = i
                row[:, 1:] = rest_index[take]
                index.append(row)
        return np.concatenate(xs), np.concatenate(ids), np.concatenate(index)


def fit_cells(length: float, dx: float, what: str) -> tuple[int, GridFit | None]:
    """Whole cells of side ``dx`` (m) that fit in ``length`` (m), and the fit record.

    An exact multiple (``|round(L / dx) dx - L| <= 1e-6 L``) gives ``round(L / dx)``
    cells and ``None``: the grid starts at the origin, as it always did. Otherwise
    ``n = floor(L / dx)`` cells, centred in ``L``, and a :class:`GridFit` saying so.
    ``L < dx`` (no whole cell fits) is a ``ValueError`` naming ``what``.
    """
    if not length > 0:
        raise ValueError(f"{what} must be > 0, got {length}")
    if not dx > 0:
        raise ValueError(f"spacing must be > 0, got {dx}")
    n = int(round(length / dx))
    if n >= 1 and abs(n * dx - length) <= 1e-6 * length:
        return n, None
    n = int(np.floor(length / dx))
    if n < 1:
        raise ValueError(
            f"{what} = {length} m is shorter than the spacing {dx} m: no whole grid cell "
            f"fits; use a spacing <= {length} m"
        )
    return n, GridFit(what, float(length), n, float(dx))


def _axis(
    lo: float, length: float, dx: float, what: str
) -> tuple[NDArray[np.float64], float, GridFit | None]:
    """Cell centres (n,) of the grid fitted into [lo, lo + length] (m), the grid's lower
    end (m) and the fit record (``None`` for an exact multiple, then the centres are
    ``lo + (k + 1/2) dx`` bit for bit)."""
    n, fit = fit_cells(length, dx, what)
    start = lo if fit is None else lo + fit.margin
    return np.asarray(start + (np.arange(n) + 0.5) * dx, dtype=np.float64), start, fit


def _grid_axes(
    origin: Sequence[float], size: Sequence[float], dx: float, names: Sequence[str]
) -> tuple[tuple[NDArray[np.float64], ...], NDArray[np.float64], NDArray[np.float64],
           tuple[GridFit, ...]]:  # fmt: skip
    """Cell-centre axes of a box grid, its lower and upper corners (dim,) (m) and the fit
    records of the sides that are not multiples of dx."""
    axes = [_axis(origin[k], size[k], dx, names[k]) for k in range(len(size))]
    lo = np.array([a[1] for a in axes], dtype=np.float64)
    hi = lo + np.array([a[0].size for a in axes]) * dx
    fits = tuple(a[2] for a in axes if a[2] is not None)
    return tuple(a[0] for a in axes), lo, hi, fits


def rectangle_lattice(
    size: Sequence[float],
    dx: float,
    thickness: float = 1.0,
    origin: Sequence[float] = (0.0, 0.0),
    plane: Plane = "stress",
    holes: Sequence[Region] = (),
) -> Lattice:
    """The lattice of :func:`~peridynamics.geometry.generators.rectangle` (same
    parameters, no jitter); no warning is issued for fitted sides (``grid_fit``)."""
    axes, lo, hi, fits = _grid_axes(origin, size, dx, ("size[0]", "size[1]"))
    return Lattice(axes, lo, hi, dx, dx**2 * thickness, tuple(holes), thickness, plane, fits)


def box_lattice(
    size: Sequence[float],
    dx: float,
    origin: Sequence[float] = (0.0, 0.0, 0.0),
    holes: Sequence[Region] = (),
) -> Lattice:
    """The lattice of :func:`~peridynamics.geometry.generators.box` (no jitter)."""
    axes, lo, hi, fits = _grid_axes(origin, size, dx, ("size[0]", "size[1]", "size[2]"))
    return Lattice(axes, lo, hi, dx, dx**3, tuple(holes), grid_fit=fits)


def cylinder_lattice(
    radius: float,
    length: float,
    dx: float,
    origin: ArrayLike = (0.0, 0.0, 0.0),
    holes: Sequence[Region] = (),
) -> Lattice:
    """The lattice of :func:`~peridynamics.geometry.generators.cylinder` (no jitter):
    the grid of its bounding box minus the outside of the cylinder and the holes."""
    if not radius > 0:
        raise ValueError("radius must be > 0")
    o = np.asarray(origin, dtype=float)
    n_r = int(np.ceil(radius / dx))
    span = 2 * n_r * dx
    corner = (o[0] - n_r * dx, o[1] - n_r * dx, o[2])
    axes, lo, hi, fits = _grid_axes(corner, (span, span, length), dx, ("span", "span", "length"))
    inside = CylinderRegion(base=o, axis=(0, 0, 1), radius=radius, length=length)
    return Lattice(axes, lo, hi, dx, dx**3, (~inside, *holes), grid_fit=fits)


def disc_lattice(
    radius: float,
    dx: float,
    center: ArrayLike = (0.0, 0.0),
    thickness: float = 1.0,
    plane: Plane = "stress",
    holes: Sequence[Region] = (),
) -> Lattice:
    """The lattice of :func:`~peridynamics.geometry.generators.disc` (no jitter): the
    square grid with a cell corner on the centre minus the outside of the circle."""
    if not radius > 0:
        raise ValueError(f"radius must be > 0, got {radius}")
    if not dx > 0:
        raise ValueError(f"spacing must be > 0, got {dx}")
    if radius < dx / math.sqrt(2.0) * (1.0 - 1e-12):
        raise ValueError(
            f"radius = {radius} m is below spacing / sqrt(2) = {dx / math.sqrt(2.0):.6g} m: "
            "no grid point lies inside the disc (the nearest are (+-dx/2, +-dx/2) from "
            f"its centre); use a spacing <= {radius * math.sqrt(2.0):.6g} m"
        )
    c = np.asarray(center, dtype=np.float64)
    if c.shape != (2,):
        raise ValueError(f"center must be 2 coordinates [x, y], got shape {c.shape}")
    n_r = max(1, int(np.ceil(radius / dx * (1.0 - 1e-9))))
    offsets = (np.arange(-n_r, n_r) + 0.5) * dx  # exactly antisymmetric about 0
    axes = (c[0] + offsets, c[1] + offsets)
    lo, hi = c - n_r * dx, c + n_r * dx
    return Lattice(
        axes, lo, hi, dx, dx**2 * thickness, (~Ball(c, radius), *holes), thickness, plane
    )
