"""The whole body's point cloud as rank 0's observers see it when no rank holds it.

A decomposed run whose ranks made only their own points
(:mod:`peridynamics.parallel.windowed`) gives its observers a :class:`GlobalCloud`:
what describes the body (dimension, number of points, spacing, thickness, bounds, grid
fits) is known on every rank from set-up; the positions, volumes and node sets are
gathered onto rank 0 when an observer first reads them (and kept), through the
session's requests, so they are counted in the gather audit (``timing.to_root``). An
output that reads none of them (frames written by each rank, histories of node sets
reduced on the ranks) never brings a per-point array of the whole body to rank 0.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.geometry.cloud import GridFit, Plane
from peridynamics.geometry.regions import Region


@dataclass(frozen=True)
class CloudMeta:
    """What every rank knows of the whole body after a windowed set-up.

    Attributes
    ----------
    n_points, dim : points of the whole body, spatial dimension.
    spacing, cross_section, plane, irregular, grid_fit : as in
        :class:`~peridynamics.geometry.cloud.PointCloud`.
    lo, hi : (dim,) corners of the bounding box of the points (m).
    set_names : the node sets of the body.
    """

    n_points: int
    dim: int
    spacing: float
    cross_section: float
    plane: Plane | None
    irregular: bool
    grid_fit: tuple[GridFit, ...]
    lo: NDArray[np.float64]
    hi: NDArray[np.float64]
    set_names: tuple[str, ...]


class _NodeSets(Mapping[str, NDArray[np.intp]]):
    """Node sets of a :class:`GlobalCloud`: global ids gathered on first access."""

    def __init__(self, session: Any, names: tuple[str, ...]) -> None:
        self._session = session
        self._names = names
        self._got: dict[str, NDArray[np.intp]] = {}

    def __getitem__(self, name: str) -> NDArray[np.intp]:
        if name not in self._names:
            raise KeyError(name)
        if name not in self._got:
            got = self._session.call("node_set", name)
            self._got[name] = np.asarray(got, dtype=np.intp)
        return self._got[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)


class GlobalCloud:
    """The whole body's cloud (global point order) of a run whose ranks hold only
    their part; per-point arrays are gathered on rank 0 on first use (module docstring).
    Only rank 0 reads it, inside the session's requests."""

    global_ids = None

    def __init__(self, session: Any, meta: CloudMeta) -> None:
        self._session = session
        self.meta = meta
        self.spacing = meta.spacing
        self.cross_section = meta.cross_section
        self.plane = meta.plane
        self.irregular = meta.irregular
        self.grid_fit = meta.grid_fit
        self.node_sets = _NodeSets(session, meta.set_names)
        self._fields: dict[str, NDArray[Any]] = {}

    @property
    def n_points(self) -> int:
        """Points of the whole body."""
        return self.meta.n_points

    @property
    def dim(self) -> int:
        """Spatial dimension."""
        return self.meta.dim

    @property
    def bounds(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lower and upper corners of the bounding box of the points (m)."""
        return self.meta.lo, self.meta.hi

    @property
    def size(self) -> float:
        """Largest extent of the body (m)."""
        return float(max(np.max(self.meta.hi - self.meta.lo), self.spacing))

    def _field(self, name: str) -> NDArray[Any]:
        if name not in self._fields:
            self._fields[name] = np.asarray(self._session.call("cloud_field", name))
        return self._fields[name]

    @property
    def x(self) -> NDArray[np.float64]:
        """(n_points, dim) reference positions (m), gathered on first use."""
        return self._field("x")

    @property
    def volume(self) -> NDArray[np.float64]:
        """(n_points,) nodal volumes (m^3), gathered on first use."""
        return self._field("volume")

    def node_set(self, name: str) -> NDArray[np.intp]:
        """Global ids of a named node set; ``KeyError`` names the known sets."""
        try:
            return self.node_sets[name]
        except KeyError:
            known = ", ".join(sorted(self.node_sets)) or "(none)"
            raise KeyError(f"unknown node set {name!r}; known sets: {known}") from None

    def select(self, region: Region) -> NDArray[np.intp]:
        """Global ids of the points inside ``region`` (gathers the positions)."""
        return np.flatnonzero(region(self.x))
