"""Crack-path extraction from a damage field: polylines, lengths, angles and tip speeds.

A crack is the set of damaged points (local damage ``>= threshold``) connected to a
*seed* -- a point such as a notch tip, or a region of seed points -- through neighbours
closer than ``link_factor`` spacings. Connectivity (``scipy.sparse.csgraph``) keeps the
path on the seed's crack: a crack that does not touch the seed's cluster is never
followed, however far it runs (the fault of "the farthest damaged point from an origin",
:func:`peridynamics.analysis.crack.crack_tip`).

The skeleton of the cluster is built from the geodesic distance g (shortest path inside
the cluster, Dijkstra) from the seed:

1. the points are binned by g in steps of ``bin_factor`` spacings;
2. the points of one bin are split into connected pieces (level-set components);
3. each piece hangs from the piece of the previous bin that holds the Dijkstra
   predecessor of its nearest point, so the pieces form a tree rooted at the seed
   (a discrete Reeb graph of g);
4. the path of a branch is the chain of piece centroids from the seed to a leaf, closed
   by the leaf's farthest point (the tip).

The main path ends at the farthest point of the cluster along the cluster (largest g),
not at the farthest point in straight line from an origin. Side branches longer than
``min_branch_length`` beyond their junction are returned too, longest first.

Several seeds can be extracted together (:func:`extract_crack_paths`): every damaged
point then belongs to the seed nearest to it along the cluster (one multi-source
Dijkstra), so two cracks that meet are split where they meet instead of one seed's path
running on along the other's crack.

Tip speeds come from the history of the path length by a local least-squares slope
(:func:`tip_speed_from_paths`) and are flagged, never clipped, where they exceed the
Rayleigh speed of the model as run (:func:`rayleigh_speed`, Viktorov (1967)).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

__all__ = [
    "CrackPath",
    "extract_crack_path",
    "extract_crack_paths",
    "polyline_angles",
    "rayleigh_speed",
    "tip_speed_from_paths",
]

_EPS = 1e-12


@dataclass(frozen=True)
class CrackPath:
    """One crack extracted from a damage field.

    Attributes
    ----------
    vertices : ndarray, shape (k, dim)
        Polyline of the main branch (the one reaching farthest from the seed along the
        cluster; the longest, up to the grid-scale difference of path and reach) from
        the seed to the tip, m. ``k >= 1``;
        an empty crack has the seed (or the seed region's centroid) as its only vertex.
    length : float
        Length of the polyline, m.
    initial_angle_deg : float
        Angle of the initial segment, degrees: the chord from the first vertex to the
        point of the polyline at arc length ``initial_length`` (clipped to ``length``),
        measured from ``reference_direction``. In 2-D it is signed, counter-clockwise
        positive, in (-180, 180]; in 3-D it is the unsigned angle in [0, 180]. NaN for
        an empty crack.
    angles_deg : ndarray, shape (k,)
        Direction of the path at each vertex from ``reference_direction``, degrees (same
        convention as ``initial_angle_deg``): the chord between the points of the
        polyline at arc lengths s - w/2 and s + w/2 (clipped to the ends), w the
        ``angle_window`` of :func:`extract_crack_path`. The raw angles of the segments,
        noisier by the grid-scale jitter of the vertices, are
        ``polyline_angles(vertices, reference_direction)``.
    arc_length : ndarray, shape (k,)
        Cumulative length along the polyline at each vertex, m (0 at the seed).
    tip : ndarray, shape (dim,)
        Last vertex: the point of the cluster farthest from the seed along the cluster, m.
    tip_index : int
        Index of the tip in the input point arrays; -1 for an empty crack.
    points : ndarray of int, shape (m,)
        Indices (into the input arrays) of the damaged points of the crack's cluster.
    geodesic : ndarray, shape (m,)
        Distance from the seed along the cluster of each of ``points``, m.
    initial_length : float
        Arc length the initial angle was measured over, m.
    reference_direction : ndarray, shape (dim,)
        Unit vector the angles are measured from.
    branches : tuple of ndarray, each shape (k_b, dim)
        Polylines of every branch kept, each from the seed to its own tip, m; the first
        is ``vertices``. Side branches are listed by decreasing length.
    branch_lengths : ndarray, shape (n_branches,)
        Length of each polyline of ``branches``, m.
    """

    vertices: NDArray[np.float64]
    length: float
    initial_angle_deg: float
    angles_deg: NDArray[np.float64]
    arc_length: NDArray[np.float64]
    tip: NDArray[np.float64]
    tip_index: int
    points: NDArray[np.intp]
    geodesic: NDArray[np.float64]
    initial_length: float
    reference_direction: NDArray[np.float64]
    branches: tuple[NDArray[np.float64], ...] = field(default_factory=tuple)
    branch_lengths: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))

    @property
    def n_branches(self) -> int:
        """Number of branches kept (0 for an empty crack, 1 for an unbranched one)."""
        return len(self.branches)

    @property
    def empty(self) -> bool:
        """True when no damaged point is connected to the seed."""
        return self.tip_index < 0

    def point_at(self, s: float) -> NDArray[np.float64]:
        """Point of the main polyline at arc length ``s`` (m, clipped to [0, length]).

        Returns
        -------
        ndarray, shape (dim,)
            Position, m.
        """
        return _point_at(self.vertices, self.arc_length, s)

    def angle_over(self, s: float) -> float:
        """Angle (degrees) of the chord from the first vertex to the point at arc length
        ``s`` (m), from ``reference_direction``; NaN for an empty crack."""
        if self.length <= 0.0:
            return math.nan
        return float(
            _angles(
                (self.point_at(s) - self.vertices[0])[None, :],
                self.reference_direction,
            )[0]
        )


def _unit(v: ArrayLike, dim: int) -> NDArray[np.float64]:
    a = np.asarray(v, dtype=np.float64).reshape(-1)
    if a.shape != (dim,):
        raise ValueError(f"reference_direction needs {dim} components, got {a.shape[0]}")
    n = float(np.linalg.norm(a))
    if n == 0.0 or not math.isfinite(n):
        raise ValueError("reference_direction must be non-zero and finite")
    return a / n


def _angles(seg: NDArray[np.float64], ref: NDArray[np.float64]) -> NDArray[np.float64]:
    """Angle (degrees) of each row of ``seg`` (j, dim) from the unit vector ``ref``."""
    if seg.shape[0] == 0:
        return np.zeros(0)
    dot = seg @ ref
    if seg.shape[1] == 2:
        cross = ref[0] * seg[:, 1] - ref[1] * seg[:, 0]
        return np.degrees(np.arctan2(cross, dot))
    norm = np.linalg.norm(seg, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.clip(dot / norm, -1.0, 1.0)
    return np.degrees(np.arccos(c))


def polyline_angles(
    vertices: ArrayLike, reference_direction: ArrayLike | None = None
) -> NDArray[np.float64]:
    """Angle of each segment of a polyline from a reference direction.

    Parameters
    ----------
    vertices : array_like, shape (k, dim)
        Polyline vertices, m.
    reference_direction : array_like, shape (dim,), optional
        Direction the angles are measured from (normalised here); default +x.

    Returns
    -------
    ndarray, shape (k - 1,)
        Degrees; signed (counter-clockwise positive) in 2-D, unsigned in 3-D.
    """
    v = np.asarray(vertices, dtype=np.float64)
    dim = v.shape[1]
    ref = _unit(np.eye(dim)[0] if reference_direction is None else reference_direction, dim)
    return _angles(np.diff(v, axis=0), ref)


def _arc(v: NDArray[np.float64]) -> NDArray[np.float64]:
    seg = np.linalg.norm(np.diff(v, axis=0), axis=1)
    return np.concatenate([[0.0], np.cumsum(seg)])


def _point_at(v: NDArray[np.float64], arc: NDArray[np.float64], s: float) -> NDArray[np.float64]:
    if v.shape[0] == 1:
        return v[0].copy()
    s = min(max(float(s), 0.0), float(arc[-1]))
    return np.array([np.interp(s, arc, v[:, j]) for j in range(v.shape[1])])


def _empty(
    start: NDArray[np.float64], ref: NDArray[np.float64], init_len: float, dim: int
) -> CrackPath:
    v = start.reshape(1, dim).copy()
    return CrackPath(
        vertices=v,
        length=0.0,
        initial_angle_deg=math.nan,
        angles_deg=np.full(1, math.nan),
        arc_length=np.zeros(1),
        tip=v[0].copy(),
        tip_index=-1,
        points=np.zeros(0, dtype=np.intp),
        geodesic=np.zeros(0),
        initial_length=init_len,
        reference_direction=ref,
        branches=(),
        branch_lengths=np.zeros(0),
    )


def _sources(
    seed: ArrayLike,
    xa: NDArray[np.float64],
    idx: NDArray[np.intp],
    link: float,
    r_s: float,
) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
    """Cracked points a seed starts from (indices into ``idx``), their distance from the
    seed (m) and the start of the path (dim,)."""
    n, dim = xa.shape
    pts = xa[idx]
    s_arr = np.asarray(seed)
    if s_arr.dtype == bool:
        mask = s_arr.reshape(-1)
        if mask.shape != (n,):
            raise ValueError(f"a seed mask must have shape ({n},), got {mask.shape}")
        if not mask.any():
            raise ValueError("the seed mask selects no point")
        if idx.size:
            dist, _ = cKDTree(xa[mask]).query(pts, distance_upper_bound=link * (1 + 1e-9))
        else:
            dist = np.zeros(0)
        src = np.flatnonzero(np.isfinite(dist))
        return src, np.where(mask[idx[src]], 0.0, dist[src]), xa[mask].mean(axis=0)
    start = s_arr.astype(np.float64).reshape(-1)
    if start.shape != (dim,):
        raise ValueError(f"a seed point needs {dim} components, got {start.shape[0]}")
    offset = np.linalg.norm(pts - start, axis=1) if idx.size else np.zeros(0)
    src = np.flatnonzero(offset <= r_s)
    return src, offset[src], start


def extract_crack_path(
    x: ArrayLike,
    damage: ArrayLike,
    seed: ArrayLike,
    spacing: float,
    threshold: float = 0.35,
    *,
    exclude: ArrayLike | None = None,
    within: ArrayLike | None = None,
    seed_radius: float | None = None,
    link_factor: float = 1.5,
    bin_factor: float = 2.0,
    initial_length: float | None = None,
    reference_direction: ArrayLike | None = None,
    min_branch_length: float | None = None,
    angle_window: float | None = None,
) -> CrackPath:
    """Extract the crack that grows from a seed as a polyline.

    Parameters
    ----------
    x : array_like, shape (n, dim)
        Point positions, m (reference positions give the path in the undeformed body;
        deformed positions ``x + u`` work too). ``dim`` is 2 or 3.
    damage : array_like, shape (n,)
        Local damage of each point, in [0, 1].
    seed : array_like, shape (dim,) or (n,) bool
        Where the crack starts. A point (e.g. the notch tip), m: the crack's first points
        are the damaged points within ``seed_radius`` of it and the path starts at it.
        Or a boolean mask of seed points (a region, e.g. the notch-tip zone): the crack's
        first points are the damaged points inside it or within ``link_factor`` spacings
        of it, and the path starts at the centroid of the seed points.
    spacing : float
        Grid spacing dx, m.
    threshold : float, optional
        A point counts as cracked from this damage on (default 0.35, as the crack-tip
        tracker of ``output.crack_tip``).
    exclude : array_like of bool, shape (n,), optional
        Points never to count as cracked, e.g. those damaged at t = 0 by pre-cracks or
        notches (``point_damage(initial bonds) >= threshold``).
    within : array_like of bool, shape (n,), optional
        Only these points may count as cracked (a region of interest, e.g. the side of
        a notch a crack is expected to run on).
    seed_radius : float, optional
        Point seeds only: radius of the seed zone, m; default 4 spacings (the damaged
        points next to a pre-crack tip are usually excluded, so the new crack's first
        cracked point lies a few spacings from the tip).
    link_factor : float, optional
        Two cracked points are neighbours when closer than ``link_factor * spacing``
        (default 1.5: the eight grid neighbours in 2-D).
    bin_factor : float, optional
        Width of the geodesic-distance bins, in spacings (default 2).
    initial_length : float, optional
        Arc length of the initial segment whose angle is ``initial_angle_deg``, m;
        default 5 spacings.
    reference_direction : array_like, shape (dim,), optional
        Direction the angles are measured from (e.g. the notch direction); default +x.
    min_branch_length : float, optional
        A side branch is kept when it reaches at least this far (m, along the cluster)
        beyond its junction; default 4 bins (8 spacings), longer than the spurs of a
        damage band 2 horizons wide.
    angle_window : float, optional
        Arc length over which ``angles_deg`` is measured, m; default 6 spacings
        (3 bins).

    Returns
    -------
    CrackPath
        The main branch (the one reaching farthest from the seed along the cluster),
        with every branch kept in ``branches``.

    See Also
    --------
    extract_crack_paths : several seeds at once; each damaged point belongs to the
        crack of the seed nearest to it along the cluster.

    Notes
    -----
    Cost: one k-d tree over the cracked points, one connected-components pass and one
    Dijkstra over the cluster graph (O(m log m) for m cracked points); the only Python
    loops run over bins (path vertices) and branches.
    """
    return extract_crack_paths(
        x,
        damage,
        [seed],
        spacing,
        threshold,
        exclude=exclude,
        within=within,
        seed_radius=seed_radius,
        link_factor=link_factor,
        bin_factor=bin_factor,
        initial_length=initial_length,
        reference_direction=reference_direction,
        min_branch_length=min_branch_length,
        angle_window=angle_window,
    )[0]


def extract_crack_paths(
    x: ArrayLike,
    damage: ArrayLike,
    seeds: Sequence[ArrayLike],
    spacing: float,
    threshold: float = 0.35,
    *,
    exclude: ArrayLike | None = None,
    within: ArrayLike | None = None,
    seed_radius: float | None = None,
    link_factor: float = 1.5,
    bin_factor: float = 2.0,
    initial_length: float | None = None,
    reference_direction: ArrayLike | Sequence[ArrayLike] | None = None,
    min_branch_length: float | None = None,
    angle_window: float | None = None,
) -> list[CrackPath]:
    """Extract the cracks of several seeds that may meet in one damaged cluster.

    Each damaged point belongs to the seed nearest to it along the cluster (a geodesic
    Voronoi partition from one multi-source Dijkstra), so two cracks that join -- the
    cracks of the two notches of a Kalthoff-Winkler plate linked by a crack between
    them, say -- are split where they meet instead of one seed's path running on along
    the other's crack.

    Parameters
    ----------
    x, damage, spacing, threshold
        As :func:`extract_crack_path`.
    seeds : sequence of array_like, each shape (dim,) or (n,) bool
        One seed per crack (points or boolean masks, as in :func:`extract_crack_path`).
    reference_direction : array_like, shape (dim,), or a sequence of them, optional
        One direction for all the seeds, or one per seed; default +x.
    exclude, within, seed_radius, link_factor, bin_factor, initial_length,
    min_branch_length, angle_window
        As :func:`extract_crack_path`.

    Returns
    -------
    list of CrackPath
        One per seed, in the order of ``seeds``.
    """
    xa = np.asarray(x, dtype=np.float64)
    if xa.ndim != 2 or xa.shape[1] not in (2, 3):
        raise ValueError(f"x must have shape (n, 2) or (n, 3), got {xa.shape}")
    n, dim = xa.shape
    d = np.asarray(damage, dtype=np.float64).reshape(-1)
    if d.shape != (n,):
        raise ValueError(f"damage must have shape ({n},), got {d.shape}")
    if not spacing > 0.0:
        raise ValueError("spacing must be > 0")
    n_s = len(seeds)
    if n_s == 0:
        return []
    ref_in = np.eye(dim)[0] if reference_direction is None else reference_direction
    ref_arr = np.asarray(ref_in, dtype=np.float64)
    refs = [_unit(r, dim) for r in ref_arr] if ref_arr.ndim == 2 else [_unit(ref_arr, dim)] * n_s
    if len(refs) != n_s:
        raise ValueError(f"give one reference_direction or {n_s}, got {len(refs)}")
    init_len = 5.0 * spacing if initial_length is None else float(initial_length)
    link = link_factor * spacing
    width = bin_factor * spacing
    min_branch = 4.0 * width if min_branch_length is None else float(min_branch_length)
    r_s = 4.0 * spacing if seed_radius is None else float(seed_radius)
    window = 6.0 * spacing if angle_window is None else float(angle_window)

    cracked = d >= threshold
    for name, extra, keep_in in (("exclude", exclude, False), ("within", within, True)):
        if extra is None:
            continue
        e = np.asarray(extra, dtype=bool).reshape(-1)
        if e.shape != (n,):
            raise ValueError(f"{name} must have shape ({n},), got {e.shape}")
        cracked &= e if keep_in else ~e
    idx = np.flatnonzero(cracked)
    pts = xa[idx]
    m = idx.size
    found = [_sources(s, xa, idx, link, r_s) for s in seeds]

    # --- cluster graph: cracked points + one virtual node per seed (m, m + 1, ...)
    pairs = cKDTree(pts).query_pairs(link * (1 + 1e-9), output_type="ndarray")
    w = np.linalg.norm(pts[pairs[:, 0]] - pts[pairs[:, 1]], axis=1)
    rows = [pairs[:, 0]] + [np.full(f[0].size, m + j) for j, f in enumerate(found)]
    cols = [pairs[:, 1]] + [f[0] for f in found]
    wts = [np.maximum(w, _EPS)] + [f[1] + _EPS * spacing for f in found]  # no zero weight
    graph = sp.coo_matrix(
        (np.concatenate(wts), (np.concatenate(rows), np.concatenate(cols))),
        shape=(m + n_s, m + n_s),
    ).tocsr()
    _, labels = csgraph.connected_components(graph, directed=False)
    g_all, pred_all, owner = csgraph.dijkstra(
        graph,
        directed=False,
        indices=np.arange(m, m + n_s),
        return_predecessors=True,
        min_only=True,
    )
    out = []
    for j, (src, _, start) in enumerate(found):  # over seeds
        if src.size == 0:
            out.append(_empty(start, refs[j], init_len, dim))
            continue
        members = np.flatnonzero((owner[:m] == m + j) & (labels[:m] == labels[m + j]))
        if members.size == 0:  # every first point is nearer another seed
            out.append(_empty(start, refs[j], init_len, dim))
            continue
        out.append(
            _skeleton(
                pts,
                idx,
                pairs,
                members,
                g_all,
                pred_all,
                m + j,
                start,
                spacing,
                width,
                min_branch,
                init_len,
                window,
                refs[j],
            )
        )
    return out


def _skeleton(
    pts: NDArray[np.float64],
    idx: NDArray[np.intp],
    pairs: NDArray[np.intp],
    members: NDArray[np.intp],
    g_all: NDArray[np.float64],
    pred_all: NDArray[np.int32],
    root: int,
    start: NDArray[np.float64],
    spacing: float,
    width: float,
    min_branch: float,
    init_len: float,
    window: float,
    ref: NDArray[np.float64],
) -> CrackPath:
    """Polylines of one seed's cluster ``members`` (indices into ``pts``) from the
    geodesic distances ``g_all`` and shortest-path predecessors ``pred_all`` (virtual
    seed node ``root``)."""
    dim = pts.shape[1]
    m = pts.shape[0]
    g = g_all[members]
    k = members.size
    local = np.full(m, -1, dtype=np.intp)
    local[members] = np.arange(k)
    pred = pred_all[members]
    pred_local = np.where(pred >= m, -1, local[np.clip(pred, 0, m - 1)])  # -1: the seed

    # --- level-set pieces: bins of g split into connected components
    b = np.floor(g / width).astype(np.intp)
    pl = local[pairs]  # pairs in cluster-local numbering (-1 if outside)
    pl = pl[(pl[:, 0] >= 0) & (pl[:, 1] >= 0)]
    ps = pl[b[pl[:, 0]] == b[pl[:, 1]]]
    sub = sp.coo_matrix((np.ones(ps.shape[0]), (ps[:, 0], ps[:, 1])), shape=(k, k)).tocsr()
    n_pc, piece = csgraph.connected_components(sub, directed=False)
    counts = np.bincount(piece, minlength=n_pc).astype(np.float64)
    cen = (
        np.stack(
            [np.bincount(piece, weights=pts[members, j], minlength=n_pc) for j in range(dim)],
            axis=1,
        )
        / counts[:, None]
    )
    # nearest (min g) and farthest (max g) point of each piece
    order = np.lexsort((g, piece))
    first = order[np.searchsorted(piece[order], np.arange(n_pc), side="left")]
    last = order[np.searchsorted(piece[order], np.arange(n_pc), side="right") - 1]
    p_near = pred_local[first]
    parent = np.where(p_near < 0, -1, piece[np.maximum(p_near, 0)])
    pbin = b[first]
    g_min = g[first]
    reach = g[last].copy()  # becomes the farthest g below each piece

    # --- subtree reach, bin by bin from the far end
    by_bin = np.argsort(pbin, kind="stable")
    bounds = np.searchsorted(pbin[by_bin], np.arange(pbin.max() + 2))
    for level in range(int(pbin.max()), 0, -1):  # over bins (path vertices)
        pcs = by_bin[bounds[level] : bounds[level + 1]]
        has = parent[pcs] >= 0
        np.maximum.at(reach, parent[pcs[has]], reach[pcs[has]])
    # best child of every piece: the child reaching farthest
    best_child = np.full(n_pc, -1, dtype=np.intp)
    child = np.flatnonzero(parent >= 0)
    if child.size:
        o = np.lexsort((reach[child], parent[child]))
        c_sorted = child[o]
        par_sorted = parent[c_sorted]
        is_last = np.r_[par_sorted[1:] != par_sorted[:-1], True]
        best_child[par_sorted[is_last]] = c_sorted[is_last]

    def chain_up(p: int) -> list[int]:
        chain = []
        while p >= 0:  # over path vertices
            chain.append(p)
            p = int(parent[p])
        return chain[::-1]

    def chain_down(p: int) -> list[int]:
        chain = []
        while p >= 0:  # over path vertices
            chain.append(p)
            p = int(best_child[p])
        return chain

    def polyline(chain: list[int]) -> NDArray[np.float64]:
        tip_pt = pts[members[last[chain[-1]]]]
        v = np.vstack([start[None, :], cen[chain], tip_pt[None, :]])
        step = np.linalg.norm(np.diff(v, axis=0), axis=1)
        return v[np.r_[True, step > 1e-9 * spacing]]  # no zero-length segments

    main = chain_up(int(piece[int(np.argmax(g))]))
    chains = [main]
    on_path = np.zeros(n_pc, dtype=bool)
    on_path[main] = True
    long_enough = (reach - g_min) >= min_branch
    while True:  # over branches kept
        hang = np.where(parent >= 0, on_path[np.maximum(parent, 0)], True)  # from a path
        roots = np.flatnonzero(hang & ~on_path & long_enough)  # or from the seed
        if roots.size == 0:
            break
        r = int(roots[np.argmax(reach[roots])])
        down = chain_down(r)
        chains.append((chain_up(int(parent[r])) if parent[r] >= 0 else []) + down)
        on_path[down] = True

    lines = [polyline(c) for c in chains]
    lengths = np.array([_arc(v)[-1] for v in lines])
    order_b = np.r_[0, 1 + np.argsort(-lengths[1:], kind="stable")].astype(np.intp)
    lines = [lines[i] for i in order_b]
    lengths = lengths[order_b]

    v = lines[0]
    arc = _arc(v)
    length = float(arc[-1])
    half = 0.5 * window
    if length > 0.0:
        ahead = np.stack([_point_at(v, arc, a + half) for a in arc])
        behind = np.stack([_point_at(v, arc, a - half) for a in arc])
        angles = _angles(ahead - behind, ref)
        s0 = min(init_len, length)
        init = float(_angles((_point_at(v, arc, s0) - v[0])[None, :], ref)[0])
    else:
        angles, s0, init = np.full(v.shape[0], math.nan), 0.0, math.nan
    tip_local = int(members[last[main[-1]]])
    return CrackPath(
        vertices=v,
        length=length,
        initial_angle_deg=init,
        angles_deg=angles,
        arc_length=arc,
        tip=v[-1].copy(),
        tip_index=int(idx[tip_local]),
        points=idx[members].astype(np.intp),
        geodesic=g,
        initial_length=s0,
        reference_direction=ref,
        branches=tuple(lines),
        branch_lengths=lengths,
    )


def tip_speed_from_paths(
    times: ArrayLike,
    lengths: ArrayLike,
    rayleigh_speed: float | None = None,
    window: int = 5,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Crack-tip speed from a history of crack-path lengths.

    The speed at record i is the least-squares slope of length against time over the
    ``window`` records centred on i (clipped at both ends of the history), which smooths
    the grid-scale jumps of a path that grows one bond at a time.

    Parameters
    ----------
    times : array_like, shape (r,)
        Record times, s, increasing.
    lengths : array_like, shape (r,)
        Crack-path length at each time, m (``CrackPath.length``).
    rayleigh_speed : float, optional
        Rayleigh-wave speed c_R of the model as run, m/s (:func:`rayleigh_speed`).
    window : int, optional
        Records in the fitting window (>= 2; default 5).

    Returns
    -------
    speeds : ndarray, shape (r,)
        Tip speed, m/s. Never clipped: a speed above c_R is what the data say.
    flagged : ndarray of bool, shape (r,)
        True where the speed exceeds ``rayleigh_speed`` (all False without it): a speed
        no mode-I crack reaches in a linear elastic solid (Freund (1990)), to be checked
        (a jump between cracks, a branch overtaking the main path, too coarse a record).
    """
    t = np.asarray(times, dtype=np.float64).reshape(-1)
    s = np.asarray(lengths, dtype=np.float64).reshape(-1)
    if t.shape != s.shape:
        raise ValueError("times and lengths must have the same length")
    if window < 2:
        raise ValueError("window must be >= 2")
    r = t.size
    if r < 2:
        return np.zeros(r), np.zeros(r, dtype=bool)
    if np.any(np.diff(t) <= 0.0):
        raise ValueError("times must increase")
    scale = (t[-1] - t[0]) / (r - 1)
    tt = (t - t[0]) / scale  # dimensionless, O(1) steps: well-conditioned sums
    lo = np.clip(np.arange(r) - window // 2, 0, None)
    hi = np.clip(lo + window, None, r)
    lo = np.clip(hi - window, 0, None)

    def csum(a: NDArray[np.float64]) -> NDArray[np.float64]:
        c = np.concatenate([[0.0], np.cumsum(a)])
        return c[hi] - c[lo]

    cnt = (hi - lo).astype(np.float64)
    st, ss, stt, sts = csum(tt), csum(s), csum(tt * tt), csum(tt * s)
    den = cnt * stt - st * st
    with np.errstate(invalid="ignore", divide="ignore"):
        slope = np.where(den > 0.0, (cnt * sts - st * ss) / den, 0.0)
    speeds = slope / scale
    flagged = speeds > rayleigh_speed if rayleigh_speed is not None else np.zeros(r, dtype=bool)
    return speeds, np.asarray(flagged, dtype=bool)


def rayleigh_speed(
    E: float,
    nu: float | None,
    rho: float,
    plane: Literal["stress", "strain", "3d"] = "stress",
    method: Literal["viktorov", "exact"] = "viktorov",
) -> float:
    """Rayleigh-wave speed c_R of an isotropic elastic solid, m/s.

    Parameters
    ----------
    E : float
        Young's modulus (the 3-D one, as in the deck), Pa.
    nu : float or None
        Poisson's ratio; None takes the value bond-based PMB fixes: 1/3 in plane stress,
        1/4 in plane strain and 3-D.
    rho : float
        Density, kg/m^3.
    plane : {"stress", "strain", "3d"}
        Plane stress and plane strain share the shear modulus mu = E / (2 (1 + nu)).
        The in-plane equations of plane stress are those of plane strain with
        nu* = nu / (1 + nu) (same mu; c_s / c_p = sqrt((1 - nu) / 2)), so the plane
        stress value uses nu* in the formula below. Plane strain and 3-D use nu.
    method : {"viktorov", "exact"}
        "viktorov": c_R = c_s (0.862 + 1.14 nu) / (1 + nu), c_s = sqrt(mu / rho)
        (Viktorov (1967); below the exact root by less than 0.3 % for
        0.2 <= nu < 0.5, by 1.4 % at nu = 0).
        "exact": the root in (0, c_s) of the Rayleigh equation
        (2 - eta^2)^2 = 4 sqrt(1 - k^2 eta^2) sqrt(1 - eta^2), eta = c / c_s,
        k = c_s / c_p (Achenbach (1973)).

    Returns
    -------
    float
        c_R, m/s. For the PMB model in plane stress (nu = 1/3, nu* = 1/4):
        0.9176 c_s (Viktorov), 0.9194 c_s (exact).
    """
    if plane not in ("stress", "strain", "3d"):
        raise ValueError(f"plane must be 'stress', 'strain' or '3d', got {plane!r}")
    if nu is None:
        nu = 1.0 / 3.0 if plane == "stress" else 0.25
    if not (E > 0.0 and rho > 0.0 and -1.0 < nu < 0.5):
        raise ValueError("need E > 0, rho > 0 and -1 < nu < 0.5")
    mu = E / (2.0 * (1.0 + nu))
    c_s = math.sqrt(mu / rho)
    nv = nu / (1.0 + nu) if plane == "stress" else nu
    if method == "viktorov":
        return c_s * (0.862 + 1.14 * nv) / (1.0 + nv)
    if method != "exact":
        raise ValueError(f"method must be 'viktorov' or 'exact', got {method!r}")
    k2 = (1.0 - 2.0 * nv) / (2.0 * (1.0 - nv))
    # eta^6 - 8 eta^4 + (24 - 16 k^2) eta^2 - 16 (1 - k^2) = 0, a cubic in eta^2
    roots = np.roots([1.0, -8.0, 24.0 - 16.0 * k2, -16.0 * (1.0 - k2)])
    real = roots[(np.abs(roots.imag) < 1e-10) & (roots.real > 0.0) & (roots.real < 1.0)]
    return c_s * math.sqrt(float(real.real.min()))
