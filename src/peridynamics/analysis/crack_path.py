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

The polyline type :class:`~peridynamics.analysis.crack_polyline.CrackPath` and its
geometry are in :mod:`peridynamics.analysis.crack_polyline`, the skeleton (steps 1-4) in
:mod:`peridynamics.analysis.crack_skeleton`. Tip speeds come from the history of the
path length by a local least-squares slope and are flagged, never clipped, where they
exceed the Rayleigh speed of the model as run
(:mod:`peridynamics.analysis.crack_speed`, Viktorov (1967)).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

from peridynamics.analysis.crack_polyline import (
    CrackPath,
    arc_lengths,
    chord_angles,
    point_at_arc,
    unit_direction,
)
from peridynamics.analysis.crack_skeleton import crack_branches

__all__ = ["extract_crack_path", "extract_crack_paths"]

_EPS = 1e-12


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
    refs = _references(reference_direction, dim, n_s)
    init_len = 5.0 * spacing if initial_length is None else float(initial_length)
    link = link_factor * spacing
    width = bin_factor * spacing
    min_branch = 4.0 * width if min_branch_length is None else float(min_branch_length)
    r_s = 4.0 * spacing if seed_radius is None else float(seed_radius)
    window = 6.0 * spacing if angle_window is None else float(angle_window)

    idx = np.flatnonzero(_cracked(d, threshold, exclude, within))
    pts = xa[idx]
    m = idx.size
    found = [_sources(s, xa, idx, link, r_s) for s in seeds]
    pairs, labels, g_all, pred_all, owner = _cluster_graph(pts, found, link, spacing)
    out = []
    for j, (src, _, start) in enumerate(found):  # over seeds
        if src.size == 0:
            out.append(_empty(start, refs[j], init_len, dim))
            continue
        members = np.flatnonzero((owner[:m] == m + j) & (labels[:m] == labels[m + j]))
        if members.size == 0:  # every first point is nearer another seed
            out.append(_empty(start, refs[j], init_len, dim))
            continue
        lines, lengths, tip = crack_branches(
            pts, pairs, members, g_all, pred_all, start, spacing, width, min_branch
        )
        out.append(
            _crack_path(
                lines, lengths, idx[tip], idx[members], g_all[members], init_len, window, refs[j]
            )
        )
    return out


def _references(
    reference_direction: ArrayLike | Sequence[ArrayLike] | None, dim: int, n_s: int
) -> list[NDArray[np.float64]]:
    """One unit reference direction per seed."""
    ref_in = np.eye(dim)[0] if reference_direction is None else reference_direction
    ref_arr = np.asarray(ref_in, dtype=np.float64)
    if ref_arr.ndim == 2:
        refs = [unit_direction(r, dim) for r in ref_arr]
    else:
        refs = [unit_direction(ref_arr, dim)] * n_s
    if len(refs) != n_s:
        raise ValueError(f"give one reference_direction or {n_s}, got {len(refs)}")
    return refs


def _cracked(
    d: NDArray[np.float64], threshold: float, exclude: ArrayLike | None, within: ArrayLike | None
) -> NDArray[np.bool_]:
    """Mask of the points that count as cracked."""
    n = d.shape[0]
    cracked = d >= threshold
    for name, extra, keep_in in (("exclude", exclude, False), ("within", within, True)):
        if extra is None:
            continue
        e = np.asarray(extra, dtype=bool).reshape(-1)
        if e.shape != (n,):
            raise ValueError(f"{name} must have shape ({n},), got {e.shape}")
        cracked &= e if keep_in else ~e
    return cracked


def _cluster_graph(
    pts: NDArray[np.float64], found: list, link: float, spacing: float
) -> tuple[NDArray[np.intp], NDArray[np.int32], NDArray[np.float64], NDArray[np.int32], NDArray]:
    """The cluster graph of the cracked points ``pts`` and one virtual node per seed
    (m, m + 1, ...): neighbour pairs, connected-component labels, and the geodesic
    distance, predecessor and nearest seed node of every node (one multi-source
    Dijkstra)."""
    m = pts.shape[0]
    n_s = len(found)
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
    return pairs, labels, g_all, pred_all, owner


def _crack_path(
    lines: list[NDArray[np.float64]],
    lengths: NDArray[np.float64],
    tip_index: int,
    points: NDArray[np.intp],
    g: NDArray[np.float64],
    init_len: float,
    window: float,
    ref: NDArray[np.float64],
) -> CrackPath:
    """The :class:`CrackPath` of the branch polylines ``lines`` (main branch first): arc
    lengths, windowed angles and the initial angle of the main one."""
    v = lines[0]
    arc = arc_lengths(v)
    length = float(arc[-1])
    half = 0.5 * window
    if length > 0.0:
        ahead = np.stack([point_at_arc(v, arc, a + half) for a in arc])
        behind = np.stack([point_at_arc(v, arc, a - half) for a in arc])
        angles = chord_angles(ahead - behind, ref)
        s0 = min(init_len, length)
        init = float(chord_angles((point_at_arc(v, arc, s0) - v[0])[None, :], ref)[0])
    else:
        angles, s0, init = np.full(v.shape[0], math.nan), 0.0, math.nan
    return CrackPath(
        vertices=v,
        length=length,
        initial_angle_deg=init,
        angles_deg=angles,
        arc_length=arc,
        tip=v[-1].copy(),
        tip_index=int(tip_index),
        points=points.astype(np.intp),
        geodesic=g,
        initial_length=s0,
        reference_direction=ref,
        branches=tuple(lines),
        branch_lengths=lengths,
    )
