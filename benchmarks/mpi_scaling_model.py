"""Weak-scaling model of the MPI domain decomposition: halo volume and step time, on paper.

Run from the repository root::

    python benchmarks/mpi_scaling_model.py                  # 2-D 500^2 and 3-D 100^3 per rank
    python benchmarks/mpi_scaling_model.py --dims 3 --threads 8 --json out.json
    python benchmarks/mpi_scaling_model.py --ghost-layers 1 # the one-layer design, to compare
    python benchmarks/mpi_scaling_model.py --check          # analytic counts vs brute force

Nothing is timed and nothing runs under MPI: the script counts, exactly, what each rank
of the decomposition built in :mod:`peridynamics.parallel` would own, hold as ghosts,
compute and exchange on a regular point grid, and puts the counts into a per-step cost
model.

Geometry. The points are the integer lattice of a box of ``shape`` points (spacing dx =
1; lengths below are in units of dx), numbered as the grid generators number them
(``meshgrid(..., indexing="ij")``, last axis fastest). For weak scaling every rank keeps
about ``side**dim`` points: with ``--domain cube`` (the default) the global grid is the
square (2-D) or cube (3-D) of side ``round(side * P**(1/dim))``; with ``--domain tiled``
it is P per-rank boxes tiled by doubling one axis at a time (P must be a power of two).

Partition (``--partition bonds``, the default, as
:func:`peridynamics.parallel.decompose.rcb_partition` does it): recursive coordinate
bisection (RCB) weighted by bond count. The weight of a point is its family size (the
points within the search radius r_s = m = ``--horizon``, the default truncated partial
volume) plus one. A box of ``k`` ranks is cut along its longest side (ties: the lower
axis) into ``k // 2`` and ``k - k // 2`` ranks at the weight fraction ``(k // 2) / k``:
the cut falls after the first point, in (coordinate, global id) order, whose cumulative
weight reaches the target, and is then moved to the nearer lattice plane (by cumulative
weight; ties: the lower plane). Only plane sums and one point weight per cut are
computed, and the check compares the boxes with ``rcb_partition`` itself.
``--partition points`` is the earlier assumption: the plane nearest to the median by
point count.

Ghosts (``--ghost-layers 2``, the default, the built design): a rank holds as ghosts the
points of other ranks within the ghost width ``w = 2 m + c`` of one of its owned points
(c = ``--contact-distance``, in dx, when contact is on). The ghosts within ``m`` of the
box (the *first layer*) get their full bond families on the rank, and their forces,
damage and pre-pass fields (dilatation and the like) are computed there redundantly,
bit for bit as their owner computes them. So one halo exchange of u and v (one message
per neighbour and field, dim float64 per ghost and field, all ghosts of both layers) per
force evaluation is all the step needs. ``--ghost-layers 1`` is the earlier assumption:
``w = m + c``, no first-layer families, no redundant compute; a state-based model then
needs a second exchange of its pre-pass fields, ``--prepass-floats`` float64 per ghost
(for example 1 for the LPS dilatation; default 0, as for PMB).

Counts, per rank, exact on the lattice (a point at distance exactly w counts as inside):

* owned points: the points of its box;
* ghost points: the grid points outside the box within distance w of some owned point.
  As the box is a full lattice box, the distance from a point q to the nearest owned
  point is the norm of the per-axis gaps ``max(lo - q, 0, q - hi)``, so the count of
  points of a region (a box) within w of the owned box is a sum over the non-negative
  gap vectors k with ``|k|**2 <= w**2`` of the product over the axes of how many
  lattice planes of the region lie at gap k_a: a few dozen products, no point is
  enumerated;
* first-layer ghosts: the same count with width m;
* directed bonds of the owned points: the pairs (p, p + v), p owned, p + v in the grid,
  0 < |v| <= m, counted per offset v;
* directed bonds of the first-layer ghosts (their full families): per offset v, the
  points of the region ``{p : p and p + v in the grid}`` (a box) within m of the owned
  box, minus the owned ones;
* neighbour ranks: the ranks whose box is within w of the box (exactly those that own
  at least one of its ghosts), and the number of points received from and sent to each.

``--check`` recounts all of this from explicit points for small grids (partition by
:func:`peridynamics.parallel.decompose.rcb_partition`, ghost sets by
:func:`peridynamics.parallel.decompose.ghost_points` with the radii of
:func:`peridynamics.build.decomposed.build_distributed`, families by
``scipy.spatial.cKDTree.query_pairs``), for several rank counts, boxes narrower than the
ghost width, a non-integer horizon, a contact distance, P not a power of two and both
designs, and stops with exit status 1 on any difference.

Cost model of one explicit step (one force evaluation) of rank r, without overlap of
computation and communication::

    t_r = (bonds_r + first_layer_bonds_r) * t_bond / threads        (forces + update)
        + fields * n_neighbours_r * latency
        + max(sent_r, recv_r) * 8 * fields * dim / bandwidth        (halo exchange of u, v)
        + allreduces * ceil(log2 P) * (latency + 8 * scalars / bandwidth)  (allreduce)

(``fields`` = 2: u and v; with ``--ghost-layers 1 --prepass-floats n`` one more exchange
of n float64 per ghost.) The step takes t(P) = max_r t_r (every step ends in the
Allreduce of bonds broken, bonds broken in the run and the stop flag); the table reports
the rank that sets it. Weak-scaling efficiency is t(1) / t(P) and includes the bond-count
effect (at P = 1 the points on the domain boundary miss bonds) and the redundant
compute of the first layer; ``comm eff`` = t_comp / t is the part lost to communication
alone. Outputs are costed separately: every ``--history-every`` steps rank 0 gathers
u (``--observe-floats`` float64 per point of the whole body, default dim) with a
``Gatherv``, ``(P - 1) * latency + bytes / bandwidth`` through rank 0's link, shown
amortised per step; it grows with the global size, unlike the halo.

Memory per rank: owned = ``--point-bytes`` per owned point + ``--bond-bytes`` per owned
bond; ghosts = ``--ghost-bytes`` per ghost of both layers + ``--bond-bytes`` per
first-layer bond, reported relative to owned; and the global point cloud that every rank
holds (``--global-bytes`` per global point; default 8 * dim positions + 8 volume + 4
partition (int32) + 8 gather order (int64)), which grows with the global size.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import math
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import cpu_model  # noqa: E402

Int = np.int64


# --------------------------------------------------------------------------- geometry
def global_shape(dim: int, side: int, ranks: int, domain: str) -> tuple[int, ...]:
    """Point counts per axis of the global grid of a weak-scaling run.

    Parameters
    ----------
    dim : int
        Spatial dimension (2 or 3).
    side : int
        Points per axis of the per-rank box (each rank keeps about ``side**dim`` points).
    ranks : int
        Number of ranks P.
    domain : {"cube", "tiled"}
        ``"cube"``: a square / cube of side ``round(side * P**(1/dim))``; ``"tiled"``:
        P per-rank boxes, doubling one axis at a time (P must be a power of two).

    Returns
    -------
    tuple of int
        Number of lattice points along each axis.
    """
    if domain == "cube":
        n = max(1, round(side * ranks ** (1.0 / dim)))
        return (n,) * dim
    if domain == "tiled":
        k = int(round(math.log2(ranks)))
        if 2**k != ranks:
            raise ValueError(f"--domain tiled needs a power of two, got P = {ranks}")
        return tuple(side * 2 ** ((k - a + dim - 1) // dim) for a in range(dim))
    raise ValueError(f"unknown domain {domain!r}")


def rcb_boxes_points(shape: tuple[int, ...], ranks: int) -> tuple[np.ndarray, np.ndarray]:
    """Recursive coordinate bisection by point count (``--partition points``).

    Parameters
    ----------
    shape : tuple of int
        Number of lattice points along each axis of the global grid.
    ranks : int
        Number of boxes (ranks); any positive integer.

    Returns
    -------
    lo, hi : numpy.ndarray
        Integer arrays of shape (ranks, dim): the first and last lattice index (both
        inclusive) of each box along each axis, in rank order.

    Notes
    -----
    A box for ``q`` ranks is cut along its longest side (ties: lowest axis) at the plane
    that gives its first part the share ``(q // 2) / q`` of the points, rounded to the
    nearest plane (the median by point count for even ``q``).
    """
    dim = len(shape)
    lo_out: list[np.ndarray] = []
    hi_out: list[np.ndarray] = []
    stack = [(np.zeros(dim, dtype=Int), np.asarray(shape, dtype=Int) - 1, ranks)]
    while stack:
        lo, hi, q = stack.pop()
        if q == 1:
            lo_out.append(lo)
            hi_out.append(hi)
            continue
        n = hi - lo + 1
        axis = int(np.argmax(n))
        if n[axis] < 2:
            raise ValueError(f"grid {shape} too small for {ranks} ranks")
        q_left = q // 2
        cut = int(round(n[axis] * q_left / q))
        cut = min(max(cut, 1), int(n[axis]) - 1)
        hi_left = hi.copy()
        hi_left[axis] = lo[axis] + cut - 1
        lo_right = lo.copy()
        lo_right[axis] = lo[axis] + cut
        # pushed right first so that the left part is numbered first
        stack.append((lo_right, hi, q - q_left))
        stack.append((lo, hi_left, q_left))
    return np.array(lo_out, dtype=Int), np.array(hi_out, dtype=Int)


def gap_vectors(width: float, dim: int) -> np.ndarray:
    """Non-negative integer vectors k with ``|k|**2 <= width**2``.

    Parameters
    ----------
    width : float
        Distance in lattice units.
    dim : int
        Spatial dimension.

    Returns
    -------
    numpy.ndarray
        Integer array of shape (n, dim), the zero vector included.
    """
    kmax = int(math.floor(width))
    axes = np.meshgrid(*[np.arange(kmax + 1, dtype=Int)] * dim, indexing="ij")
    k = np.stack([a.ravel() for a in axes], axis=1)
    return k[(k**2).sum(axis=1) <= width * width]


def bond_offsets(horizon: float, dim: int) -> np.ndarray:
    """Nonzero integer offsets v with ``|v| <= horizon`` (one per directed bond).

    Parameters
    ----------
    horizon : float
        Horizon m = delta / dx.
    dim : int
        Spatial dimension.

    Returns
    -------
    numpy.ndarray
        Integer array of shape (n, dim); n = 28 (2-D) and 122 (3-D) at m = 3.
    """
    kmax = int(math.floor(horizon))
    r = np.arange(-kmax, kmax + 1, dtype=Int)
    axes = np.meshgrid(*[r] * dim, indexing="ij")
    v = np.stack([a.ravel() for a in axes], axis=1)
    d2 = (v**2).sum(axis=1)
    return v[(d2 > 0) & (d2 <= horizon * horizon)]


def halo_counts(
    box_lo: np.ndarray,
    box_hi: np.ndarray,
    reg_lo: np.ndarray,
    reg_hi: np.ndarray,
    width: float,
) -> np.ndarray:
    """Number of lattice points of each region within ``width`` of each box.

    Parameters
    ----------
    box_lo, box_hi : numpy.ndarray
        Inclusive index ranges of the boxes, shape (n, dim).
    reg_lo, reg_hi : numpy.ndarray
        Inclusive index ranges of the regions (one per box), shape (n, dim).
    width : float
        Distance in lattice units (a point at exactly ``width`` counts).

    Returns
    -------
    numpy.ndarray
        Integer array of shape (n,): points of region i whose distance to the nearest
        point of box i is at most ``width`` (points inside box i included).
    """
    box_lo = np.atleast_2d(box_lo)
    box_hi = np.atleast_2d(box_hi)
    reg_lo = np.atleast_2d(reg_lo)
    reg_hi = np.atleast_2d(reg_hi)
    dim = box_lo.shape[1]
    k = gap_vectors(width, dim)
    kmax = int(k.max()) if k.size else 0
    # planes[i, a, g]: lattice planes of region i along axis a at gap g from box i
    planes = np.zeros((box_lo.shape[0], dim, kmax + 1), dtype=Int)
    planes[:, :, 0] = np.clip(np.minimum(box_hi, reg_hi) - np.maximum(box_lo, reg_lo) + 1, 0, None)
    for g in range(1, kmax + 1):
        below = box_lo - g
        above = box_hi + g
        planes[:, :, g] = ((below >= reg_lo) & (below <= reg_hi)).astype(Int) + (
            (above >= reg_lo) & (above <= reg_hi)
        ).astype(Int)
    prod = np.ones((box_lo.shape[0], k.shape[0]), dtype=Int)
    for a in range(dim):
        prod *= planes[:, a, k[:, a]]
    return prod.sum(axis=1)


def bond_counts(
    lo: np.ndarray, hi: np.ndarray, shape: tuple[int, ...], horizon: float
) -> np.ndarray:
    """Directed bonds of the owned points of each box (partners anywhere in the grid).

    Parameters
    ----------
    lo, hi : numpy.ndarray
        Inclusive index ranges of the boxes, shape (n, dim).
    shape : tuple of int
        Points per axis of the global grid.
    horizon : float
        Horizon m = delta / dx.

    Returns
    -------
    numpy.ndarray
        Integer array of shape (n,).
    """
    v = bond_offsets(horizon, len(shape))  # (n_off, dim)
    top = np.asarray(shape, dtype=Int) - 1
    first = np.maximum(lo[:, None, :], -v[None, :, :])
    last = np.minimum(hi[:, None, :], top[None, None, :] - v[None, :, :])
    return np.clip(last - first + 1, 0, None).prod(axis=2).sum(axis=1)


def _plane_points_weights(
    lo: np.ndarray, hi: np.ndarray, axis: int, plane: int, shape: tuple[int, ...], horizon: float
) -> np.ndarray:
    """Partition weights (family size + 1) of the points of one plane of a box, in
    global-id order (last axis fastest); only needed for cuts in very small boxes."""
    ranges = [
        np.array([plane], dtype=Int) if a == axis else np.arange(lo[a], hi[a] + 1, dtype=Int)
        for a in range(len(shape))
    ]
    if int(np.prod([r.size for r in ranges])) > 1_000_000:
        raise ValueError("plane too large for a point-by-point cut")
    grid = np.meshgrid(*ranges, indexing="ij")
    p = np.stack([g.ravel() for g in grid], axis=1)
    return bond_counts(p, p, shape, horizon) + 1


def rcb_boxes_bonds(
    shape: tuple[int, ...], ranks: int, horizon: float
) -> tuple[np.ndarray, np.ndarray]:
    """Recursive coordinate bisection weighted by bond count, as the implementation cuts.

    Parameters
    ----------
    shape : tuple of int
        Number of lattice points along each axis of the global grid.
    ranks : int
        Number of boxes (ranks); any positive integer.
    horizon : float
        Horizon m = bond search radius / dx; a point weighs its family size plus one.

    Returns
    -------
    lo, hi : numpy.ndarray
        Integer arrays of shape (ranks, dim): the first and last lattice index (both
        inclusive) of each box along each axis, in rank order.

    Notes
    -----
    The rule of :func:`peridynamics.parallel.decompose.rcb_partition` on a lattice: a box
    of ``k`` ranks is cut along its longest side (ties: the lowest axis) after the first
    point, in (coordinate, global id) order, whose cumulative weight reaches
    ``W * (k // 2) / k`` (the cut clipped so that every part keeps a point per rank),
    moved to the lattice plane on either side of it that is valid and nearer by
    cumulative weight (ties: the lower one). Plane weights are bond counts of slabs; the
    weight of the last point of the plane tells whether the first point reaching the
    target ends its plane; per-point weights are needed only when the clip can act.
    """
    dim = len(shape)
    if int(np.prod(shape, dtype=Int)) < ranks:
        raise ValueError(f"grid {shape} too small for {ranks} ranks")
    v = bond_offsets(horizon, dim)
    top = np.asarray(shape, dtype=Int) - 1
    reach = int(math.floor(horizon))
    shifts = np.arange(-reach, reach + 1, dtype=Int)
    lo_out = np.zeros((ranks, dim), dtype=Int)
    hi_out = np.zeros((ranks, dim), dtype=Int)
    stack = [(np.zeros(dim, dtype=Int), top.copy(), 0, ranks)]
    while stack:
        lo, hi, first, k = stack.pop()
        if k == 1:
            lo_out[first], hi_out[first] = lo, hi
            continue
        n = hi - lo + 1
        axis = int(np.argmax(n))
        n_planes, n_pts = int(n[axis]), int(n.prod())
        s = n_pts // n_planes  # points per plane
        planes = lo[axis] + np.arange(n_planes, dtype=Int)
        # plane weights: per offset, the points of the plane with a partner in the grid
        # (a product over the other axes, the plane's own axis only tests the grid edge)
        other = [a for a in range(dim) if a != axis]
        first_o = np.maximum(lo[other][None, :], -v[:, other])
        last_o = np.minimum(hi[other][None, :], top[other][None, :] - v[:, other])
        per_offset = np.clip(last_o - first_o + 1, 0, None).prod(axis=1)
        by_shift = np.zeros(2 * reach + 1, dtype=Int)
        np.add.at(by_shift, v[:, axis] + reach, per_offset)
        partner = planes[:, None] + shifts[None, :]
        inside = (partner >= 0) & (partner <= top[axis])
        pw = inside.astype(Int) @ by_shift + s
        cum = np.cumsum(pw)
        left = k // 2
        target = float(cum[-1]) * left / k
        j = int(np.searchsorted(cum.astype(np.float64), target, side="left"))
        before = int(cum[j] - pw[j])
        lower, upper = left, n_pts - (k - left)
        corner = hi.copy()  # the point of plane j with the largest global id
        corner[axis] = planes[j]
        w_last = int(np.all((corner + v >= 0) & (corner + v <= top), axis=1).sum()) + 1
        if before + int(pw[j]) - w_last < target:  # the last point of plane j reaches it
            cut = (j + 1) * s
        elif j * s + 1 >= lower and (j + 1) * s - 1 <= upper:
            cut = j * s + 1  # strictly inside plane j, unclipped: the same two candidates
        else:  # the clip may act: locate the point exactly
            w = before + np.cumsum(
                _plane_points_weights(lo, hi, axis, int(planes[j]), shape, horizon)
            )
            cut = j * s + int(np.searchsorted(w.astype(np.float64), target, side="left")) + 1
        cut = min(max(cut, lower), upper)
        cands = [c for c in ((cut // s) * s, -(-cut // s) * s) if lower <= c <= upper]
        if not cands:
            raise ValueError(
                f"grid {shape}, {ranks} ranks: a cut splits a lattice plane (a few points "
                "per rank); the model needs box parts"
            )
        best = min(cands, key=lambda c: abs(float(cum[c // s - 1]) - target))
        hi_left = hi.copy()
        hi_left[axis] = lo[axis] + best // s - 1
        lo_right = lo.copy()
        lo_right[axis] = hi_left[axis] + 1
        stack.append((lo, hi_left, first, left))
        stack.append((lo_right, hi, first + left, k - left))
    return lo_out, hi_out


def ghost_width(horizon: float, contact: float, layers: int) -> float:
    """Ghost width in dx: ``layers * m + c`` (``2 m + c`` in the built design).

    Parameters
    ----------
    horizon : float
        Horizon m = bond search radius / dx.
    contact : float
        Contact distance / dx (0 without contact).
    layers : int
        1 (one layer, the earlier assumption) or 2 (the built design).

    Returns
    -------
    float
        The ghost width.
    """
    return layers * horizon + contact


def first_layer_bonds(
    lo: np.ndarray, hi: np.ndarray, shape: tuple[int, ...], horizon: float
) -> np.ndarray:
    """Directed bonds of the full families of the first-layer ghosts of each box.

    Parameters
    ----------
    lo, hi : numpy.ndarray
        Inclusive index ranges of the boxes, shape (n, dim).
    shape : tuple of int
        Points per axis of the global grid.
    horizon : float
        Horizon m = delta / dx (the first layer is the ghosts within m of the box).

    Returns
    -------
    numpy.ndarray
        Integer array of shape (n,): for every offset v, the points p outside the box
        within m of it with p + v in the grid, summed over v.
    """
    v = bond_offsets(horizon, len(shape))
    top = np.asarray(shape, dtype=Int) - 1
    reg_lo = np.maximum(0, -v)  # {p : p in the grid and p + v in the grid}
    reg_hi = np.minimum(top[None, :], top[None, :] - v)
    n, n_off = lo.shape[0], v.shape[0]
    total = np.zeros(n, dtype=Int)
    chunk = max(1, 200_000 // max(n_off, 1))
    for a in range(0, n, chunk):
        b = min(n, a + chunk)
        m = b - a
        near = halo_counts(
            np.repeat(lo[a:b], n_off, axis=0),
            np.repeat(hi[a:b], n_off, axis=0),
            np.tile(reg_lo, (m, 1)),
            np.tile(reg_hi, (m, 1)),
            horizon,
        )
        total[a:b] = near.reshape(m, n_off).sum(axis=1)
    return total - bond_counts(lo, hi, shape, horizon)


@dataclass
class Decomposition:
    """Per-rank counts of one decomposition (arrays of length P)."""

    shape: tuple[int, ...]
    width: float
    lo: np.ndarray
    hi: np.ndarray
    owned: np.ndarray
    ghosts: np.ndarray  # both layers
    first: np.ndarray  # first-layer ghosts (with bond families)
    bonds: np.ndarray  # directed bonds of the owned points
    first_bonds: np.ndarray  # directed bonds of the first-layer ghosts
    neighbours: np.ndarray
    recv_points: np.ndarray
    sent_points: np.ndarray
    messages: np.ndarray  # (n_pairs, 3): receiver, owner, points


def neighbour_pairs(lo: np.ndarray, hi: np.ndarray, width: float) -> tuple[np.ndarray, np.ndarray]:
    """Ordered pairs (i, j), i != j, of boxes within ``width`` of each other.

    Parameters
    ----------
    lo, hi : numpy.ndarray
        Inclusive index ranges of the boxes, shape (P, dim).
    width : float
        Ghost width in lattice units.

    Returns
    -------
    i, j : numpy.ndarray
        Indices of the pairs.
    """
    p = lo.shape[0]
    d2 = np.zeros((p, p), dtype=Int)
    for a in range(lo.shape[1]):
        gap = np.maximum(lo[None, :, a] - hi[:, None, a], lo[:, None, a] - hi[None, :, a])
        d2 += np.maximum(gap, 0) ** 2
    near = d2 <= width * width
    np.fill_diagonal(near, False)
    i, j = np.nonzero(near)
    return i.astype(Int), j.astype(Int)


def decompose(
    shape: tuple[int, ...],
    ranks: int,
    horizon: float,
    contact: float = 0.0,
    layers: int = 2,
    partition: str = "bonds",
    lo: np.ndarray | None = None,
    hi: np.ndarray | None = None,
) -> Decomposition:
    """Count owned, ghost and exchanged points and bonds of every rank analytically.

    Parameters
    ----------
    shape : tuple of int
        Points per axis of the global grid.
    ranks : int
        Number of ranks P.
    horizon : float
        Horizon m = bond search radius / dx.
    contact : float, optional
        Contact distance / dx, added to the ghost width.
    layers : {1, 2}, optional
        Ghost layers: 2 (the built design, ``w = 2 m + c``, first layer with families)
        or 1 (``w = m + c``, no families on ghosts).
    partition : {"bonds", "points"}, optional
        RCB weighted by bond count (the implementation) or by point count.
    lo, hi : numpy.ndarray, optional
        Boxes to use instead of the RCB.

    Returns
    -------
    Decomposition
        The per-rank counts.
    """
    if lo is None or hi is None:
        if partition == "bonds":
            lo, hi = rcb_boxes_bonds(shape, ranks, horizon)
        elif partition == "points":
            lo, hi = rcb_boxes_points(shape, ranks)
        else:
            raise ValueError(f"unknown partition {partition!r}")
    width = ghost_width(horizon, contact, layers)
    top = np.asarray(shape, dtype=Int) - 1
    owned = (hi - lo + 1).prod(axis=1)
    glo = np.zeros_like(lo)
    ghi = np.broadcast_to(top, hi.shape)
    ghosts = halo_counts(lo, hi, glo, ghi, width) - owned
    bonds = bond_counts(lo, hi, shape, horizon)
    if layers == 2:
        first = halo_counts(lo, hi, glo, ghi, horizon) - owned
        first_bonds = first_layer_bonds(lo, hi, shape, horizon)
    elif layers == 1:
        first = np.zeros_like(owned)
        first_bonds = np.zeros_like(owned)
    else:
        raise ValueError(f"layers must be 1 or 2, got {layers}")
    i, j = neighbour_pairs(lo, hi, width)
    if i.size:
        msg = halo_counts(lo[i], hi[i], lo[j], hi[j], width)  # receiver i gets from j
    else:
        msg = np.zeros(0, dtype=Int)
    recv = np.bincount(i, weights=msg, minlength=ranks).astype(Int)
    sent = np.bincount(j, weights=msg, minlength=ranks).astype(Int)
    if not np.array_equal(recv, ghosts):
        raise AssertionError("ghosts by owner do not add up to the ghost count")
    neighbours = np.bincount(i, minlength=ranks).astype(Int)
    messages = np.stack([i, j, msg], axis=1) if i.size else np.zeros((0, 3), dtype=Int)
    return Decomposition(
        shape,
        width,
        lo,
        hi,
        owned,
        ghosts,
        first,
        bonds,
        first_bonds,
        neighbours,
        recv,
        sent,
        messages,
    )


# --------------------------------------------------------------------------- brute force
def brute_force(
    shape: tuple[int, ...],
    ranks: int,
    horizon: float,
    contact: float,
    layers: int,
    partition: str,
    lo: np.ndarray,
    hi: np.ndarray,
) -> dict[str, np.ndarray]:
    """Recount every per-rank quantity from explicit points with the implementation's
    own partition and ghost search.

    Parameters
    ----------
    shape : tuple of int
        Points per axis of the global grid.
    ranks : int
        Number of ranks P.
    horizon : float
        Horizon m = delta / dx.
    contact : float
        Contact distance / dx.
    layers : {1, 2}
        Ghost layers.
    partition : {"bonds", "points"}
        ``"bonds"``: the parts of :func:`peridynamics.parallel.decompose.rcb_partition`
        (compared with the model's boxes); ``"points"``: the model's boxes.
    lo, hi : numpy.ndarray
        The model's boxes, shape (P, dim).

    Returns
    -------
    dict of str to numpy.ndarray
        ``partition`` (1 when the parts equal the boxes), ``owned``, ``ghosts``,
        ``first``, ``bonds``, ``first_bonds``, ``neighbours``, ``recv_points``,
        ``sent_points`` per rank and ``messages`` (receiver, owner, points).
    """
    from scipy.spatial import cKDTree

    from peridynamics.bonds.partial_volume import search_radius
    from peridynamics.parallel.decompose import ghost_points, rcb_partition

    axes = np.meshgrid(*[np.arange(n, dtype=Int) for n in shape], indexing="ij")
    xi = np.stack([a.ravel() for a in axes], axis=1)
    x = xi.astype(np.float64)  # dx = 1
    boxes = np.full(x.shape[0], -1, dtype=Int)
    for r in range(ranks):
        inside = np.all((xi >= lo[r]) & (xi <= hi[r]), axis=1)
        if np.any(boxes[inside] >= 0):
            raise AssertionError("the boxes overlap")
        boxes[inside] = r
    if np.any(boxes < 0):
        raise AssertionError("the boxes do not cover the grid")
    # the radii of build_distributed (truncated partial volume, spacing 1)
    r_s = search_radius(horizon, 1.0, "truncated")
    r_ghost = layers * r_s + contact
    bpairs = cKDTree(x).query_pairs(r_s, output_type="ndarray")
    family = np.bincount(bpairs.ravel(), minlength=x.shape[0]).astype(Int)
    if partition == "bonds":
        part = rcb_partition(x, family.astype(np.float64) + 1.0, ranks).astype(Int)
    else:
        part = boxes
    out: dict[str, Any] = {
        k: np.zeros(ranks, dtype=Int)
        for k in ("owned", "ghosts", "first", "bonds", "first_bonds", "recv_points")
    }
    sent = np.zeros(ranks, dtype=Int)
    messages = []
    for r in range(ranks):
        owned = np.flatnonzero(part == r)
        ghosts = ghost_points(x, owned, r_ghost)
        first = ghost_points(x, owned, r_s) if layers == 2 else ghosts[:0]
        out["owned"][r] = owned.size
        out["ghosts"][r] = ghosts.size
        out["first"][r] = first.size
        out["bonds"][r] = family[owned].sum()
        out["first_bonds"][r] = family[first].sum()
        out["recv_points"][r] = ghosts.size
        owners, counts = np.unique(part[ghosts], return_counts=True)
        np.add.at(sent, owners, counts)
        messages += [(r, int(q), int(c)) for q, c in zip(owners, counts, strict=True)]
    msg = np.array(messages, dtype=Int).reshape(-1, 3)
    out["partition"] = np.array([int(np.array_equal(part, boxes))])
    out["sent_points"] = sent
    out["neighbours"] = np.bincount(msg[:, 0], minlength=ranks).astype(Int)
    out["messages"] = msg
    return out


CheckCase = tuple[int, int, int, float, float, int, str, str]
"""``(dim, side, ranks, horizon, contact, layers, domain, partition)``."""


def run_check(cases: list[CheckCase]) -> bool:
    """Compare :func:`decompose` with :func:`brute_force` and print one line per case.

    Parameters
    ----------
    cases : list of tuple
        ``(dim, side, ranks, horizon, contact, layers, domain, partition)`` per case.

    Returns
    -------
    bool
        True when every count of every case agrees.
    """
    ok_all = True
    print(
        "| dim | side | P | m | c | layers | w | partition | grid | points | ghosts (sum) "
        "| 1st layer (sum) | bonds (sum) | 1st-layer bonds (sum) | pairs | result |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    names = ("owned", "ghosts", "first", "bonds", "first_bonds", "neighbours")
    for dim, side, ranks, horizon, contact, layers, domain, partition in cases:
        shape = global_shape(dim, side, ranks, domain)
        dec = decompose(shape, ranks, horizon, contact, layers, partition)
        ref = brute_force(shape, ranks, horizon, contact, layers, partition, dec.lo, dec.hi)
        bad = [] if ref["partition"][0] else ["partition"]
        for name in (*names, "recv_points", "sent_points"):
            if not np.array_equal(getattr(dec, name), ref[name]):
                bad.append(name)
        mine = dec.messages[np.lexsort((dec.messages[:, 1], dec.messages[:, 0]))]
        theirs = ref["messages"][np.lexsort((ref["messages"][:, 1], ref["messages"][:, 0]))]
        if mine.shape != theirs.shape or not np.array_equal(mine, theirs):
            bad.append("messages")
        ok = not bad
        ok_all &= ok
        grid = "x".join(map(str, shape))
        print(
            f"| {dim} | {side} | {ranks} | {horizon:g} | {contact:g} | {layers} "
            f"| {dec.width:g} | {partition} | {grid} | {int(dec.owned.sum())} "
            f"| {int(dec.ghosts.sum())} | {int(dec.first.sum())} | {int(dec.bonds.sum())} "
            f"| {int(dec.first_bonds.sum())} | {len(mine)} "
            f"| {'ok' if ok else 'MISMATCH: ' + ', '.join(bad)} |"
        )
    return ok_all


def default_check_cases() -> list[CheckCase]:
    """The cases of ``--check``: small grids, up to 256 ranks in 2-D and 64 in 3-D.

    Returns
    -------
    list of tuple
        ``(dim, side, ranks, horizon, contact, layers, domain, partition)`` per case.
    """
    cases: list[CheckCase] = []
    for p in (1, 2, 4, 8, 16, 32, 64, 128, 256):
        cases.append((2, 16, p, 3.0, 0.0, 2, "cube", "bonds"))
    cases += [
        (2, 13, 8, 3.0, 0.0, 2, "tiled", "bonds"),
        (2, 8, 64, 3.0, 0.0, 2, "cube", "bonds"),  # boxes narrower than the ghost width
        (2, 3, 64, 3.0, 0.0, 2, "cube", "bonds"),  # ghosts from ranks several boxes away
        (2, 10, 32, 2.5, 0.0, 2, "cube", "bonds"),  # non-integer horizon
        (2, 10, 32, 3.0, 1.5, 2, "cube", "bonds"),  # contact distance
        (2, 9, 7, 3.0, 0.0, 2, "cube", "bonds"),  # P not a power of two
        (2, 16, 64, 3.0, 0.0, 2, "cube", "points"),  # the earlier partition
        (2, 16, 64, 3.0, 0.0, 1, "cube", "bonds"),  # one ghost layer
        (2, 10, 32, 3.0, 1.5, 1, "cube", "points"),  # one layer, contact, by points
    ]
    for p in (1, 2, 4, 8, 16, 32, 64):
        cases.append((3, 7, p, 3.0, 0.0, 2, "cube", "bonds"))
    cases += [
        (3, 6, 16, 3.0, 0.0, 2, "tiled", "bonds"),
        (3, 3, 64, 3.0, 0.0, 2, "cube", "bonds"),  # boxes narrower than the ghost width
        (3, 6, 12, 3.0, 0.0, 2, "cube", "bonds"),  # P not a power of two
        (3, 6, 32, 3.0, 1.5, 2, "cube", "bonds"),  # contact distance
        (3, 7, 64, 3.0, 0.0, 1, "cube", "points"),  # the earlier design
    ]
    return cases


# --------------------------------------------------------------------------- cost model
@dataclass
class CostParams:
    """Parameters of the per-step cost model (SI units, bytes)."""

    t_bond: float = 6.7e-9  # s per directed bond per core (whole step)
    threads: int = 1  # threads (cores) per rank
    latency: float = 2e-6  # s per message
    bandwidth: float = 10e9  # bytes per s per rank
    allreduces: int = 1  # global allreduces per step
    allreduce_scalars: int = 3  # float64 per allreduce: broken, broken in the run, stop
    fields: int = 2  # per-point fields exchanged per step (u, v), dim float64 each
    prepass_floats: int = 0  # one layer only: float64 per ghost of a pre-pass exchange
    history_every: int = 10  # steps between observations (0: no outputs)
    observe_floats: int = 0  # float64 per point gathered per observation; 0 = dim
    point_bytes: float = 200.0  # bytes per owned point (without bonds)
    ghost_bytes: float = 200.0  # bytes per ghost point (without bonds)
    bond_bytes: float = 14.0  # bytes per directed bond held
    global_bytes: float = 0.0  # bytes per global point on every rank; 0 = 8 * dim + 20
    set_up: str = "windowed"  # windowed (0.4.0: no global cloud) or replicated (0.3.0)
    requests: int = 5  # windowed: small gathers and reductions per observation


def global_point_bytes(cp: CostParams, dim: int) -> float:
    """Bytes every rank holds per point of the whole body.

    Parameters
    ----------
    cp : CostParams
        Cost model parameters.
    dim : int
        Spatial dimension.

    Returns
    -------
    float
        ``cp.global_bytes``, or by default 8 * dim (positions) + 8 (volume) + 4
        (partition, int32) + 8 (gather order, int64).
    """
    return cp.global_bytes or 8.0 * dim + 8.0 + 4.0 + 8.0


def largest_model(
    row: dict[str, Any], cp: CostParams, args: argparse.Namespace, dim: int
) -> dict[str, float]:
    """The most points that fit ``args.nodes`` nodes of ``args.node_gib`` GiB, one rank
    per node: each node holds its share of the points (``--peak-bytes-per-point``, the
    measured serial peak, or the model's owned + ghost bytes per owned point of ``row``)
    plus the replicated part (the global cloud when replicated; the slab ids and the
    ranks' boxes, well under a megabyte, when windowed).
    """
    per_point = args.peak_bytes_per_point or (
        (row["owned_memory_bytes"] + row["ghost_memory_bytes"]) / row["owned"]
    )
    node = args.node_gib * 2.0**30
    nodes = float(args.nodes)
    if cp.set_up == "replicated":  # node >= N per_point / nodes + N global_bytes
        points = node / (per_point / nodes + global_point_bytes(cp, dim))
    else:  # 8 B per slab (about N^(1/dim) slabs) and 16 dim B per rank's box
        points = (node - 16.0 * dim * nodes) / (per_point / nodes)
        points -= 8.0 * points ** (1.0 / dim) * nodes / per_point
    return {"points": float(points), "bytes_per_point": float(per_point)}


def replicated_bytes(cp: CostParams, dec: Decomposition) -> float:
    """Bytes every rank holds whatever its share.

    ``replicated`` (0.3.0): the global cloud, :func:`global_point_bytes` per point of the
    whole body. ``windowed`` (0.4.0, :mod:`peridynamics.parallel.windowed`): the first
    global id of every slab of the first grid axis (8 B each) and the box of every rank
    (2 dim int64 each).
    """
    points = float(np.prod(dec.shape, dtype=np.float64))
    if cp.set_up == "replicated":
        return points * global_point_bytes(cp, len(dec.shape))
    return 8.0 * dec.shape[0] + 16.0 * len(dec.shape) * dec.owned.size


def step_times(dec: Decomposition, cp: CostParams) -> dict[str, np.ndarray]:
    """Modelled time of one explicit step of every rank.

    Parameters
    ----------
    dec : Decomposition
        Per-rank counts.
    cp : CostParams
        Cost model parameters.

    Returns
    -------
    dict of str to numpy.ndarray
        Per-rank ``compute``, ``halo``, ``allreduce``, ``total`` and ``gather`` (the
        observation, amortised per step; not in ``total``) seconds, and ``bytes`` (the
        larger of bytes sent and received per step).
    """
    dim = len(dec.shape)
    ranks = dec.owned.size
    compute = (dec.bonds + dec.first_bonds) * cp.t_bond / cp.threads
    exchanges = cp.fields + (1 if cp.prepass_floats else 0)
    floats = cp.fields * dim + cp.prepass_floats
    nbytes = np.maximum(dec.recv_points, dec.sent_points) * (8.0 * floats)
    halo = exchanges * dec.neighbours * cp.latency + nbytes / cp.bandwidth
    stages = math.ceil(math.log2(ranks)) if ranks > 1 else 0
    one = stages * (cp.latency + 8.0 * cp.allreduce_scalars / cp.bandwidth)
    allreduce = np.full(ranks, cp.allreduces * one)
    total = compute + halo + allreduce
    gather = 0.0
    if ranks > 1 and cp.history_every > 0 and cp.set_up == "replicated":
        received = float(dec.owned.sum() - dec.owned[0]) * 8.0 * (cp.observe_floats or dim)
        gather = ((ranks - 1) * cp.latency + received / cp.bandwidth) / cp.history_every
    elif ranks > 1 and cp.history_every > 0:  # reductions and node-set rows: latency-bound
        received = float(dec.owned.sum() - dec.owned[0]) * 8.0 * cp.observe_floats
        tree = cp.requests * np.ceil(np.log2(ranks)) * cp.latency
        gather = (tree + received / cp.bandwidth) / cp.history_every
    return {
        "compute": compute,
        "halo": halo,
        "allreduce": allreduce,
        "total": total,
        "gather": np.full(ranks, gather),
        "bytes": nbytes,
    }


def summarize(dec: Decomposition, cp: CostParams, t1: float | None) -> dict[str, Any]:
    """One row of the table: the rank that sets the step time, plus spreads over ranks.

    Parameters
    ----------
    dec : Decomposition
        Per-rank counts.
    cp : CostParams
        Cost model parameters.
    t1 : float or None
        Step time at P = 1 (None: this is the P = 1 run).

    Returns
    -------
    dict
        JSON-ready summary.
    """
    dim = len(dec.shape)
    t = step_times(dec, cp)
    r = int(np.argmax(t["total"]))
    tot = float(t["total"][r])
    comm = float(t["halo"][r] + t["allreduce"][r])
    gather = float(t["gather"][r])
    points = int(np.prod(dec.shape, dtype=Int))
    mem_owned = dec.owned * cp.point_bytes + dec.bonds * cp.bond_bytes
    mem_ghost = dec.ghosts * cp.ghost_bytes + dec.first_bonds * cp.bond_bytes
    gbytes = global_point_bytes(cp, dim)
    mem_global = replicated_bytes(cp, dec)
    computed = dec.bonds + dec.first_bonds
    base = t1 if t1 is not None else tot

    def spread(a: np.ndarray) -> dict[str, float]:
        return {"min": float(a.min()), "mean": float(a.mean()), "max": float(a.max())}

    return {
        "ranks": int(dec.owned.size),
        "grid": list(dec.shape),
        "points": points,
        "ghost_width": dec.width,
        "critical_rank": r,
        "owned": int(dec.owned[r]),
        "ghosts": int(dec.ghosts[r]),
        "first_layer": int(dec.first[r]),
        "ghost_ratio": float(dec.ghosts[r] / dec.owned[r]),
        "first_layer_ratio": float(dec.first[r] / dec.owned[r]),
        "bonds": int(dec.bonds[r]),
        "first_layer_bonds": int(dec.first_bonds[r]),
        "bonds_per_point": float(dec.bonds[r] / dec.owned[r]),
        "redundant_share": float(dec.first_bonds[r] / computed[r]),
        "neighbours": int(dec.neighbours[r]),
        "recv_points": int(dec.recv_points[r]),
        "sent_points": int(dec.sent_points[r]),
        "mb_per_step": float(t["bytes"][r] / 1e6),
        "t_compute_s": float(t["compute"][r]),
        "t_halo_s": float(t["halo"][r]),
        "t_allreduce_s": float(t["allreduce"][r]),
        "t_step_s": tot,
        "comm_share": comm / tot,
        "comm_efficiency": float(t["compute"][r]) / tot,
        "efficiency": base / tot,
        "t_gather_per_step_s": gather,
        "efficiency_with_gather": base / (tot + gather),
        "ghost_memory_ratio": float(mem_ghost[r] / mem_owned[r]),
        "owned_memory_bytes": float(mem_owned[r]),
        "ghost_memory_bytes": float(mem_ghost[r]),
        "global_cloud_bytes": float(mem_global),
        "global_memory_ratio": float(mem_global / mem_owned[r]),
        "global_points_at_bond_parity": float(dec.bonds[r] * cp.bond_bytes / gbytes),
        "rank0_gather_bytes": float(
            points * 8.0 * (cp.observe_floats or (dim if cp.set_up == "replicated" else 0))
        ),
        "spread": {
            "owned": spread(dec.owned),
            "ghosts": spread(dec.ghosts),
            "first_layer": spread(dec.first),
            "ghost_ratio": spread(dec.ghosts / dec.owned),
            "bonds": spread(dec.bonds),
            "bonds_computed": spread(computed),
            "redundant_share": spread(dec.first_bonds / computed),
            "neighbours": spread(dec.neighbours),
            "mb_per_step": spread(t["bytes"] / 1e6),
            "t_step_s": spread(t["total"]),
        },
    }


def markdown_table(rows: list[dict[str, Any]]) -> str:
    """Format the summaries as a Markdown table.

    Parameters
    ----------
    rows : list of dict
        Outputs of :func:`summarize`, one per P.

    Returns
    -------
    str
        The table.
    """
    head = (
        "| P | global grid | owned | ghosts | 1st layer | ghost/owned | nbrs | MB/step "
        "| bonds/pt | redundant | t_step (ms) | comm share | efficiency t(1)/t(P) "
        "| comm eff | gather (ms/step) | ghost memory | replicated (MB/rank) |\n"
        "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    )
    lines = [head]
    for s in rows:
        grid = "x".join(str(n) for n in s["grid"])
        lines.append(
            f"| {s['ranks']} | {grid} | {s['owned']:,} | {s['ghosts']:,} "
            f"| {s['first_layer']:,} | {100 * s['ghost_ratio']:.2f} % | {s['neighbours']} "
            f"| {s['mb_per_step']:.3f} | {s['bonds_per_point']:.2f} "
            f"| {100 * s['redundant_share']:.2f} % | {1e3 * s['t_step_s']:.2f} "
            f"| {100 * s['comm_share']:.3f} % | {100 * s['efficiency']:.2f} % "
            f"| {100 * s['comm_efficiency']:.2f} % | {1e3 * s['t_gather_per_step_s']:.2f} "
            f"| {100 * s['ghost_memory_ratio']:.2f} % | {s['global_cloud_bytes'] / 1e6:,.0f} |"
        )
    return "\n".join(lines)


def parse_ranks(text: str) -> list[int]:
    """Parse ``--ranks``: a comma-separated list, or ``pow2:N`` for 1, 2, 4, ..., N.

    Parameters
    ----------
    text : str
        The option's value.

    Returns
    -------
    list of int
        Rank counts, ascending.
    """
    if text.startswith("pow2:"):
        top = int(text.split(":", 1)[1])
        out, p = [], 1
        while p <= top:
            out.append(p)
            p *= 2
        return out
    return sorted({int(s) for s in text.split(",") if s.strip()})


def build_parser() -> argparse.ArgumentParser:
    """Command-line options.

    Returns
    -------
    argparse.ArgumentParser
        The parser.
    """
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n", 1)[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    ap.add_argument("--dims", default="2,3", help="dimensions to model, comma-separated")
    ap.add_argument("--side-2d", type=int, default=500, help="points per axis per rank, 2-D")
    ap.add_argument("--side-3d", type=int, default=100, help="points per axis per rank, 3-D")
    ap.add_argument("--ranks", default="pow2:1024", help="'pow2:N' or a comma list")
    ap.add_argument("--domain", choices=("cube", "tiled"), default="cube", help="global grid")
    ap.add_argument(
        "--partition",
        choices=("bonds", "points"),
        default="bonds",
        help="RCB weighted by bond count (built) or by point count",
    )
    ap.add_argument("--horizon", type=float, default=3.0, help="m = search radius / dx")
    ap.add_argument(
        "--contact-distance", type=float, default=0.0, help="contact distance / dx (0: none)"
    )
    ap.add_argument(
        "--ghost-layers",
        type=int,
        choices=(1, 2),
        default=2,
        help="2: w = 2m + c, first layer computed redundantly (built); 1: w = m + c",
    )
    ap.add_argument(
        "--prepass-floats",
        type=int,
        default=0,
        help="one layer only: float64 per ghost of a second (pre-pass) exchange",
    )
    ap.add_argument("--t-bond", type=float, default=6.7e-9, help="s per bond per core")
    ap.add_argument("--threads", type=int, default=1, help="threads (cores) per rank")
    ap.add_argument("--latency", type=float, default=2e-6, help="s per message")
    ap.add_argument("--bandwidth", type=float, default=10e9, help="bytes/s per rank")
    ap.add_argument("--allreduces", type=int, default=1, help="allreduces per step")
    ap.add_argument("--allreduce-scalars", type=int, default=3, help="float64 per allreduce")
    ap.add_argument("--fields", type=int, default=2, help="fields exchanged per step (u, v)")
    ap.add_argument("--history-every", type=int, default=10, help="steps per observation")
    ap.add_argument(
        "--observe-floats", type=int, default=0, help="float64 per point gathered (0: dim)"
    )
    ap.add_argument("--point-bytes", type=float, default=200.0, help="bytes per owned point")
    ap.add_argument("--ghost-bytes", type=float, default=200.0, help="bytes per ghost point")
    ap.add_argument("--bond-bytes", type=float, default=14.0, help="bytes per directed bond")
    ap.add_argument(
        "--global-bytes",
        type=float,
        default=0.0,
        help="bytes per global point on every rank (0: 8*dim + 20)",
    )
    ap.add_argument(
        "--set-up",
        choices=("windowed", "replicated"),
        default="windowed",
        help="windowed: no rank holds the global cloud, histories reduce (0.4.0); "
        "replicated: every rank holds it, rank 0 gathers u per record (0.3.0)",
    )
    ap.add_argument("--node-gib", type=float, default=256.0, help="memory per node (GiB)")
    ap.add_argument("--nodes", type=int, default=1024, help="nodes for the largest model")
    ap.add_argument(
        "--peak-bytes-per-point",
        type=float,
        default=0.0,
        help="measured serial peak per point (0: the model's owned + ghost bytes)",
    )
    ap.add_argument("--json", type=Path, default=None, help="write the results here")
    ap.add_argument(
        "--check",
        action="store_true",
        help="compare the analytic counts with a brute force at small sizes first",
    )
    return ap


def run_design(args: argparse.Namespace, dim: int, side: int, ranks: int) -> Decomposition:
    """The decomposition of one weak-scaling run with the design of the options.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options (domain, horizon, contact distance, ghost layers, partition).
    dim : int
        Spatial dimension.
    side : int
        Points per axis per rank.
    ranks : int
        Number of ranks P.

    Returns
    -------
    Decomposition
        The per-rank counts.
    """
    return decompose(
        global_shape(dim, side, ranks, args.domain),
        ranks,
        args.horizon,
        args.contact_distance,
        args.ghost_layers,
        args.partition,
    )


def main(argv: list[str] | None = None) -> int:
    """Run the model (and the check) and print the tables.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 1 when ``--check`` finds a difference, else 0.
    """
    args = build_parser().parse_args(argv)
    if args.prepass_floats and args.ghost_layers == 2:
        raise SystemExit("--prepass-floats applies to --ghost-layers 1 only")
    if args.contact_distance < 0:
        raise SystemExit("--contact-distance must be >= 0")
    cp = CostParams(
        t_bond=args.t_bond,
        threads=args.threads,
        latency=args.latency,
        bandwidth=args.bandwidth,
        allreduces=args.allreduces,
        allreduce_scalars=args.allreduce_scalars,
        fields=args.fields,
        prepass_floats=args.prepass_floats,
        history_every=args.history_every,
        observe_floats=args.observe_floats,
        point_bytes=args.point_bytes,
        ghost_bytes=args.ghost_bytes,
        bond_bytes=args.bond_bytes,
        global_bytes=args.global_bytes,
        set_up=args.set_up,
    )
    design = {
        "horizon": args.horizon,
        "contact_distance": args.contact_distance,
        "ghost_layers": args.ghost_layers,
        "ghost_width": ghost_width(args.horizon, args.contact_distance, args.ghost_layers),
        "partition": args.partition,
        "domain": args.domain,
    }
    out: dict[str, Any] = {
        "script": "benchmarks/mpi_scaling_model.py",
        "argv": sys.argv[1:] if argv is None else argv,
        "date": _dt.datetime.now().isoformat(timespec="seconds"),
        "cpu": cpu_model(),
        "params": {**asdict(cp), **design},
    }
    status = 0
    if args.check:
        t0 = time.perf_counter()
        print("## Check: analytic counts vs the implementation's partition and ghost search\n")
        ok = run_check(default_check_cases())
        print(f"\ncheck {'passed' if ok else 'FAILED'} ({time.perf_counter() - t0:.1f} s)\n")
        out["check_passed"] = ok
        status = 0 if ok else 1
    ranks = parse_ranks(args.ranks)
    for dim in (int(d) for d in args.dims.split(",")):
        side = args.side_2d if dim == 2 else args.side_3d
        t0 = time.perf_counter()
        t1 = summarize(run_design(args, dim, side, 1), cp, None)["t_step_s"]
        rows = [summarize(run_design(args, dim, side, p), cp, float(t1)) for p in ranks]
        floats = cp.fields * dim + cp.prepass_floats
        last = rows[-1]
        print(
            f"## {dim}-D, {side}^{dim} points per rank, m = {args.horizon:g}, contact "
            f"{args.contact_distance:g} dx, {args.ghost_layers} ghost layer(s): ghost width "
            f"{design['ghost_width']:g} dx, partition by {args.partition}, domain "
            f"{args.domain}\n\n"
            f"t_bond = {cp.t_bond:g} s / {cp.threads} thread(s), latency {cp.latency:g} s, "
            f"bandwidth {cp.bandwidth:g} B/s, {floats} float64 per ghost per step in "
            f"{cp.fields + (1 if cp.prepass_floats else 0)} exchange(s), "
            f"{cp.allreduces} allreduce(s) of {cp.allreduce_scalars} float64 per step, "
            f"{'gather of u' if cp.set_up == 'replicated' else 'reductions'} every "
            f"{cp.history_every} steps; row = the rank with the longest step\n"
        )
        print(markdown_table(rows))
        print(
            f"\nAt P = {last['ranks']}: efficiency with the observations "
            f"{100 * last['efficiency_with_gather']:.2f} %; rank 0 receives "
            f"{last['rank0_gather_bytes'] / 1e9:.2f} GB per observation; every rank holds "
            f"{last['global_cloud_bytes'] / 1e9:.4f} GB replicated ({cp.set_up} set-up), "
            f"{last['global_memory_ratio']:.4f} x its owned points and bonds "
            f"({last['owned_memory_bytes'] / 1e6:,.0f} MB); the global cloud equals the "
            f"rank's own bonds at {last['global_points_at_bond_parity']:.3g} global points "
            f"({time.perf_counter() - t0:.1f} s)\n"
        )
        fit = largest_model(last, cp, args, dim)
        print(
            f"Largest model on {args.nodes} nodes of {args.node_gib:g} GiB (one rank per "
            f"node, {fit['bytes_per_point']:,.0f} B per owned point with its bonds and "
            f"ghosts): {fit['points']:.3g} points ({cp.set_up} set-up)\n"
        )
        out[f"{dim}d_largest"] = fit
        out[f"{dim}d"] = {"side": side, "rows": rows}
    if args.json is not None:
        args.json.write_text(json.dumps(out, indent=1) + "\n")
        print(f"wrote {args.json}")
    return status


if __name__ == "__main__":
    sys.exit(main())
