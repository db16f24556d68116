"""The bond list: a frozen struct of flat arrays in directed CSR order."""

from __future__ import annotations

from collections.abc import Sequence

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
SETUP_CHUNK_BYTES = 64 * 2**20

#: clouds with at least this many points use the cell-grid search
#: (:func:`~peridynamics.bonds.search.directed_bonds`, memory-bounded); smaller ones the
#: k-d tree and a global sort, which skips loading the search kernels (~35 ms once per
#: process) where its transients are small anyway. Both give the same arrays, bit for bit.
CELL_SEARCH_MIN_POINTS = 30_000


def bond_norm(xi: NDArray[np.float64]) -> NDArray[np.float64]:
    """Row norms, shape (n,): the squares summed component by component in order,
    ((xi_0^2 + xi_1^2) + xi_2^2), the order the kernels use when they recompute |xi|
    from the positions (``np.einsum`` pairs components differently in 3-D)."""
    sq = xi[:, 0] * xi[:, 0]
    for c in range(1, xi.shape[1]):
        sq += xi[:, c] * xi[:, c]
    return np.sqrt(sq)


def setup_chunk_bonds(dim: int, bytes_per_bond: int = 0) -> int:
    """Bonds per range of the set-up work: :data:`SETUP_CHUNK_BYTES` over the transient
    bytes of one bond (``bytes_per_bond``; by default two gathered positions and about a
    dozen float64 temporaries)."""
    per_bond = bytes_per_bond or (16 * dim + 96)
    return max(SETUP_CHUNK_BYTES // per_bond, 1)


#: per-bond arrays a :class:`Bonds` can hold; all but ``bond_j`` and ``bond_intact`` are
#: derived from the positions on first use when they were not given
PER_BOND = (
    "bond_i", "bond_j", "bond_xi", "bond_length", "bond_volume", "bond_correction",
    "bond_intact",
)  # fmt: skip
#: arrays that depend on which bonds there are (not on their state)
_TOPOLOGY = ("offsets", "bond_j")


class Bonds:
    """Directed full bond list (both (i, j) and (j, i)), bonds of point i contiguous.

    What is stored per directed bond is the neighbour index (int32) and the as-built
    intact flag (uint8): 5 bytes. Everything else per bond is derived from the
    reference positions ``x``, the point volumes and the spacing on first use (and
    then kept), unless it was given (a surface correction, sub-lists of bodies): a run
    whose kernels recompute |xi| from ``x`` (the bond-based force pass, its diagnostics)
    never materialises those arrays. :meth:`bond_range` gives a range of any of them
    without keeping the whole.

    Attributes
    ----------
    offsets : (n_points + 1,) int64
        Bonds of point ``i`` are ``offsets[i]:offsets[i + 1]``.
    bond_j : (n_bonds,) int32
        Neighbour point of each directed bond.
    bond_intact : (n_bonds,) uint8
        1 for intact bonds, 0 for bonds cut by pre-cracks.
    bond_i : (n_bonds,) int32
        Owner point (derived from ``offsets``).
    bond_xi : (n_bonds, dim) float64
        Reference bond vector ``x_j - x_i`` (m) (derived).
    bond_length : (n_bonds,) float64
        ``|xi|`` (m) (derived).
    bond_volume : (n_bonds,) float64
        Partial volume ``beta * V_j`` (m^3) used in every family sum (derived).
    bond_correction : (n_bonds,) float64
        Surface-correction factor (1 without correction), symmetric in (i, j).
    horizon : float
        delta (m).
    partial_volume : str
        Rule used for ``bond_volume`` (see :mod:`peridynamics.bonds.partial_volume`).

    Examples
    --------
    >>> import numpy as np
    >>> import peridynamics as pd
    >>> grid = np.meshgrid(np.arange(10), np.arange(5), indexing="ij")
    >>> x = np.stack(grid, -1).reshape(-1, 2) * 1e-3  # m
    >>> cloud = pd.PointCloud(x=x, volume=np.full(50, 1e-9), spacing=1e-3, plane="stress")
    >>> bonds = pd.build_bonds(cloud, 3.015e-3)
    >>> int(bonds.offsets[1] - bonds.offsets[0])  # the family of point 0 (a corner)
    10
    """

    def __init__(
        self,
        offsets: NDArray[np.int64],
        bond_j: NDArray[np.int32],
        bond_intact: NDArray[np.uint8] | None = None,
        horizon: float = 0.0,
        partial_volume: str = "truncated",
        *,
        x: NDArray[np.float64] | None = None,
        point_volume: NDArray[np.float64] | None = None,
        spacing: float = 0.0,
        **given: NDArray | None,
    ) -> None:
        unknown = set(given) - set(PER_BOND)
        if unknown:
            raise TypeError(f"unknown bond arrays {sorted(unknown)}; known: {PER_BOND}")
        self.offsets = offsets
        self.bond_j = bond_j
        self.horizon = float(horizon)
        self.partial_volume = str(partial_volume)
        self.x = x
        self.point_volume = point_volume
        self.spacing = float(spacing)
        self._arrays: dict[str, NDArray] = {k: v for k, v in given.items() if v is not None}
        if bond_intact is None:
            bond_intact = np.ones(len(bond_j), dtype=np.uint8)
        self.bond_intact = bond_intact

    # -- derived per-bond arrays, kept once made ---------------------------------------
    def _get(self, name: str) -> NDArray:
        got = self._arrays.get(name)
        if got is None:
            got = self._derive(name, 0, self.n_bonds)
            self._arrays[name] = got
        return got

    @property
    def bond_i(self) -> NDArray[np.int32]:
        return self._get("bond_i")

    @property
    def bond_xi(self) -> NDArray[np.float64]:
        return self._get("bond_xi")

    @property
    def bond_length(self) -> NDArray[np.float64]:
        return self._get("bond_length")

    @property
    def bond_volume(self) -> NDArray[np.float64]:
        return self._get("bond_volume")

    @property
    def bond_correction(self) -> NDArray[np.float64]:
        return self._get("bond_correction")

    @property
    def inv_length(self) -> NDArray[np.float64]:
        """``1 / |xi|`` (1/m), shape (n_bonds,): computed once and shared."""
        got = self._arrays.get("inv_length")
        if got is None:
            got = self._arrays["inv_length"] = 1.0 / self.bond_length
        return got

    def bond_range(self, name: str, a: int, b: int) -> NDArray:
        """Bonds ``a:b`` of the per-bond array ``name`` (a view when it is kept, else
        computed for that range alone: the same bits as the whole array's)."""
        got = self._arrays.get(name)
        if got is not None:
            return got[a:b]
        return self._derive(name, a, b)

    def _owners(self, a: int, b: int) -> NDArray[np.int32]:
        p0 = int(np.searchsorted(self.offsets, a, side="right")) - 1
        p1 = int(np.searchsorted(self.offsets, b, side="left"))
        rows = np.arange(p0, p1, dtype=np.int32)
        counts = np.diff(np.clip(self.offsets[p0 : p1 + 1], a, b)).astype(np.int64)
        return np.repeat(rows, counts)

    def _derive(self, name: str, a: int, b: int) -> NDArray:
        if name == "bond_i":
            return self._owners(a, b)
        if name == "bond_correction":
            return np.ones(b - a)
        if name == "bond_intact":
            return self.bond_intact[a:b]
        if self.x is None:
            raise ValueError(
                f"this bond list was built without positions and has no {name!r}; pass it "
                "or build the list with build_bonds"
            )
        x = self.x
        if name == "bond_xi":
            return x[self.bond_j[a:b]] - x[self.bond_range("bond_i", a, b)]
        xi = self.bond_range("bond_xi", a, b)
        length = bond_norm(xi)
        if name == "bond_length":
            return length
        if name == "bond_volume":
            if self.point_volume is None:
                raise ValueError("this bond list has no point volumes; pass bond_volume")
            beta = partial_volume_factor(
                length,
                self.horizon,
                self.spacing,
                self.partial_volume,  # type: ignore[arg-type]
            )
            return beta * self.point_volume[self.bond_j[a:b]]
        raise KeyError(name)

    # -- sizes --------------------------------------------------------------------------
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
        """Memory held now by the per-bond arrays (bytes): the stored ones and those
        derived so far."""
        held: list[NDArray] = [self.bond_j, self.bond_intact, *self._arrays.values()]
        return int(sum(a.nbytes for a in held))

    @property
    def held(self) -> tuple[str, ...]:
        """Names of the per-bond arrays held now besides ``bond_j`` and ``bond_intact``."""
        return tuple(self._arrays)

    # -- copies -------------------------------------------------------------------------
    def replace(self, **changes: object) -> Bonds:
        """A copy with ``changes`` (any constructor argument). Derived arrays are kept
        unless the topology (``offsets``, ``bond_j``) changes."""
        keep_derived = not any(k in changes for k in _TOPOLOGY)
        kw: dict[str, object] = dict(
            offsets=self.offsets, bond_j=self.bond_j, bond_intact=self.bond_intact,
            horizon=self.horizon, partial_volume=self.partial_volume, x=self.x,
            point_volume=self.point_volume, spacing=self.spacing,
        )  # fmt: skip
        if keep_derived:
            kw.update({k: v for k, v in self._arrays.items() if k in PER_BOND})
        elif "bond_correction" in self._arrays and "bond_correction" not in changes:
            raise ValueError("changing the bonds of a corrected list needs bond_correction")
        kw.update(changes)
        return Bonds(**kw)  # type: ignore[arg-type]

    def reverse_index(self) -> NDArray[np.int64]:
        """Index of bond (j, i) for every bond (i, j), shape (n_bonds,)."""
        n = np.int64(self.n_points)
        key = self.bond_i.astype(np.int64) * n + self.bond_j
        rkey = self.bond_j.astype(np.int64) * n + self.bond_i
        if len(key) < 2 or bool(np.all(key[1:] > key[:-1])):
            got = np.searchsorted(key, rkey)  # keys sorted by construction (serial)
            if bool(np.all(got < len(key))) and np.array_equal(key[got], rkey):
                return got
        # a rank's list (families in global-id order, ghosts of the second layer
        # without a family): look up through a sort; a bond whose reverse is not held
        # here points to itself (only ghost families have such bonds)
        order = np.argsort(key, kind="stable")
        pos = np.minimum(np.searchsorted(key, rkey, sorter=order), len(key) - 1)
        found = order[pos]
        return np.where(key[found] == rkey, found, np.arange(len(key)))

    def cut(self, x: NDArray[np.float64], cracks: Sequence[Crack]) -> Bonds:
        """Return a copy with every bond crossing one of ``cracks`` marked broken."""
        return self.without(crossing_bonds(x, self.bond_i, self.bond_j, cracks))

    def without(self, hit: NDArray[np.bool_]) -> Bonds:
        """Return a copy with the bonds of mask ``hit`` (n_bonds,) marked broken."""
        intact = self.bond_intact.copy()
        intact[hit] = 0
        return self.replace(bond_intact=intact)

    def with_correction(self, factors: NDArray[np.float64]) -> Bonds:
        """Return a copy with per-bond surface-correction ``factors`` (n_bonds,)."""
        f = np.ascontiguousarray(factors, dtype=np.float64)
        if f.shape != (self.n_bonds,):
            raise ValueError(f"expected {self.n_bonds} correction factors, got {f.shape}")
        return self.replace(bond_correction=f)


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
    sort); the partial volumes are checked in ranges of :data:`SETUP_CHUNK_BYTES` of
    transients, and only ``offsets``, ``bond_j`` (int32) and ``bond_intact`` (uint8) are
    kept: 5 bytes per directed bond. The other per-bond arrays are derived on first use
    (:class:`Bonds`), the same bits as the one-shot construction (k-d tree pairs, sort,
    whole-array expressions).

    Examples
    --------
    >>> import numpy as np
    >>> import peridynamics as pd
    >>> grid = np.meshgrid(np.arange(10), np.arange(5), indexing="ij")
    >>> x = np.stack(grid, -1).reshape(-1, 2) * 1e-3  # m
    >>> cloud = pd.PointCloud(x=x, volume=np.full(50, 1e-9), spacing=1e-3, plane="stress")
    >>> bonds = pd.build_bonds(cloud, horizon=3.015e-3)
    >>> bonds.n_bonds
    896
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
    keep: NDArray[np.bool_] | None = None
    for a, b in bond_chunks(offsets, setup_chunk_bonds(cloud.dim)):  # bounded transients
        xi = x[bond_j[a:b]] - x[bond_i[a:b]]
        length = bond_norm(xi)
        beta = partial_volume_factor(length, horizon, dx, partial_volume)
        if not np.all(beta > 0):  # zero-weight bonds (rare: only at the search rim)
            if keep is None:
                keep = np.ones(len(bond_j), dtype=bool)
            keep[a:b] = beta > 0
    if keep is not None:  # drop them
        bond_i, bond_j = bond_i[keep], bond_j[keep]
        offsets = np.zeros(cloud.n_points + 1, dtype=np.int64)
        np.cumsum(np.bincount(bond_i, minlength=cloud.n_points), out=offsets[1:])
    del bond_i  # derived again from the offsets when someone asks
    lonely = np.flatnonzero(np.diff(offsets) == 0)
    if lonely.size:
        k = int(lonely[0])
        raise ValueError(
            f"{lonely.size} point(s) have no bond within the horizon {horizon} m, e.g. point "
            f"{k} at {x[k].tolist()}; increase the horizon or remove isolated points"
        )
    bonds = Bonds(
        offsets=offsets,
        bond_j=np.ascontiguousarray(bond_j, dtype=np.int32),
        bond_intact=np.ones(len(bond_j), dtype=np.uint8),
        horizon=float(horizon),
        partial_volume=str(partial_volume),
        x=x,
        point_volume=cloud.volume,
        spacing=dx,
    )
    if cracks:
        bonds = bonds.cut(x, cracks)
    return bonds
