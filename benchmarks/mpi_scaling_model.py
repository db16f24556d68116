"""Weak-scaling model of the MPI domain decomposition: halo volume and step time, on paper.

Run from the repository root::

    python benchmarks/mpi_scaling_model.py                  # 2-D 500^2 and 3-D 100^3 per rank
    python benchmarks/mpi_scaling_model.py --dims 3 --threads 8 --json out.json
    python benchmarks/mpi_scaling_model.py --check          # analytic counts vs cKDTree

Nothing is timed and nothing runs under MPI: the script counts, exactly, what each rank
of a recursive coordinate bisection (RCB) of a regular point grid would own, hold as
ghosts and exchange, and puts the counts into a per-step cost model.

Geometry. The points are the integer lattice of a box of ``shape`` points (spacing dx =
1; lengths below are in units of dx). For weak scaling every rank keeps about
``side**dim`` points: with ``--domain cube`` (the default) the global grid is the square
(2-D) or cube (3-D) of side ``round(side * P**(1/dim))``, exact for P = 4**k in 2-D and
8**k in 3-D and within a fraction of a per cent of ``P * side**dim`` otherwise; with
``--domain tiled`` it is P per-rank boxes tiled by doubling one axis at a time (every rank
owns exactly ``side**dim`` points; P must be a power of two). RCB splits the box with the
most points along its longest side (ties: the lower axis) at the lattice plane nearest
to the median by point count (a box for ``P`` ranks is cut in ``P // 2`` and
``P - P // 2`` ranks, in proportion), recursively, until each rank has one box.

Counts, per rank, exact on the lattice (a point at distance exactly w counts as inside):

* owned points: the points of its box;
* ghost points: the grid points outside the box within distance w (the ghost width,
  ``--ghost-width``, default the horizon m = ``--horizon``) of some owned point. As the
  box is a full lattice box, the distance from a point q to the nearest owned point is
  the norm of the per-axis gaps ``max(lo - q, 0, q - hi)``, so the count of points of a
  region (a box) within w of the owned box is a sum over the non-negative gap vectors k
  with ``|k|**2 <= w**2`` of the product over the axes of how many lattice planes of the
  region lie at gap k_a: a few dozen products, no point is enumerated;
* directed bonds of the owned points: the pairs (p, p + v), p owned, p + v in the grid,
  0 < |v| <= m, counted the same way per offset v;
* neighbour ranks: the ranks whose box is within w of the box (exactly those that own at
  least one of its ghosts), and the number of points received from and sent to each.

``--check`` recounts all of this by brute force (``scipy.spatial.cKDTree.query_pairs``
on the explicit points) for small grids, several rank counts, a box narrower than the
ghost width, a non-integer horizon and a widened ghost width, and stops with exit
status 1 on any difference.

Cost model of one explicit step of rank r (no overlap of computation and communication)::

    t_r = bonds_r * t_bond / threads                          (bond forces + update)
        + n_neighbours_r * latency + max(sent_r, recv_r) / bandwidth     (halo exchange)
        + allreduces * ceil(log2 P) * (latency + 8 * scalars / bandwidth)  (allreduce)

with ``sent``, ``recv`` in bytes (``2 * dim`` float64 per ghost point: displacement and
velocity). The step takes t(P) = max_r t_r (every step ends in a collective); the table
reports the rank that sets it. Weak-scaling efficiency is t(1) / t(P) and includes the
bond-count effect: at P = 1 the points on the domain boundary miss bonds, whereas an
interior rank of a large run has full families; ``comm eff`` = t_comp / t is the part
lost to communication alone. The memory of the ghosts (``--ghost-bytes`` per point) is
reported relative to what the rank holds for its owned points (``--point-bytes`` per
point + ``--bond-bytes`` per directed bond).
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


def rcb_boxes(shape: tuple[int, ...], ranks: int) -> tuple[np.ndarray, np.ndarray]:
    """Recursive coordinate bisection of a lattice box into ``ranks`` boxes.

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


@dataclass
class Decomposition:
    """Per-rank counts of one decomposition (arrays of length P)."""

    shape: tuple[int, ...]
    lo: np.ndarray
    hi: np.ndarray
    owned: np.ndarray
    ghosts: np.ndarray
    bonds: np.ndarray
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
    width: float,
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
        Horizon m = delta / dx (bonds).
    width : float
        Ghost width w >= m in lattice units (halo).
    lo, hi : numpy.ndarray, optional
        Boxes to use instead of :func:`rcb_boxes`.

    Returns
    -------
    Decomposition
        The per-rank counts.
    """
    if lo is None or hi is None:
        lo, hi = rcb_boxes(shape, ranks)
    top = np.asarray(shape, dtype=Int) - 1
    owned = (hi - lo + 1).prod(axis=1)
    glo = np.zeros_like(lo)
    ghi = np.broadcast_to(top, hi.shape)
    ghosts = halo_counts(lo, hi, glo, ghi, width) - owned
    bonds = bond_counts(lo, hi, shape, horizon)
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
    return Decomposition(shape, lo, hi, owned, ghosts, bonds, neighbours, recv, sent, messages)


# --------------------------------------------------------------------------- brute force
def brute_force(
    shape: tuple[int, ...], lo: np.ndarray, hi: np.ndarray, horizon: float, width: float
) -> dict[str, np.ndarray]:
    """Recount owned, ghost, bond, neighbour and message counts from explicit points.

    Parameters
    ----------
    shape : tuple of int
        Points per axis of the global grid.
    lo, hi : numpy.ndarray
        Inclusive index ranges of the boxes, shape (P, dim).
    horizon : float
        Horizon m (bonds).
    width : float
        Ghost width w (halo).

    Returns
    -------
    dict of str to numpy.ndarray
        ``owned``, ``ghosts``, ``bonds``, ``neighbours``, ``recv_points``,
        ``sent_points`` per rank and ``messages`` (receiver, owner, points), sorted.
    """
    from scipy.spatial import cKDTree

    p = lo.shape[0]
    axes = np.meshgrid(*[np.arange(n, dtype=Int) for n in shape], indexing="ij")
    x = np.stack([a.ravel() for a in axes], axis=1)
    inside = np.all((x[:, None, :] >= lo[None]) & (x[:, None, :] <= hi[None]), axis=2)
    if not np.all(inside.sum(axis=1) == 1):
        raise AssertionError("the boxes do not partition the grid")
    rank = np.argmax(inside, axis=1).astype(Int)
    tree = cKDTree(x.astype(np.float64))
    bpairs = tree.query_pairs(horizon, output_type="ndarray")
    bonds = np.bincount(rank[bpairs[:, 0]], minlength=p) + np.bincount(
        rank[bpairs[:, 1]], minlength=p
    )
    gpairs = tree.query_pairs(width, output_type="ndarray")
    a, b = gpairs[:, 0], gpairs[:, 1]
    cross = rank[a] != rank[b]
    a, b = a[cross], b[cross]
    # (receiving rank, ghost point): b is a ghost of rank[a] and a a ghost of rank[b]
    recv_rank = np.concatenate([rank[a], rank[b]])
    point = np.concatenate([b, a])
    n = x.shape[0]
    key = np.unique(recv_rank * n + point)
    recv_rank, point = key // n, key % n
    ghosts = np.bincount(recv_rank, minlength=p)
    owner = rank[point]
    pair, counts = np.unique(recv_rank * p + owner, return_counts=True)
    messages = np.stack([pair // p, pair % p, counts], axis=1)
    return {
        "owned": np.bincount(rank, minlength=p),
        "ghosts": ghosts,
        "bonds": bonds,
        "neighbours": np.bincount(messages[:, 0], minlength=p),
        "recv_points": np.bincount(messages[:, 0], weights=counts, minlength=p).astype(Int),
        "sent_points": np.bincount(messages[:, 1], weights=counts, minlength=p).astype(Int),
        "messages": messages,
    }


def run_check(cases: list[tuple[int, int, int, float, float, str]]) -> bool:
    """Compare :func:`decompose` with :func:`brute_force` and print one line per case.

    Parameters
    ----------
    cases : list of tuple
        ``(dim, side, ranks, horizon, width, domain)`` per case.

    Returns
    -------
    bool
        True when every count of every case agrees.
    """
    ok_all = True
    print(
        "| dim | side | P | m | w | grid | points | ghosts (sum) | bonds (sum) | pairs | result |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for dim, side, ranks, horizon, width, domain in cases:
        shape = global_shape(dim, side, ranks, domain)
        dec = decompose(shape, ranks, horizon, width)
        ref = brute_force(shape, dec.lo, dec.hi, horizon, width)
        bad = []
        for name in ("owned", "ghosts", "bonds", "neighbours", "recv_points", "sent_points"):
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
            f"| {dim} | {side} | {ranks} | {horizon:g} | {width:g} | {grid} | "
            f"{int(dec.owned.sum())} | {int(dec.ghosts.sum())} | {int(dec.bonds.sum())} | "
            f"{len(mine)} | {'ok' if ok else 'MISMATCH: ' + ', '.join(bad)} |"
        )
    return ok_all


def default_check_cases() -> list[tuple[int, int, int, float, float, str]]:
    """The cases of ``--check``: small grids, up to 256 ranks in 2-D and 64 in 3-D.

    Returns
    -------
    list of tuple
        ``(dim, side, ranks, horizon, width, domain)`` per case.
    """
    cases: list[tuple[int, int, int, float, float, str]] = []
    for p in (1, 2, 4, 8, 16, 32, 64, 128, 256):
        cases.append((2, 16, p, 3.0, 3.0, "cube"))
    cases += [
        (2, 13, 8, 3.0, 3.0, "tiled"),
        (2, 4, 64, 3.0, 3.0, "cube"),  # boxes barely wider than the ghost width
        (2, 2, 64, 3.0, 3.0, "cube"),  # boxes narrower: ghosts from ranks two boxes away
        (2, 10, 32, 2.5, 2.5, "cube"),  # non-integer horizon
        (2, 10, 32, 3.0, 4.5, "cube"),  # ghost width widened (contact)
        (2, 9, 7, 3.0, 3.0, "cube"),  # P not a power of two
    ]
    for p in (1, 2, 4, 8, 16, 32, 64):
        cases.append((3, 7, p, 3.0, 3.0, "cube"))
    cases += [
        (3, 6, 16, 3.0, 3.0, "tiled"),
        (3, 3, 64, 3.0, 3.0, "cube"),  # boxes as wide as the ghost width
        (3, 2, 64, 3.0, 3.0, "cube"),  # boxes narrower: ghosts from ranks two boxes away
        (3, 6, 12, 3.0, 3.0, "cube"),  # P not a power of two
        (3, 6, 32, 3.0, 4.5, "cube"),  # ghost width widened (contact)
    ]
    return cases


# --------------------------------------------------------------------------- cost model
@dataclass
class CostParams:
    """Parameters of the per-step cost model (SI units)."""

    t_bond: float = 6.7e-9  # s per directed bond per core (whole step)
    threads: int = 1  # threads (cores) per rank
    latency: float = 2e-6  # s per message
    bandwidth: float = 10e9  # bytes per s per rank
    allreduces: int = 1  # global allreduces per step
    allreduce_scalars: int = 4  # float64 scalars per allreduce
    ghost_floats: int = 0  # float64 per ghost point per step; 0 = 2 * dim
    point_bytes: float = 200.0  # bytes per owned point (without bonds)
    ghost_bytes: float = 200.0  # bytes per ghost point
    bond_bytes: float = 14.0  # bytes per directed bond held


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
        Per-rank ``compute``, ``halo``, ``allreduce`` and ``total`` seconds, and
        ``bytes`` (the larger of bytes sent and received).
    """
    dim = len(dec.shape)
    floats = cp.ghost_floats or 2 * dim
    ranks = dec.owned.size
    compute = dec.bonds * cp.t_bond / cp.threads
    nbytes = np.maximum(dec.recv_points, dec.sent_points) * (8.0 * floats)
    halo = dec.neighbours * cp.latency + nbytes / cp.bandwidth
    stages = math.ceil(math.log2(ranks)) if ranks > 1 else 0
    one = stages * (cp.latency + 8.0 * cp.allreduce_scalars / cp.bandwidth)
    allreduce = np.full(ranks, cp.allreduces * one)
    total = compute + halo + allreduce
    return {
        "compute": compute,
        "halo": halo,
        "allreduce": allreduce,
        "total": total,
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
    t = step_times(dec, cp)
    r = int(np.argmax(t["total"]))
    tot = float(t["total"][r])
    comm = float(t["halo"][r] + t["allreduce"][r])
    mem_owned = dec.owned * cp.point_bytes + dec.bonds * cp.bond_bytes
    mem_ghost = dec.ghosts * cp.ghost_bytes

    def spread(a: np.ndarray) -> dict[str, float]:
        return {"min": float(a.min()), "mean": float(a.mean()), "max": float(a.max())}

    return {
        "ranks": int(dec.owned.size),
        "grid": list(dec.shape),
        "points": int(np.prod(dec.shape, dtype=Int)),
        "critical_rank": r,
        "owned": int(dec.owned[r]),
        "ghosts": int(dec.ghosts[r]),
        "ghost_ratio": float(dec.ghosts[r] / dec.owned[r]),
        "bonds": int(dec.bonds[r]),
        "bonds_per_point": float(dec.bonds[r] / dec.owned[r]),
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
        "efficiency": (t1 if t1 is not None else tot) / tot,
        "ghost_memory_ratio": float(mem_ghost[r] / mem_owned[r]),
        "spread": {
            "owned": spread(dec.owned),
            "ghosts": spread(dec.ghosts),
            "ghost_ratio": spread(dec.ghosts / dec.owned),
            "bonds": spread(dec.bonds),
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
        "| P | global grid | owned | ghosts | ghost/owned | nbrs | MB/step | bonds/pt "
        "| t_step (ms) | comm share | efficiency t(1)/t(P) | comm eff | ghost memory |\n"
        "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    )
    lines = [head]
    for s in rows:
        grid = "x".join(str(n) for n in s["grid"])
        lines.append(
            f"| {s['ranks']} | {grid} | {s['owned']:,} | {s['ghosts']:,} "
            f"| {100 * s['ghost_ratio']:.2f} % | {s['neighbours']} | {s['mb_per_step']:.3f} "
            f"| {s['bonds_per_point']:.2f} | {1e3 * s['t_step_s']:.2f} "
            f"| {100 * s['comm_share']:.3f} % | {100 * s['efficiency']:.2f} % "
            f"| {100 * s['comm_efficiency']:.2f} % | {100 * s['ghost_memory_ratio']:.2f} % |"
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
    ap.add_argument("--horizon", type=float, default=3.0, help="m = delta / dx (bonds)")
    ap.add_argument(
        "--ghost-width", type=float, default=None, help="ghost width / dx, >= m (None: m)"
    )
    ap.add_argument("--t-bond", type=float, default=6.7e-9, help="s per bond per core")
    ap.add_argument("--threads", type=int, default=1, help="threads (cores) per rank")
    ap.add_argument("--latency", type=float, default=2e-6, help="s per message")
    ap.add_argument("--bandwidth", type=float, default=10e9, help="bytes/s per rank")
    ap.add_argument("--allreduces", type=int, default=1, help="allreduces per step")
    ap.add_argument("--allreduce-scalars", type=int, default=4, help="float64 per allreduce")
    ap.add_argument(
        "--ghost-floats", type=int, default=0, help="float64 per ghost per step (0: 2*dim)"
    )
    ap.add_argument("--point-bytes", type=float, default=200.0, help="bytes per owned point")
    ap.add_argument("--ghost-bytes", type=float, default=200.0, help="bytes per ghost point")
    ap.add_argument("--bond-bytes", type=float, default=14.0, help="bytes per directed bond")
    ap.add_argument("--json", type=Path, default=None, help="write the results here")
    ap.add_argument(
        "--check",
        action="store_true",
        help="compare the analytic counts with a cKDTree brute force at small sizes first",
    )
    return ap


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
    width = args.ghost_width if args.ghost_width is not None else args.horizon
    if width < args.horizon:
        raise SystemExit("--ghost-width must be at least --horizon")
    cp = CostParams(
        t_bond=args.t_bond,
        threads=args.threads,
        latency=args.latency,
        bandwidth=args.bandwidth,
        allreduces=args.allreduces,
        allreduce_scalars=args.allreduce_scalars,
        ghost_floats=args.ghost_floats,
        point_bytes=args.point_bytes,
        ghost_bytes=args.ghost_bytes,
        bond_bytes=args.bond_bytes,
    )
    out: dict[str, Any] = {
        "script": "benchmarks/mpi_scaling_model.py",
        "argv": sys.argv[1:] if argv is None else argv,
        "date": _dt.datetime.now().isoformat(timespec="seconds"),
        "cpu": cpu_model(),
        "params": {**asdict(cp), "horizon": args.horizon, "ghost_width": width},
    }
    status = 0
    if args.check:
        t0 = time.perf_counter()
        print("## Check: analytic counts vs cKDTree brute force\n")
        ok = run_check(default_check_cases())
        print(f"\ncheck {'passed' if ok else 'FAILED'} ({time.perf_counter() - t0:.1f} s)\n")
        out["check_passed"] = ok
        status = 0 if ok else 1
    ranks = parse_ranks(args.ranks)
    for dim in (int(d) for d in args.dims.split(",")):
        side = args.side_2d if dim == 2 else args.side_3d
        t0 = time.perf_counter()
        t1 = summarize(
            decompose(global_shape(dim, side, 1, args.domain), 1, args.horizon, width), cp, None
        )["t_step_s"]
        rows = []
        for p in ranks:
            dec = decompose(global_shape(dim, side, p, args.domain), p, args.horizon, width)
            rows.append(summarize(dec, cp, float(t1)))
        floats = cp.ghost_floats or 2 * dim
        print(
            f"## {dim}-D, {side}^{dim} points per rank, m = {args.horizon:g}, ghost width "
            f"{width:g} dx, domain {args.domain}\n\n"
            f"t_bond = {cp.t_bond:g} s / {cp.threads} thread(s), latency {cp.latency:g} s, "
            f"bandwidth {cp.bandwidth:g} B/s, {floats} float64 per ghost, "
            f"{cp.allreduces} allreduce(s) per step; row = the rank with the longest step\n"
        )
        print(markdown_table(rows))
        print(f"\n({time.perf_counter() - t0:.1f} s)\n")
        out[f"{dim}d"] = {"side": side, "rows": rows}
    if args.json is not None:
        args.json.write_text(json.dumps(out, indent=1) + "\n")
        print(f"wrote {args.json}")
    return status


if __name__ == "__main__":
    sys.exit(main())
