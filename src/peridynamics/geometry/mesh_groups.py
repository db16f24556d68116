"""Node sets from the groups of a finite-element mesh (Exodus II, Abaqus ``.inp``, ...)
read by meshio, on the cloud of cell centroids of
:func:`~peridynamics.geometry.mesh.from_mesh`.

* Element blocks: ``block_<k>`` (k = 1, 2, ... in file order), the points of the
  block's cells (Exodus element blocks; Abaqus ``*ELEMENT`` sections).
* Element sets (meshio's ``cell_sets``: Abaqus ``*ELSET`` and ``*ELEMENT, ELSET=``;
  Gmsh physical groups of a ``.msh``): the points of their cells of the cloud's kind.
* Node sets (meshio's ``point_sets``: Abaqus ``*NSET``, Exodus node sets): the point
  nearest to each node of the set, each point once.

Exodus side sets are not read by meshio 5 and are left out (export them as node sets).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import meshio
import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from peridynamics.geometry.cloud import Plane, PointCloud
from peridynamics.geometry.mesh import _AREA_CELLS, _VOLUME_CELLS, from_mesh


def _read(path: str | Path) -> meshio.Mesh:
    name = str(path)
    if Path(name).suffix.lower() in (".exo", ".e", ".ex2", ".exii"):
        try:
            import netCDF4  # noqa: F401
        except ImportError:
            raise ValueError(
                f"reading the Exodus II file {name!r} needs netCDF4: "
                'pip install "peridynamics[geometry]" (or pip install netCDF4)'
            ) from None
    try:
        return meshio.read(name)
    except Exception as exc:  # meshio raises many kinds for a bad file
        raise ValueError(f"meshio cannot read {name!r}: {exc}") from None


def group_sets(mesh: meshio.Mesh, dim: int, x: NDArray[np.float64]) -> dict[str, NDArray[np.intp]]:
    """Node sets of blocks, element sets and node sets (module docstring) on the cloud
    points ``x`` (n, dim) made from ``mesh``'s cells of dimension ``dim``, in
    :func:`~peridynamics.geometry.mesh.from_mesh`'s order."""
    wanted = _VOLUME_CELLS if dim == 3 else _AREA_CELLS
    starts: list[int | None] = []
    n = 0
    for blk in mesh.cells:
        if blk.type in wanted:
            starts.append(n)
            n += len(blk.data)
        else:
            starts.append(None)
    sets: dict[str, NDArray[np.intp]] = {}
    for k, start in enumerate(starts):
        if start is not None:
            sets[f"block_{k + 1}"] = np.arange(start, start + len(mesh.cells[k].data))
    for name, per_block in (mesh.cell_sets or {}).items():
        if name.startswith("gmsh:"):
            continue
        idx = [
            start + np.asarray(cells, dtype=np.intp)
            for start, cells in zip(starts, per_block, strict=False)
            if start is not None and cells is not None and len(cells)
        ]
        if idx:
            sets[str(name)] = np.unique(np.concatenate(idx))
    if mesh.point_sets:
        tree = cKDTree(x)
        pts = np.asarray(mesh.points, dtype=float)[:, :dim]
        for name, nodes in mesh.point_sets.items():
            nodes = np.asarray(nodes, dtype=np.intp)
            if len(nodes):
                sets[str(name)] = np.unique(tree.query(pts[nodes])[1])
    return sets


def from_mesh_groups(
    path: str | Path,
    dim: int | None = None,
    thickness: float = 1.0,
    plane: Plane = "stress",
    spacing: float | None = None,
    groups: Sequence[str] | None = None,
) -> PointCloud:
    """:func:`~peridynamics.geometry.mesh.from_mesh` with the mesh's groups as node sets.

    Parameters
    ----------
    path : str or Path
        A mesh file meshio reads (Exodus II needs netCDF4).
    dim, thickness, plane, spacing
        As for :func:`~peridynamics.geometry.mesh.from_mesh`.
    groups : sequence of str, optional
        The groups kept as node sets (default: all); a missing one is an error naming
        the groups there are.

    Returns
    -------
    PointCloud
        Cell centroids (n, dim) (m), cell volumes (n,) (m^3), node sets of the groups.
    """
    mesh = _read(path)
    cloud = from_mesh(mesh, dim=dim, thickness=thickness, plane=plane, spacing=spacing)
    sets = group_sets(mesh, cloud.dim, cloud.x)
    if groups is not None:
        missing = [g for g in groups if g not in sets]
        if missing:
            raise ValueError(
                f"no group {missing[0]!r} in the mesh {str(path)!r}; it has: {sorted(sets)}"
            )
        sets = {g: sets[g] for g in groups}
    return cloud.with_node_sets(**sets)
