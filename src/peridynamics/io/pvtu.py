"""Parallel VTU output: one ``.vtu`` piece per MPI rank and a ``.pvtu`` file per frame.

In an MPI run each rank writes the points it owns as one piece with
:func:`peridynamics.io.vtk.write_vtu` (named by :func:`piece_name`, beside the
``.pvtu`` file), and rank 0 writes the ``.pvtu`` file of the frame with
:func:`write_pvtu`. The ``.pvd`` series written by
:func:`peridynamics.io.vtk.write_pvd` then lists the ``.pvtu`` file names in place of
the ``.vtu`` ones, and ParaView opens the whole set as one data set per time.

A ``.pvtu`` file holds no data: it declares the type and the number of components of
every point array and of the points, and names the pieces. The declarations must be
exactly those inside the pieces (ParaView's reader refuses a piece whose arrays differ
from them), so they are derived here, by :func:`pvtu_fields`, with the same casting
that :func:`~peridynamics.io.vtk.write_vtu` applies: every field and the points in the
frame ``precision``, arrays of one dimension as scalars, arrays of two dimensions
padded to 3 components.

Reference: Kitware, "VTK File Formats", in *The VTK User's Guide*, 11th ed., section
"XML File Formats", subsection "Parallel File Formats" (the PUnstructuredGrid file with
its ``PPointData``, ``PPoints`` and ``Piece`` elements). Online:
https://docs.vtk.org/en/latest/vtk_file_formats/vtkxml_file_format.html
"""

from __future__ import annotations

import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Literal
from xml.sax.saxutils import quoteattr

import numpy as np
from numpy.typing import DTypeLike, NDArray

from peridynamics.io.atomic import atomic_path
from peridynamics.io.vtk import _pad3

__all__ = ["VTK_TYPES", "piece_name", "pvtu_fields", "write_pvtu"]

#: The VTK XML name of each numpy data type (the types meshio writes in a ``.vtu``).
VTK_TYPES: dict[np.dtype, str] = {
    np.dtype(np.float32): "Float32",
    np.dtype(np.float64): "Float64",
    np.dtype(np.int8): "Int8",
    np.dtype(np.int16): "Int16",
    np.dtype(np.int32): "Int32",
    np.dtype(np.int64): "Int64",
    np.dtype(np.uint8): "UInt8",
    np.dtype(np.uint16): "UInt16",
    np.dtype(np.uint32): "UInt32",
    np.dtype(np.uint64): "UInt64",
}


def piece_name(frame_name: str, rank: int) -> str:
    """The file name of the piece that ``rank`` writes of a frame.

    Parameters
    ----------
    frame_name : str
        The frame's file name, ``.vtu`` or ``.pvtu`` (e.g. ``frame_000010.vtu``); a
        name with neither suffix is taken as the stem.
    rank : int
        The MPI rank that writes the piece (0 or more).

    Returns
    -------
    str
        The stem of ``frame_name`` with ``_p`` and the rank in 4 digits (more for
        ranks past 9999) and the suffix ``.vtu``, e.g. ``frame_000010_p0003.vtu``.
        Any folder in ``frame_name`` is kept: the pieces lie beside the ``.pvtu``
        file.

    Raises
    ------
    ValueError
        If ``rank`` is negative.
    """
    if rank < 0:
        raise ValueError(f"rank must be >= 0, got {rank}")
    stem = frame_name
    for suffix in (".pvtu", ".vtu"):
        if stem.endswith(suffix):
            stem = stem[: -len(suffix)]
            break
    return f"{stem}_p{rank:04d}.vtu"


def pvtu_fields(
    fields: Mapping[str, NDArray], precision: Literal["float32", "float64"] = "float64"
) -> dict[str, tuple[np.dtype, int]]:
    """The data type and number of components of each field as ``write_vtu`` writes it.

    The arrays are cast exactly as :func:`peridynamics.io.vtk.write_vtu` casts them
    (through its ``_pad3``, applied to an empty slice of each array, so nothing is
    copied): to ``precision``, with one component for an array of one dimension and
    3 for an array of two dimensions (fewer columns are padded with zeros).

    Parameters
    ----------
    fields : Mapping[str, NDArray]
        The point fields passed to ``write_vtu`` (any rank's: only the dimensions of
        the arrays count, not their length).
    precision : {"float32", "float64"}
        The ``precision`` passed to ``write_vtu``.

    Returns
    -------
    dict[str, tuple[numpy.dtype, int]]
        Name to (data type, number of components), in the order of ``fields``: the
        ``point_data`` argument of :func:`write_pvtu`.
    """
    dtype = np.float32 if precision == "float32" else np.float64
    out: dict[str, tuple[np.dtype, int]] = {}
    for name, values in fields.items():
        a = _pad3(np.asarray(values)[:0], dtype)
        out[name] = (a.dtype, 1 if a.ndim == 1 else int(a.shape[1]))
    return out


def _vtk_type(dtype: DTypeLike) -> str:
    dt = np.dtype(dtype).newbyteorder("=")
    try:
        return VTK_TYPES[dt]
    except KeyError:
        raise ValueError(f"no VTK XML type for numpy type {dt}") from None


def write_pvtu(
    path: str | Path,
    pieces: Sequence[str],
    points_dtype: DTypeLike,
    point_data: Mapping[str, tuple[DTypeLike, int]],
) -> None:
    """Write the ``.pvtu`` file (VTK XML PUnstructuredGrid) of a frame split in pieces.

    Parameters
    ----------
    path : str or Path
        The ``.pvtu`` file to write; it appears atomically (written to a temporary
        name, then renamed).
    pieces : Sequence[str]
        The pieces' file names relative to the folder of ``path`` (as
        :func:`piece_name` makes them), one ``<Piece Source=...>`` each, in order.
    points_dtype : numpy data type
        The type of the pieces' points: the ``precision`` of ``write_vtu``
        (``"float32"`` or ``"float64"``).
    point_data : Mapping[str, tuple[numpy data type, int]]
        Name to (data type, number of components) of each point array of the
        pieces, as :func:`pvtu_fields` returns it.

    Raises
    ------
    ValueError
        If a type has no VTK name, a number of components is below 1, or a piece
        name is empty.

    Notes
    -----
    The pieces are the ``.vtu`` files of meshio (``version="0.1"``, UInt32 block
    headers); this file carries no data block, so its own ``version="1.0"`` and
    ``header_type="UInt64"`` do not constrain them: VTK reads each piece with its
    own header.
    """
    byte_order = "LittleEndian" if sys.byteorder == "little" else "BigEndian"
    lines = [
        '<?xml version="1.0"?>',
        f'<VTKFile type="PUnstructuredGrid" version="1.0" byte_order="{byte_order}"'
        ' header_type="UInt64">',
        '  <PUnstructuredGrid GhostLevel="0">',
        "    <PPointData>",
    ]
    for name, (dtype, ncomp) in point_data.items():
        if int(ncomp) < 1:
            raise ValueError(f"field {name!r}: NumberOfComponents must be >= 1, got {ncomp}")
        lines.append(
            f'      <PDataArray type="{_vtk_type(dtype)}" Name={quoteattr(name)}'
            f' NumberOfComponents="{int(ncomp)}"/>'
        )
    lines += [
        "    </PPointData>",
        "    <PPoints>",
        f'      <PDataArray type="{_vtk_type(points_dtype)}" Name="Points"'
        ' NumberOfComponents="3"/>',
        "    </PPoints>",
    ]
    for source in pieces:
        if not source:
            raise ValueError("empty piece file name")
        lines.append(f"    <Piece Source={quoteattr(source)}/>")
    lines += ["  </PUnstructuredGrid>", "</VTKFile>", ""]
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines), encoding="utf-8")
