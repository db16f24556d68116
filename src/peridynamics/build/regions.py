"""Turn deck region specs into :class:`~peridynamics.geometry.regions.Region` objects."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from peridynamics.deck import RegionSpec
from peridynamics.geometry import regions as rg


class IndexSet(rg.Region):
    """A fixed set of point indices (a reference to another node set, a point chosen on
    the whole body): selects those rows of the points it is given."""

    pointwise = False

    def __init__(self, idx: np.ndarray) -> None:
        self.idx = idx

    def mask(self, x: np.ndarray) -> np.ndarray:
        out = np.zeros(len(x), dtype=bool)
        out[self.idx] = True
        return out


def to_region(
    spec: RegionSpec, known_sets: Mapping[str, np.ndarray] | None = None, spacing: float = 0.0
) -> rg.Region:
    """Build a region from a validated spec; ``set`` refers to ``known_sets``;
    ``spacing`` (m) sizes ``edge`` layers."""
    k = spec.kind()
    v = getattr(spec, k)
    if k == "box":
        return rg.Box(v.min, v.max)
    if k in ("ball", "circle", "sphere"):
        return rg.Ball(v.center, v.radius)
    if k == "cylinder":
        return rg.CylinderRegion(v.base, v.axis, v.radius, v.length)
    if k == "polygon":
        return rg.Polygon(v.vertices)
    if k == "half_space":
        return rg.HalfSpace(v.point, v.normal)
    if k == "edge":
        if not spacing > 0:
            raise ValueError("edge regions need the grid spacing")
        return rg.Layer(v.normal, v.layers * spacing)
    if k == "point":
        return rg.NearestPoint(v, max_distance=spacing if spacing > 0 else np.inf)
    if k == "everywhere":
        return rg.Everywhere()
    if k == "set":
        if known_sets is None or v not in known_sets:
            raise KeyError(f"node set {v!r} is not defined before it is used")
        return IndexSet(np.asarray(known_sets[v]))
    parts = [to_region(s, known_sets, spacing) for s in (v if isinstance(v, list) else [v])]
    if k == "all_of":
        out = parts[0]
        for p in parts[1:]:
            out = out & p
        return out
    if k == "any_of":
        out = parts[0]
        for p in parts[1:]:
            out = out | p
        return out
    return ~parts[0]  # not
