"""Point clouds from Gmsh models (``.geo`` meshed by gmsh, or a ``.msh``) with their
physical groups as node sets.

Points are the centroids of the model's cells (tetrahedra and hexahedra in 3-D,
triangles and quadrangles in 2-D), each with its cell's volume (area x thickness in
2-D), as :func:`~peridynamics.geometry.mesh.from_mesh` makes them. Physical groups
become node sets named after the group (an unnamed group: ``physical_<dim>_<tag>``):

* a group of the model's dimension (a physical volume in 3-D, a physical surface in
  2-D): the points of the cells of its entities;
* a lower-dimensional group (surfaces, curves, points): the point nearest to each mesh
  node gmsh lists for the group (``gmsh.model.mesh.getNodesForPhysicalGroup``), each
  point once.

A ``.geo`` is meshed with first-order elements no larger than ``mesh_size`` (m, in
file units before ``scale``). The default, from the grid spacing dx, gives cells of the
volume of a grid cell: edges of about 2.04 dx for tetrahedra (a regular tetrahedron of
edge h has the volume h^3 / (6 sqrt 2)) and 1.52 dx for triangles (area sqrt(3) h^2 / 4).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from peridynamics.geometry.cloud import Plane, PointCloud
from peridynamics.geometry.mesh import _cell_centroids_and_measures

INSTALL = 'pip install "peridynamics[geometry]"'
#: gmsh element type -> (meshio-style kind, nodes); first-order cells only
_KINDS = {2: ("triangle", 3), 3: ("quad", 4), 4: ("tetra", 4), 5: ("hexahedron", 8)}
#: element edge for one cell of volume dx^dim, in units of dx
_EDGE_PER_DX = {2: math.sqrt(4.0 / math.sqrt(3.0)), 3: (6.0 * math.sqrt(2.0)) ** (1.0 / 3.0)}


def default_mesh_size(spacing: float, dim: int) -> float:
    """Element edge (m) whose regular simplex has the volume of a grid cell dx^dim."""
    return _EDGE_PER_DX[dim] * spacing


def _gmsh() -> Any:
    try:
        import gmsh
    except ImportError:
        raise ValueError(
            f"Gmsh models need the gmsh wheel: {INSTALL} (or pip install gmsh)"
        ) from None
    return gmsh


def _open(gmsh: Any, path: Path, mesh_size: float | None, dim: int | None, cell: float) -> int:
    """Open (and for a .geo mesh) the model; return its dimension. ``cell``: the grid
    spacing in file units (the default element size)."""
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.Verbosity", 1)
    try:
        gmsh.open(str(path))
    except Exception as exc:
        raise ValueError(f"gmsh cannot read {str(path)!r}: {exc}") from None
    model_dim = int(gmsh.model.getDimension()) if dim is None else int(dim)
    if model_dim not in (2, 3):
        raise ValueError(f"{str(path)!r} holds a {model_dim}-D model; 2-D or 3-D is needed")
    if path.suffix.lower() != ".msh":
        size = default_mesh_size(cell, model_dim) if mesh_size is None else mesh_size
        gmsh.option.setNumber("Mesh.MeshSizeMax", float(size))
        gmsh.option.setNumber("Mesh.ElementOrder", 1)
        try:
            gmsh.model.mesh.generate(model_dim)
        except Exception as exc:
            raise ValueError(f"gmsh cannot mesh {str(path)!r}: {exc}") from None
    return model_dim


def _cells(
    gmsh: Any, dim: int, scale: float, path: Path
) -> tuple[NDArray[np.float64], NDArray[np.float64], dict[int, NDArray[np.intp]]]:
    """Centroids (n, 3), measures (n,) and the cell indices of each entity of ``dim``."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    where = np.zeros(int(tags.max()) + 1 if len(tags) else 1, dtype=np.intp)
    where[tags.astype(np.intp)] = np.arange(len(tags))
    xyz = np.asarray(coords, dtype=float).reshape(-1, 3) * scale
    centres, sizes, by_entity, n = [], [], {}, 0
    for _, ent in gmsh.model.getEntities(dim):
        types, _, nodes = gmsh.model.mesh.getElements(dim, ent)
        start = n
        for etype, enodes in zip(types, nodes, strict=True):
            if int(etype) not in _KINDS:
                name = gmsh.model.mesh.getElementProperties(int(etype))[0]
                raise ValueError(
                    f"{str(path)!r} has {name} cells; first-order triangles, quadrangles, "
                    "tetrahedra or hexahedra are needed (Mesh.ElementOrder = 1, no prisms)"
                )
            kind, k = _KINDS[int(etype)]
            pts = xyz[where[np.asarray(enodes, dtype=np.intp)]].reshape(-1, k, 3)[:, :, :dim]
            c, s = _cell_centroids_and_measures(kind, pts)
            centres.append(c)
            sizes.append(s)
            n += len(c)
        by_entity[int(ent)] = np.arange(start, n)
    if not centres:
        raise ValueError(f"{str(path)!r} has no {dim}-D cells (mesh it, or check its dim)")
    return np.concatenate(centres), np.concatenate(sizes), by_entity


def _group_sets(
    gmsh: Any,
    dim: int,
    scale: float,
    x: NDArray[np.float64],
    by_entity: Mapping[int, NDArray[np.intp]],
    wanted: Sequence[str] | None,
) -> dict[str, NDArray[np.intp]]:
    """Node sets of the physical groups (see the module docstring)."""
    tree = cKDTree(x)
    sets: dict[str, NDArray[np.intp]] = {}
    for gdim, tag in gmsh.model.getPhysicalGroups():
        name = gmsh.model.getPhysicalName(gdim, tag) or f"physical_{gdim}_{tag}"
        if wanted is not None and name not in wanted:
            continue
        if gdim == dim:
            ents = gmsh.model.getEntitiesForPhysicalGroup(gdim, tag)
            idx = np.concatenate([by_entity.get(int(e), np.zeros(0, np.intp)) for e in ents])
        elif gdim < dim:
            _, coords = gmsh.model.mesh.getNodesForPhysicalGroup(gdim, tag)
            pts = np.asarray(coords, dtype=float).reshape(-1, 3)[:, :dim] * scale
            idx = tree.query(pts)[1] if len(pts) else np.zeros(0, np.intp)
        else:
            continue
        sets[name] = np.unique(np.asarray(idx, dtype=np.intp))
    missing = sorted(set(wanted or ()) - set(sets))
    if missing:
        known = sorted(
            gmsh.model.getPhysicalName(d, t) or f"physical_{d}_{t}"
            for d, t in gmsh.model.getPhysicalGroups()
        )
        raise ValueError(f"no physical group {missing[0]!r} in the model; it has: {known}")
    return sets


def from_gmsh(
    path: str | Path,
    spacing: float,
    dim: int | None = None,
    mesh_size: float | None = None,
    scale: float = 1.0,
    thickness: float = 1.0,
    plane: Plane = "stress",
    groups: Sequence[str] | None = None,
) -> PointCloud:
    """A cloud of cell centroids of a Gmsh model with its physical groups as node sets.

    Parameters
    ----------
    path : str or Path
        ``.geo`` (meshed here) or ``.msh`` file.
    spacing : float
        Nominal point spacing dx (m); a ``.geo`` is meshed at ``default_mesh_size``
        unless ``mesh_size`` is given.
    dim : {2, 3}, optional
        Model dimension; default: the model's (gmsh's ``getDimension``).
    mesh_size : float, optional
        Largest element edge for a ``.geo``, in file units.
    scale : float
        Metres per file unit.
    thickness, plane
        2-D only: volume = cell area x thickness (m), plane stress or strain.
    groups : sequence of str, optional
        The physical groups to keep as node sets (default: all).

    Returns
    -------
    PointCloud
        Points (n, dim) (m) with volumes (n,) (m^3) and one node set per group.

    Notes
    -----
    In a gmsh session the caller has open, the model read here becomes its current
    model and the session stays open; otherwise gmsh is initialised and finalised here.
    """
    gmsh = _gmsh()
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"gmsh file {str(path)!r} does not exist")
    own = not gmsh.isInitialized()  # a caller's gmsh session is left open
    if own:
        gmsh.initialize(readConfigFiles=False)
    try:
        model_dim = _open(gmsh, path, mesh_size, dim, spacing / scale)
        x, size, by_entity = _cells(gmsh, model_dim, scale, path)
        sets = _group_sets(gmsh, model_dim, scale, x, by_entity, groups)
    finally:
        if own:
            gmsh.finalize()
    if model_dim == 2:
        return PointCloud(x=x, volume=size * thickness, spacing=spacing,
                          cross_section=thickness, plane=plane, node_sets=sets,
                          irregular=True)  # fmt: skip
    return PointCloud(x=x, volume=size, spacing=spacing, node_sets=sets, irregular=True)


def model_dimension(path: str | Path) -> int:
    """The dimension of a Gmsh model (2 or 3) without meshing it."""
    gmsh = _gmsh()
    own = not gmsh.isInitialized()
    if own:
        gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        try:
            gmsh.open(str(path))
        except Exception as exc:
            raise ValueError(f"gmsh cannot read {str(path)!r}: {exc}") from None
        return int(gmsh.model.getDimension())
    finally:
        if own:
            gmsh.finalize()
