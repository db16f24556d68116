"""Finite-difference tangent of any force model (fallback and test oracle).

``K = -d(V f)/du`` (N/m), shape (n dim, n dim), by central differences. The force of
point i depends on the displacements of the points at most ``reach`` bonds away (1 for a
bond-based model, 2 for a state-based one through the neighbours' dilatation), so the
points of a colour whose mutual distances exceed ``2 reach r_max`` (r_max the longest
bond) can be perturbed together: no point feels two of them, and the change of its force
is attributed to the one perturbed point within its reach (the sparsity pattern of
:func:`assemble_pattern`). Each column then gets the very same numbers as a
one-dof-at-a-time difference, with ``2 dim n_colours`` force evaluations instead of
``2 dim n``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds

if TYPE_CHECKING:
    from peridynamics.families.base import ForceModel
    from peridynamics.state import State

#: default perturbation relative to the grid spacing: central differences of the
#: geometric nonlinearity err by O((eps/dx)^2), round-off by O(1e-16 dx / eps)
_REL_EPS = 1e-6


def assemble_pattern(bonds: Bonds, reach: int = 2) -> sp.csr_matrix:
    """Point-level sparsity pattern of the tangent, (n, n) CSR of ones (float64).

    Entry (i, p) is present when point p is at most ``reach`` bonds from point i (every
    bond of the list counted, broken or not), itself included.
    """
    if reach < 1:
        raise ValueError(f"reach must be >= 1, got {reach}")
    n = bonds.n_points
    adj = sp.csr_matrix(
        (np.ones(bonds.n_bonds), (bonds.bond_i, bonds.bond_j)), shape=(n, n)
    ) + sp.identity(n, format="csr")
    pattern = adj
    for _ in range(reach - 1):
        pattern = pattern @ adj
    pattern = sp.csr_matrix(pattern)
    pattern.data[:] = 1.0
    pattern.sort_indices()
    return pattern


def grid_colouring(x: NDArray[np.float64], separation: float, cell: float) -> NDArray[np.intp]:
    """Colour points so that two points of one colour are farther apart than
    ``separation`` (m), shape (n,).

    Points are binned into cells of size ``cell`` (nearest cell centre); the colour is
    the cell index modulo ``k = ceil(separation / cell) + 1`` per axis plus the rank of
    the point within its cell. Same-colour points lie in cells at least ``k`` apart
    along some axis, hence more than ``(k - 1) cell >= separation`` apart. On a regular
    grid of spacing ``cell`` this gives ``k^dim`` colours.
    """
    if not (separation >= 0 and cell > 0):
        raise ValueError("separation must be >= 0 and cell > 0")
    n, d = x.shape
    k = math.ceil(separation / cell) + 1
    idx = np.floor((x - x.min(axis=0)) / cell + 0.5).astype(np.int64)
    residue = np.zeros(n, dtype=np.int64)
    for a in range(d):  # loop over the (<= 3) axes only
        residue = residue * k + idx[:, a] % k
    # rank of each point within its cell
    span = idx.max(axis=0) + 1
    key = np.ravel_multi_index(tuple(idx.T), tuple(span))
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    first = np.searchsorted(sorted_key, sorted_key, side="left")
    rank = np.empty(n, dtype=np.int64)
    rank[order] = np.arange(n) - first
    colours = rank * k**d + residue
    # renumber densely 0..n_colours-1
    _, dense = np.unique(colours, return_inverse=True)
    return np.asarray(dense.reshape(-1), dtype=np.intp)


def _evaluate(model: ForceModel, work: State, u: NDArray[np.float64]) -> NDArray[np.float64]:
    work.u[...] = u
    model.prepass(work)
    model.force(work)
    return np.array(work.force, dtype=np.float64, copy=True)


def finite_difference_tangent(
    model: ForceModel,
    state: State,
    eps: float | None = None,
    reach: int | None = None,
    colours: NDArray[np.integer] | None = None,
) -> sp.csr_matrix:
    """Central-difference tangent K = -d(V f)/du (N/m), shape (n dim, n dim), CSR.

    Parameters
    ----------
    model : ForceModel
        Evaluated with ``prepass`` then ``force`` on a copy of ``state``.
    state : State
        Linearisation point (``u``, ``intact``, any model field); not changed.
    eps : float, optional
        Displacement perturbation (m); default ``1e-6 * cloud.spacing``.
    reach : int, optional
        Bonds over which a displacement acts on a force; default ``model.reach`` if the
        model has one, else 2 (safe for bond- and state-based models).
    colours : (n,) int, optional
        Point colouring; points of one colour are perturbed together and must be more
        than ``2 reach`` bonds apart. Default: :func:`grid_colouring` with separation
        ``2 reach r_max``. ``np.arange(n)`` gives the brute-force one-point-at-a-time
        tangent.

    Returns
    -------
    scipy.sparse.csr_matrix
        Entries on the ``reach`` pattern of :func:`assemble_pattern` (N/m).
    """
    cloud, bonds = model.cloud, model.bonds
    n, d = cloud.n_points, cloud.dim
    if bonds.n_points != n:
        raise NotImplementedError("the finite-difference tangent needs every family (no ghosts)")
    if reach is None:
        reach = int(getattr(model, "reach", 2))
    h = float(eps) if eps is not None else _REL_EPS * cloud.spacing
    if not h > 0:
        raise ValueError(f"eps must be > 0 m, got {eps}")
    if colours is None:
        r_max = float(bonds.bond_length.max()) if bonds.n_bonds else 0.0
        colours = grid_colouring(cloud.x, 2.0 * reach * r_max * (1.0 + 1e-9), cloud.spacing)
    colours = np.asarray(colours, dtype=np.intp)
    if colours.shape != (n,):
        raise ValueError(f"colours must have shape ({n},), got {colours.shape}")
    pattern = assemble_pattern(bonds, reach).tocoo()
    rows = pattern.row.astype(np.intp)
    cols = pattern.col.astype(np.intp)
    if len(np.unique(colours[cols] * n + rows)) != len(rows):
        raise ValueError("colours are too coarse: a point feels two points of one colour")
    order = np.argsort(colours[cols], kind="stable")
    rows, cols = rows[order], cols[order]
    n_colours = int(colours.max()) + 1
    bounds = np.searchsorted(colours[cols], np.arange(n_colours + 1))
    values = np.empty((len(rows), d, d))  # [entry, row component, column component]
    work = state.copy()
    u0 = np.array(state.u, dtype=np.float64, copy=True)
    vol = cloud.volume
    scale = -vol / (2.0 * h)
    for colour in range(n_colours):  # loop over colours (not points)
        lo, hi = bounds[colour], bounds[colour + 1]
        if lo == hi:
            continue
        members = np.flatnonzero(colours == colour)
        r = rows[lo:hi]
        for c in range(d):
            up = u0.copy()
            up[members, c] = u0[members, c] + h
            f_plus = _evaluate(model, work, up)
            up[members, c] = u0[members, c] - h
            f_minus = _evaluate(model, work, up)
            values[lo:hi, :, c] = (f_plus[r] - f_minus[r]) * scale[r][:, None]
    comp = np.arange(d)
    rr = (rows[:, None, None] * d + comp[None, :, None]) * np.ones((1, 1, d), dtype=np.intp)
    cc = (cols[:, None, None] * d + comp[None, None, :]) * np.ones((1, d, 1), dtype=np.intp)
    k = sp.csr_matrix((values.ravel(), (rr.ravel(), cc.ravel())), shape=(n * d, n * d))
    k.sum_duplicates()
    return k
