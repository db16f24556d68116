"""Point clouds from finite-element meshes (through meshio): one point per cell."""

from __future__ import annotations

import contextlib
import io
from collections.abc import Callable
from pathlib import Path

import meshio
import numpy as np
from numpy.typing import NDArray

from peridynamics.geometry.cloud import Plane, PointCloud

_AREA_CELLS = {"triangle", "quad"}
_VOLUME_CELLS = {"tetra", "hexahedron"}


def _triangle_area(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """Areas of triangles p (n, 3, 2 or 3)."""
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    if p.shape[2] == 2:
        return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    return 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)


def _tet_volume(p: NDArray[np.float64]) -> NDArray[np.float64]:
    a, b, c, d = (p[:, k] for k in range(4))
    return np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))) / 6.0


#: simplex decompositions of the cells: triangles of a quad, tetrahedra of a hexahedron
#: (VTK ordering, split around the 0-6 diagonal)
_SPLITS: dict[str, list[tuple[int, ...]]] = {
    "triangle": [(0, 1, 2)],
    "quad": [(0, 1, 2), (0, 2, 3)],
    "tetra": [(0, 1, 2, 3)],
    "hexahedron": [
        (0, 1, 2, 6),
        (0, 2, 3, 6),
        (0, 3, 7, 6),
        (0, 7, 4, 6),
        (0, 4, 5, 6),
        (0, 5, 1, 6),
    ],
}


def _cell_centroids_and_measures(
    kind: str, pts: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centroids (n, dim) and areas/volumes (n,) of cells with vertices pts (n, k, dim),
    exact for straight-edged cells: the measure-weighted mean of simplex centroids."""
    measure: Callable[[NDArray[np.float64]], NDArray[np.float64]] = (
        _triangle_area if kind in ("triangle", "quad") else _tet_volume
    )
    total = np.zeros(len(pts))
    moment = np.zeros((len(pts), pts.shape[2]))
    for simplex in _SPLITS[kind]:
        sub = pts[:, list(simplex)]
        w = measure(sub)
        total += w
        moment += w[:, None] * sub.mean(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        centroid = np.where(total[:, None] > 0, moment / total[:, None], pts.mean(axis=1))
    return centroid, total


def from_mesh(
    path: str | Path | meshio.Mesh,
    dim: int | None = None,
    thickness: float = 1.0,
    plane: Plane = "stress",
    spacing: float | None = None,
) -> PointCloud:
    """Build a cloud with one point per cell at its centroid and the cell's volume.

    Centroids and measures are exact for straight-edged cells (triangles, quads,
    tetrahedra, hexahedra; quads and hexahedra through a simplex split).

    Parameters
    ----------
    path : path or meshio.Mesh
        Any file meshio reads (Gmsh, VTU, Abaqus, ...).
    dim : {2, 3}, optional
        2 uses triangle/quad cells (volume = area * thickness); 3 uses tetra/hexahedron
        cells. Default: 3 if the mesh has volume cells, else 2.
    spacing : float, optional
        Nominal spacing; default the cube (3-D) or square (2-D) root of the mean cell size.
    """
    if isinstance(path, meshio.Mesh):
        mesh = path
    else:
        said = io.StringIO()  # meshio may print its reason and then raise SystemExit(1)
        try:
            with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said):
                mesh = meshio.read(path)
        except (Exception, SystemExit) as exc:
            reason = " ".join(said.getvalue().split()).removeprefix("Error: ")
            if not isinstance(exc, SystemExit) and str(exc):
                reason = f"{reason}; {exc}" if reason else str(exc)
            detail = f": {reason}" if reason else " (not a mesh format meshio recognises)"
            raise ValueError(f"meshio cannot read {str(path)!r}{detail}") from None
    kinds = {blk.type for blk in mesh.cells}
    if dim is None:
        dim = 3 if kinds & _VOLUME_CELLS else 2
    wanted = _VOLUME_CELLS if dim == 3 else _AREA_CELLS
    centres, measures = [], []
    for blk in mesh.cells:
        if blk.type not in wanted:
            continue
        pts = np.asarray(mesh.points, dtype=float)[blk.data][:, :, :dim]
        centre, size = _cell_centroids_and_measures(blk.type, pts)
        centres.append(centre)
        measures.append(size)
    if not centres:
        raise ValueError(
            f"mesh has no {'/'.join(sorted(wanted))} cells for a {dim}-D cloud "
            f"(found: {', '.join(sorted(kinds)) or 'none'})"
        )
    x = np.concatenate(centres)
    size = np.concatenate(measures)
    if spacing is None:
        spacing = float(np.mean(size) ** (1.0 / dim))
    if dim == 2:
        return PointCloud(
            x=x, volume=size * thickness, spacing=spacing, cross_section=thickness, plane=plane
        )
    return PointCloud(x=x, volume=size, spacing=spacing)
