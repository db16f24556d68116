"""The bond list: a frozen struct of flat arrays in directed CSR order."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.partial_volume import (
    PARTIAL_VOLUME_RULES,
    PartialVolume,
    partial_volume_factor,
    search_radius,
)
from peridynamics.bonds.precrack import Crack, crossing_bonds
from peridynamics.bonds.search import bond_chunks, directed_bonds, directed_csr, find_pairs
from peridynamics.geometry.cloud import PointCloud

#: transient memory of the per-bond set-up work, per range of bonds (bytes): the arrays
#: of a bond list are filled range by range, so building them costs about their own size
SETUP_CHUNK_BYTES = 256 * 2**20

#: clouds with at least this many points use the cell-grid search
#: (:func:`~peridynamics.bonds.search.directed_bonds`, memory-bounded); smaller ones the
#: k-d tree and a global sort, which skips loading the search kernels (~35 ms once per
#: process) where its transients are small anyway. Both give the same arrays, bit for bit.
CELL_SEARCH_MIN_POINTS = 30_000


def setup_chunk_bonds(dim: int, bytes_per_bond: int = 0) -> int:
    """Bonds per range of the set-up work: :data:`SETUP_CHUNK_BYTES` over the transient
    bytes of one bond (``bytes_per_bond``; by default two gathered positions and about a
    dozen float64 temporaries)."""
    per_bond = bytes_per_bond or (16 * dim + 96)
    return max(SETUP_CHUNK_BYTES // per_bond, 1)


@dataclass(frozen=True)
class Bonds:
    """Directed full bond list (both (i, j) and (j, i)), bonds of point i contiguous.

    Attributes
    ----------
    offsets : (n_points + 1,) int64
        Bonds of point ``i`` are ``offsets[i]:offsets[i + 1]``.
    bond_i, bond_j : (n_bonds,) int32
        Owner point and neighbour point of each directed bond.
    bond_xi : (n_bonds, dim) float64
        Reference bond vector ``x_j - x_i`` (m).
    bond_length : (n_bonds,) float64
        ``|xi|`` (m).
    bond_volume : (n_bonds,) float64
        Partial volume ``beta * V_j`` (m^3) used in every family sum.
    bond_correction : (n_bonds,) float64
        Surface-correction factor (1 without correction), symmetric in (i, j).
    bond_intact : (n_bonds,) uint8
        1 for intact bonds, 0 for bonds cut by pre-cracks.
    horizon : float
        delta (m).
    partial_volume : str
        Rule used for ``bond_volume`` (see :mod:`peridynamics.bonds.partial_volume`).
    """

    offsets: NDArray[np.int64]
    bond_i: NDArray[np.int32]
    bond_j: NDArray[np.int32]
    bond_xi: NDArray[np.float64]
    bond_length: NDArray[np.float64]
    bond_volume: NDArray[np.float64]
    bond_correction: NDArray[np.float64]
    bond_intact: NDArray[np.uint8]
    horizon: float
    partial_volume: str

    @cached_property
    def inv_length(self) -> NDArray[np.float64]:
        """``1 / |xi|`` (1/m), shape (n_bonds,): computed once and shared by the force
        model, the evaluator and the damage law."""
        return 1.0 / self.bond_length

    @property
    def n_bonds(self) -> int:
        """Number of directed bonds."""
        return int(self.bond_j.shape[0])

    @property
    def n_points(self) -> int:
        """Number of points."""
        return int(self.offsets.shape[0] - 1)

    @property
    def family_size(self) -> NDArray[np.int64]:
        """Number of bonds per point, shape (n_points,)."""
        return np.diff(self.offsets)

    @property
    def nbytes(self) -> int:
        """Memory held by the per-bond arrays (bytes)."""
        return sum(
            a.nbytes
            for a in (
                self.bond_i,
                self.bond_j,
                self.bond_xi,
                self.bond_length,
                self.bond_volume,
                self.bond_correction,
                self.bond_intact,
            )
        )

    def reverse_index(self) -> NDArray[np.int64]:
        """Index of bond (j, i) for every bond (i, j), shape (n_bonds,)."""
        n = np.int64(self.n_points)
        key = self.bond_i.astype(np.int64) * n + self.bond_j
        rkey = self.bond_j.astype(np.int64) * n + self.bond_i
        return np.searchsorted(key, rkey)  # keys are sorted by construction

    def cut(self, x: NDArray[np.float64], cracks: Sequence[Crack]) -> Bonds:
        """Return a copy with every bond crossing one of ``cracks`` marked broken."""
        hit = crossing_bonds(x, self.bond_i, self.bond_j, cracks)
        intact = self.bond_intact.copy()
        intact[hit] = 0
        return replace(self, bond_intact=intact)

    def with_correction(self, factors: NDArray[np.float64]) -> Bonds:
        """Return a copy with per-bond surface-correction ``factors`` (n_bonds,)."""
        f = np.ascontiguousarray(factors, dtype=np.float64)
        if f.shape != (self.n_bonds,):
            raise ValueError(f"expected {self.n_bonds} correction factors, got {f.shape}")
        return replace(self, bond_correction=f)


def build_bonds(
    cloud: PointCloud,
    horizon: float,
    partial_volume: PartialVolume = "truncated",
    cracks: Sequence[Crack] = (),
) -> Bonds:
    """Find every bond within the horizon and build the directed CSR list.

    Parameters
    ----------
    cloud : PointCloud
    horizon : float
        delta (m); must be >= the grid spacing.
    partial_volume : {"truncated", "extended", "none"}
        Partial-volume rule (Lu & Wang (2016), eq. 9 / SED-PD (2021), eq. 11 / none).
    cracks : sequence of cracks
        Pre-cracks; bonds crossing them start broken.

    Raises
    ------
    ValueError
        If delta < dx, or some point has no bond (it would move freely).

    Notes
    -----
    Memory: for clouds of at least :data:`CELL_SEARCH_MIN_POINTS` points the search
    allocates ``offsets``, ``bond_i`` and ``bond_j`` once (no pair list, no global
    sort), and every per-bond array is allocated once and filled in ranges of
    :data:`SETUP_CHUNK_BYTES` of transients, so the peak is the bond list itself plus
    O(n_points) and one range. The arrays are the same, bit for bit, as the one-shot
    construction (k-d tree pairs, sort, whole-array expressions).
    """
    dx = cloud.spacing
    if not horizon >= dx * (1 - 1e-9):
        raise ValueError(
            f"horizon {horizon} m is smaller than the grid spacing {dx} m: every point "
            "would be alone; use horizon >= spacing (typically about 3 * spacing)"
        )
    if partial_volume not in PARTIAL_VOLUME_RULES:
        raise ValueError(
            f"unknown partial_volume {partial_volume!r}; use one of {PARTIAL_VOLUME_RULES}"
        )
    x = cloud.x
    radius = search_radius(horizon, dx, partial_volume)
    if cloud.n_points >= CELL_SEARCH_MIN_POINTS:
        offsets, bond_i, bond_j = directed_bonds(x, radius)
    else:
        offsets, bond_i, bond_j = directed_csr(find_pairs(x, radius), cloud.n_points)
    n_bonds = len(bond_j)
    xi = np.empty((n_bonds, cloud.dim))
    length = np.empty(n_bonds)
    volume = np.empty(n_bonds)
    keep: NDArray[np.bool_] | None = None
    for a, b in bond_chunks(offsets, setup_chunk_bonds(cloud.dim)):  # bounded transients
        part = xi[a:b]
        np.subtract(x[bond_j[a:b]], x[bond_i[a:b]], out=part)
        length[a:b] = np.sqrt(np.einsum("ij,ij->i", part, part))
        beta = partial_volume_factor(length[a:b], horizon, dx, partial_volume)
        volume[a:b] = beta * cloud.volume[bond_j[a:b]]
        if not np.all(beta > 0):  # zero-weight bonds (rare: only at the search rim)
            if keep is None:
                keep = np.ones(n_bonds, dtype=bool)
            keep[a:b] = beta > 0
    if keep is not None:  # drop them, one array at a time
        bond_i, bond_j = bond_i[keep], bond_j[keep]
        xi, length, volume = xi[keep], length[keep], volume[keep]
        offsets = np.zeros(cloud.n_points + 1, dtype=np.int64)
        np.cumsum(np.bincount(bond_i, minlength=cloud.n_points), out=offsets[1:])
    lonely = np.flatnonzero(np.diff(offsets) == 0)
    if lonely.size:
        k = int(lonely[0])
        raise ValueError(
            f"{lonely.size} point(s) have no bond within the horizon {horizon} m, e.g. point "
            f"{k} at {x[k].tolist()}; increase the horizon or remove isolated points"
        )
    bonds = Bonds(
        offsets=offsets,
        bond_i=np.ascontiguousarray(bond_i),
        bond_j=np.ascontiguousarray(bond_j),
        bond_xi=np.ascontiguousarray(xi),
        bond_length=np.ascontiguousarray(length),
        bond_volume=np.ascontiguousarray(volume),
        bond_correction=np.ones(len(bond_j)),
        bond_intact=np.ones(len(bond_j), dtype=np.uint8),
        horizon=float(horizon),
        partial_volume=str(partial_volume),
    )
    if cracks:
        bonds = bonds.cut(x, cracks)
    return bonds
