"""Jittered grids and their nodal volumes: the uniform offsets of the points of a grid
(``numpy.random.default_rng(seed)``, one ``(n_grid, dim)`` draw in grid-point order) and
the volumes of their Voronoi cells clipped to the grid's bounding box. The generators
that use them and the measured effect are described in
:mod:`peridynamics.geometry.generators`.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import Voronoi

__all__ = ["block_volumes", "check_jitter", "grid_offsets", "voronoi_volumes"]


def check_jitter(jitter: float, seed: int) -> None:
    """Raise ``ValueError`` unless 0 <= ``jitter`` < 0.5 and ``seed`` is an int >= 0."""
    if isinstance(jitter, bool) or not (np.isfinite(jitter) and 0.0 <= jitter < 0.5):
        raise ValueError(
            f"jitter must be a fraction of the spacing with 0 <= jitter < 0.5, got {jitter!r}"
        )
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {seed!r}")


def voronoi_volumes(
    x: NDArray[np.float64],
    lo: ArrayLike,
    hi: ArrayLike,
    reach: float | None = None,
    n_target: int | None = None,
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
    n_target : int, optional
        Only the first ``n_target`` points' volumes are wanted; the others only shape
        their cells (a margin around them: its own cells may be unbounded). Default:
        every point.

    Returns
    -------
    ndarray, shape (n_target,)
        Cell volumes (m^dim); over every point they sum to the box volume.
    """
    x = np.asarray(x, dtype=np.float64)
    n, dim = x.shape
    wanted = n if n_target is None else int(n_target)
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
    keep = np.flatnonzero(rp.min(axis=1) < wanted)  # ridges of at least one wanted point
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
    vol = np.zeros(wanted)
    for end in (0, 1):
        mine = rp[:, end] < wanted
        vol += np.bincount(rp[mine, end], pyramid[mine], minlength=wanted)
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


#: points per block of :func:`block_volumes` (whole slabs of the first axis)
BLOCK_POINTS = 1 << 17
#: slabs of the first axis on each side of a block that shape its points' cells
MARGIN_SLABS = 3


def grid_offsets(
    seed: int, jitter: float, dx: float, start: int, n: int, dim: int
) -> NDArray[np.float64]:
    """The offsets (n, dim) (m) of grid points ``start .. start + n - 1`` (grid order)
    of the one ``(n_grid, dim)`` uniform draw of ``numpy.random.default_rng(seed)``:
    the generator is advanced past the ``start * dim`` earlier numbers (one 64-bit
    output per double), so any window of the grid gets its rows of that draw bit for
    bit without drawing the others."""
    bits = np.random.PCG64(int(seed))  # default_rng(seed)'s generator
    bits.advance(int(start) * int(dim))
    rng = np.random.Generator(bits)
    return rng.uniform(-jitter * dx, jitter * dx, size=(int(n), int(dim)))


def block_slabs(n_slabs: int, per_slab: int) -> int:
    """Slabs per block of :func:`block_volumes`: about :data:`BLOCK_POINTS` points, at
    least 4 slabs (a property of the grid alone, so every rank cuts the same blocks)."""
    return max(4, -(-BLOCK_POINTS // max(per_slab, 1)))


def block_volumes(
    grid: Callable[[int, int], NDArray[np.float64]],
    n_slabs: int,
    per_slab: int,
    lo: ArrayLike,
    hi: ArrayLike,
    dx: float,
    first: int,
    last: int,
) -> NDArray[np.float64]:
    """Voronoi volumes of the grid points of slabs ``first .. last - 1`` (grid order),
    shape ((last - first) * per_slab,), computed block by block.

    The slabs are cut into fixed blocks of :func:`block_slabs` slabs; the cells of a
    block's points are those of the Voronoi diagram of the block and
    :data:`MARGIN_SLABS` slabs on each side (:func:`voronoi_volumes` with ``n_target``):
    exact, as a jittered point's cell reaches less than two spacings, and the same bits
    whoever asks for the block, since it depends on the block alone. ``grid(i0, i1)``
    gives the (jittered) points of slabs ``i0 <= i < i1`` in grid order."""
    size = block_slabs(n_slabs, per_slab)
    out = []
    for b in range(first // size, -(-last // size)):
        b0, b1 = b * size, min((b + 1) * size, n_slabs)
        m0, m1 = max(0, b0 - MARGIN_SLABS), min(n_slabs, b1 + MARGIN_SLABS)
        pts = grid(m0, m1)
        own = slice((b0 - m0) * per_slab, (b1 - m0) * per_slab)
        rest = np.ones(len(pts), dtype=bool)
        rest[own] = False
        vol = voronoi_volumes(
            np.concatenate([pts[own], pts[rest]]), lo, hi, 3.0 * dx, (b1 - b0) * per_slab
        )
        s0, s1 = max(first, b0), min(last, b1)
        out.append(vol[(s0 - b0) * per_slab : (s1 - b0) * per_slab])
    return np.concatenate(out) if out else np.zeros(0)
