"""Jittered grids and their nodal volumes: the uniform offsets of the points of a grid
(``numpy.random.default_rng(seed)``, one ``(n_grid, dim)`` draw in grid-point order) and
the volumes of their Voronoi cells clipped to the grid's bounding box. The generators
that use them and the measured effect are described in
:mod:`peridynamics.geometry.generators`.
"""

from __future__ import annotations

import itertools

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import Voronoi

__all__ = ["check_jitter", "jittered", "voronoi_volumes"]


def check_jitter(jitter: float, seed: int) -> None:
    """Raise ``ValueError`` unless 0 <= ``jitter`` < 0.5 and ``seed`` is an int >= 0."""
    if isinstance(jitter, bool) or not (np.isfinite(jitter) and 0.0 <= jitter < 0.5):
        raise ValueError(
            f"jitter must be a fraction of the spacing with 0 <= jitter < 0.5, got {jitter!r}"
        )
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {seed!r}")


def jittered(
    x: NDArray[np.float64],
    dx: float,
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    jitter: float,
    seed: int,
    volumes: str,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Grid points ``x`` (n, dim) of the box [lo, hi] (m) moved by uniform offsets in
    [-jitter dx, jitter dx]^dim, and their nodal volumes (m^dim), shape (n,)."""
    check_jitter(jitter, seed)
    if volumes not in ("voronoi", "cell"):
        raise ValueError(f"volumes must be 'voronoi' or 'cell', got {volumes!r}")
    dim = x.shape[1]
    cell = np.full(len(x), dx**dim)
    if jitter == 0:
        return x, cell
    rng = np.random.default_rng(int(seed))
    moved = np.asarray(x + rng.uniform(-jitter * dx, jitter * dx, size=x.shape), np.float64)
    if volumes == "cell":
        return moved, cell
    return moved, voronoi_volumes(moved, lo, hi, reach=3.0 * dx)


def voronoi_volumes(
    x: NDArray[np.float64],
    lo: ArrayLike,
    hi: ArrayLike,
    reach: float | None = None,
) -> NDArray[np.float64]:
    """Volumes (areas in 2-D) of the Voronoi cells of points ``x`` clipped to a box.

    The points near each face are mirrored across it: the bisector of a point and its
    mirror is the face, and no mirror is nearer than the original to a point inside,
    so the cells of the original points are exactly their box-clipped cells.

    Parameters
    ----------
    x : ndarray, shape (n_points, dim), dim in (2, 3)
        Distinct points (m) strictly inside the box.
    lo, hi : array_like, shape (dim,)
        Lowest and highest corner of the box (m).
    reach : float, optional
        Mirror only the points closer than this to a face (m); it must exceed the
        width of the cells that touch the face (3 dx is ample for a jittered grid).
        Default: every point.

    Returns
    -------
    ndarray, shape (n_points,)
        Cell volumes (m^dim); they sum to the box volume.
    """
    x = np.asarray(x, dtype=np.float64)
    n, dim = x.shape
    lo_, hi_ = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    if dim not in (2, 3):
        raise ValueError(f"Voronoi volumes need 2-D or 3-D points, got dim {dim}")
    if np.any(x <= lo_) or np.any(x >= hi_):
        raise ValueError("every point must lie strictly inside the box")
    near = np.inf if reach is None else float(reach)
    parts = [x]
    for k, side in itertools.product(range(dim), range(2)):
        face = (lo_, hi_)[side][k]
        sel = np.abs(x[:, k] - face) < near
        mirrored = x[sel].copy()
        mirrored[:, k] = 2.0 * face - mirrored[:, k]
        parts.append(mirrored)
    pts = np.concatenate(parts)
    vor = Voronoi(pts)
    rp = np.asarray(vor.ridge_points)
    keep = np.flatnonzero(rp.min(axis=1) < n)  # ridges of at least one original point
    rp = rp[keep]
    ridges = [vor.ridge_vertices[k] for k in keep]
    sizes = np.fromiter((len(r) for r in ridges), dtype=np.int64, count=len(ridges))
    verts = np.fromiter(itertools.chain.from_iterable(ridges), dtype=np.int64)
    if verts.size == 0 or verts.min() < 0:
        raise ValueError("a Voronoi cell is unbounded: increase reach")
    p, q = pts[rp[:, 0]], pts[rp[:, 1]]
    height = 0.5 * np.linalg.norm(q - p, axis=1)  # point to the bisector
    owner = np.repeat(np.arange(len(rp)), sizes)
    v = vor.vertices[verts]
    if dim == 2:
        face = np.linalg.norm(v[1::2] - v[0::2], axis=1)  # two vertices per ridge
    else:
        face = _polygon_areas(v, owner, sizes, (q - p) / (2.0 * height[:, None]))
    pyramid = face * height / dim
    vol = np.zeros(n)
    for end in (0, 1):
        mine = rp[:, end] < n
        vol += np.bincount(rp[mine, end], pyramid[mine], minlength=n)
    return vol


def _polygon_areas(
    v: NDArray[np.float64],
    owner: NDArray[np.int64],
    sizes: NDArray[np.int64],
    normal: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Areas of convex planar polygons whose unordered vertices ``v`` (m, 3) belong to
    polygon ``owner`` (m,), ``sizes`` vertices each, unit ``normal`` (k, 3) each."""
    k = len(sizes)
    centre = np.zeros((k, 3))
    for c in range(3):
        centre[:, c] = np.bincount(owner, v[:, c], minlength=k) / sizes
    # in-plane basis: e1 normal to the normal and to its least aligned axis
    axis = np.eye(3)[np.argmin(np.abs(normal), axis=1)]
    e1 = np.cross(normal, axis)
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    e2 = np.cross(normal, e1)
    d = v - centre[owner]
    angle = np.arctan2(np.einsum("ij,ij->i", d, e2[owner]), np.einsum("ij,ij->i", d, e1[owner]))
    order = np.lexsort((angle, owner))  # vertices in order around each centre
    d = d[order]
    start = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    nxt = np.arange(len(d)) + 1
    last = start + sizes - 1
    nxt[last] = start
    tri = 0.5 * np.linalg.norm(np.cross(d, d[nxt]), axis=1)
    return np.asarray(np.bincount(owner[order], tri, minlength=k), dtype=np.float64)
