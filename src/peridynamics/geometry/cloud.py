"""The point cloud: reference positions, nodal volumes and named node sets."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from peridynamics.geometry.regions import Region

Plane = Literal["stress", "strain"]


class GeometryFitWarning(UserWarning):
    """A nominal length is not a whole multiple of the spacing: the grid is shorter."""


@dataclass(frozen=True)
class GridFit:
    """How a grid was fitted into a nominal length that is not a whole multiple of the
    spacing: ``cells`` whole cells of side ``spacing``, centred in ``nominal``.

    Attributes
    ----------
    key : str
        The length's name in the generator (``"size[1]"``, ``"length"``).
    nominal : float
        The length asked for (m).
    cells : int
        Whole cells that fit, ``floor(nominal / spacing)``.
    spacing : float
        Grid spacing dx (m).
    """

    key: str
    nominal: float
    cells: int
    spacing: float

    @property
    def grid_length(self) -> float:
        """Length of the discrete body, ``cells * spacing`` (m)."""
        return self.cells * self.spacing

    @property
    def margin(self) -> float:
        """Gap left at each end, ``(nominal - grid_length) / 2`` (m)."""
        return 0.5 * (self.nominal - self.grid_length)

    def as_dict(self) -> dict[str, float | int | str]:
        """The record written to ``summary.json`` (``results.geometry_fit``)."""
        return {
            "key": self.key,
            "nominal_m": self.nominal,
            "grid_m": self.grid_length,
            "cells": self.cells,
            "margin_m": self.margin,
        }

    def message(self) -> str:
        """One line for the warning."""
        return (
            f"geometry {self.key} = {self.nominal:.6g} m is not a whole multiple of the "
            f"spacing {self.spacing:.6g} m: the grid has {self.cells} cells "
            f"({self.grid_length:.6g} m, {self.grid_length / self.nominal:.6f} of it), "
            f"centred with a margin of {self.margin:.4g} m at each end; every point keeps "
            "the volume of its cell"
        )


@dataclass(frozen=True)
class PointCloud:
    """Discretised body.

    Attributes
    ----------
    x : ndarray, shape (n_points, dim)
        Reference positions (m).
    volume : ndarray, shape (n_points,)
        Nodal volumes (m^3). In 1-D ``A * dx``; in 2-D ``dx**2 * thickness``.
    spacing : float
        Nominal grid spacing ``dx`` (m), used for horizon ratios and partial volumes.
    cross_section : float
        1-D: bar cross-section area ``A`` (m^2); 2-D: thickness ``h`` (m); 3-D: 1.
    plane : {"stress", "strain"} or None
        2-D idealisation; ``None`` in 1-D and 3-D.
    node_sets : mapping of str to ndarray of int
        Named, sorted point indices.
    irregular : bool
        True when the points are not on an axis-aligned grid of spacing ``spacing``
        (jittered generators set it): corrections that assume the symmetry of the grid
        family (the axis energy method of the PMB surface correction) do not hold;
        :func:`peridynamics.bonds.surface.moment_correction_factors` does.
    grid_fit : tuple of GridFit
        The lengths of a grid generator that were not whole multiples of the spacing
        (the grid is shorter and centred in them); empty when every length fitted.
    global_ids : ndarray of int, shape (n_points,), optional
        Under MPI, the global id of every point of a rank's part of the body (owned
        points, then ghosts; :mod:`peridynamics.parallel.local`); ``None`` in a serial
        run (the ids are ``0 .. n_points - 1``). Random fields are drawn by global id.
    body_size : float, optional
        Under MPI, the largest extent of the whole body (m), which :attr:`size` returns
        for a rank's part (blow-up checks judge every rank by the body's size); ``None``
        in a serial run.

    Examples
    --------
    >>> import numpy as np
    >>> import peridynamics as pd
    >>> grid = np.meshgrid(np.arange(10), np.arange(5), indexing="ij")
    >>> x = np.stack(grid, -1).reshape(-1, 2) * 1e-3  # m
    >>> cloud = pd.PointCloud(x=x, volume=np.full(50, 1e-9), spacing=1e-3, plane="stress")
    >>> cloud.n_points, cloud.dim
    (50, 2)
    """

    x: NDArray[np.float64]
    volume: NDArray[np.float64]
    spacing: float
    cross_section: float = 1.0
    plane: Plane | None = None
    node_sets: Mapping[str, NDArray[np.intp]] = field(default_factory=dict)
    irregular: bool = False
    grid_fit: tuple[GridFit, ...] = ()
    global_ids: NDArray[np.int64] | None = None
    body_size: float | None = None

    def __post_init__(self) -> None:
        x = np.ascontiguousarray(np.atleast_2d(np.asarray(self.x, dtype=np.float64)))
        if x.shape[0] == 1 and np.asarray(self.x).ndim == 1:
            x = x.T.copy()
        vol = np.ascontiguousarray(np.asarray(self.volume, dtype=np.float64).reshape(-1))
        if x.ndim != 2 or x.shape[1] not in (1, 2, 3):
            raise ValueError(f"positions must have shape (n_points, 1|2|3), got {x.shape}")
        if vol.shape != (x.shape[0],):
            raise ValueError(f"volume must have shape ({x.shape[0]},), got {vol.shape}")
        if x.shape[0] == 0:
            raise ValueError("the point cloud is empty (did a hole or cut-out remove every point?)")
        if not np.all(np.isfinite(x)):
            raise ValueError("positions contain NaN or inf")
        if np.any(vol <= 0) or not np.all(np.isfinite(vol)):
            raise ValueError("every nodal volume must be finite and > 0")
        if not self.spacing > 0:
            raise ValueError("spacing must be > 0")
        if not self.cross_section > 0:
            raise ValueError("cross_section (area in 1-D, thickness in 2-D) must be > 0")
        if x.shape[1] == 2 and self.plane not in ("stress", "strain"):
            raise ValueError("2-D clouds need plane='stress' or plane='strain'")
        x.setflags(write=False)
        vol.setflags(write=False)
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "volume", vol)
        sets = {}
        for name, idx in dict(self.node_sets).items():
            arr = np.unique(np.asarray(idx, dtype=np.intp))
            if arr.size and (arr[0] < 0 or arr[-1] >= x.shape[0]):
                raise ValueError(f"node set {name!r} has indices outside 0..{x.shape[0] - 1}")
            arr.setflags(write=False)
            sets[name] = arr
        object.__setattr__(self, "node_sets", sets)

    @property
    def n_points(self) -> int:
        """Number of points."""
        return int(self.x.shape[0])

    @property
    def dim(self) -> int:
        """Spatial dimension (1, 2 or 3)."""
        return int(self.x.shape[1])

    @property
    def bounds(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lower and upper corners of the bounding box of the points, shape (dim,) each."""
        return self.x.min(axis=0), self.x.max(axis=0)

    @property
    def size(self) -> float:
        """Largest extent of the body (m), the reference length for blow-up checks (the
        whole body's, ``body_size``, for a rank's part under MPI)."""
        if self.body_size is not None:
            return self.body_size
        lo, hi = self.bounds
        return float(max(np.max(hi - lo), self.spacing))

    def select(self, region: Region) -> NDArray[np.intp]:
        """Indices of points inside ``region``."""
        return np.flatnonzero(region(self.x))

    def with_node_sets(self, **sets: Region | ArrayLike) -> PointCloud:
        """Return a copy with extra named node sets (regions or index arrays)."""
        new = dict(self.node_sets)
        for name, spec in sets.items():
            new[name] = self.select(spec) if isinstance(spec, Region) else np.asarray(spec)
        return replace(self, node_sets=new)

    def node_set(self, name: str) -> NDArray[np.intp]:
        """Indices of a named node set; ``KeyError`` names the known sets."""
        try:
            return self.node_sets[name]
        except KeyError:
            known = ", ".join(sorted(self.node_sets)) or "(none)"
            raise KeyError(f"unknown node set {name!r}; known sets: {known}") from None

    def remove(self, region: Region) -> PointCloud:
        """Return a copy without the points inside ``region`` (holes, cut-outs).

        Node sets are re-indexed; points removed from a set simply leave it.
        """
        keep = ~region(self.x)
        new_index = np.full(self.n_points, -1, dtype=np.intp)
        new_index[keep] = np.arange(int(keep.sum()))
        sets = {}
        for name, idx in self.node_sets.items():
            mapped = new_index[idx]
            sets[name] = mapped[mapped >= 0]
        return replace(self, x=self.x[keep], volume=self.volume[keep], node_sets=sets)
