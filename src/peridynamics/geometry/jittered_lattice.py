"""A jittered grid body described without its points, like a regular
:class:`~peridynamics.geometry.lattice.Lattice`: any window of points, with its global
ids and nodal volumes, is made on demand, bit for bit the rows of the whole cloud.

The offsets are the rows of the one ``(n_grid, dim)`` uniform draw of
``numpy.random.default_rng(seed)`` in grid order (:func:`~peridynamics.geometry.jitter.grid_offsets`
jumps the generator to a slab's first row), added before the removed regions are tested,
as the generators describe (:mod:`peridynamics.geometry.generators`). The Voronoi
volumes are computed in fixed blocks of slabs, each with a margin of slabs around it
(:func:`~peridynamics.geometry.jitter.block_volumes`), so the volume of a point is the
same whichever rank (or the one process) asks for it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from peridynamics.geometry.cloud import PointCloud
from peridynamics.geometry.jitter import block_volumes, check_jitter, grid_offsets
from peridynamics.geometry.lattice import Lattice
from peridynamics.geometry.regions import Region


@dataclass(frozen=True)
class JitteredLattice(Lattice):
    """A :class:`Lattice` whose grid points are jittered (``jitter`` in (0, 1/2) of the
    spacing, ``seed``), with ``volumes`` ``"voronoi"`` or ``"cell"`` and, in 2-D, the
    ``thickness`` (m) the areas are multiplied by."""

    jitter: float = 0.0
    seed: int = 0
    volumes: str = "voronoi"
    thickness: float = 1.0

    def __post_init__(self) -> None:
        super().__post_init__()
        check_jitter(self.jitter, self.seed)
        if self.volumes not in ("voronoi", "cell"):
            raise ValueError(f"volumes must be 'voronoi' or 'cell', got {self.volumes!r}")

    @property
    def irregular(self) -> bool:
        """True: the points are not a regular grid."""
        return self.jitter > 0

    @property
    def per_slab(self) -> int:
        """Grid points per slab of the first axis."""
        return math.prod(self.shape[1:])

    def with_removed(self, *regions: Region) -> JitteredLattice:
        """The lattice with further regions removed (notches), still jittered."""
        return jittered_lattice(
            super().with_removed(*regions), self.jitter, self.seed, self.volumes, self.thickness
        )

    def grid(self, i0: int = 0, i1: int | None = None) -> NDArray[np.float64]:
        """The jittered grid points of the slabs ``i0 <= i < i1`` (grid order, removed
        ones included), shape (n, dim) (m)."""
        g = super().grid(i0, i1)
        if self.jitter == 0:
            return g
        start = i0 * self.per_slab
        off = grid_offsets(self.seed, self.jitter, self.spacing, start, len(g), self.dim)
        return np.asarray(g + off, np.float64)

    def slab_volumes(self, i0: int, i1: int) -> NDArray[np.float64]:
        """Nodal volumes (m^3) of every grid point of slabs ``i0 <= i < i1`` (removed ones
        included), grid order."""
        n = (i1 - i0) * self.per_slab
        if self.volumes == "cell" or self.jitter == 0:
            vol = np.full(n, self.spacing**self.dim)
        else:
            vol = block_volumes(
                self.grid, self.shape[0], self.per_slab, self.lo, self.hi, self.spacing, i0, i1
            )
        return vol * self.thickness if self.dim == 2 else vol

    def volumes_at(self, index: NDArray[np.intp]) -> NDArray[np.float64]:
        """Nodal volumes (m^3) of the grid points of indices ``index`` (n, dim)."""
        if len(index) == 0:
            return np.zeros(0)
        i0, i1 = int(index[:, 0].min()), int(index[:, 0].max()) + 1
        vol = self.slab_volumes(i0, i1)
        flat = (index[:, 0] - i0) * self.per_slab
        if self.dim > 1:
            flat = flat + np.ravel_multi_index(tuple(index[:, 1:].T), self.shape[1:])
        return vol[flat]

    def cloud(self) -> PointCloud:
        """The whole body (without node sets), the generators' jittered cloud."""
        x = self.grid()
        keep = self.kept(x)
        return PointCloud(
            x=x[keep],
            volume=self.slab_volumes(0, self.shape[0])[keep],
            spacing=self.spacing,
            cross_section=self.cross_section,
            plane=self.plane,
            irregular=self.irregular,
            grid_fit=self.grid_fit,
        )


def jittered_lattice(
    lattice: Lattice, jitter: float, seed: int, volumes: str = "voronoi", thickness: float = 1.0
) -> JitteredLattice:
    """``lattice`` jittered (arguments as in :class:`JitteredLattice`)."""
    return JitteredLattice(
        lattice.axes, lattice.lo, lattice.hi, lattice.spacing, lattice.cell_volume,
        lattice.removed, lattice.cross_section, lattice.plane, lattice.grid_fit,
        jitter, seed, volumes, thickness,
    )  # fmt: skip
