"""VTK output: one .vtu per frame (points as vertex cells) plus a .pvd series for ParaView."""

from __future__ import annotations

from pathlib import Path
from typing import Literal
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np
from numpy.typing import NDArray

from peridynamics.io.atomic import atomic_path


def _pad3(a: NDArray, dtype: type = np.float64) -> NDArray:
    a = np.asarray(a, dtype=dtype)
    if a.ndim == 1 or a.shape[1] > 3:  # scalars, and tensors (9 components) as they are
        return a
    out: NDArray = np.zeros((a.shape[0], 3), dtype=dtype)
    out[:, : a.shape[1]] = a
    return out


def write_vtu(
    path: str | Path,
    x: NDArray,
    fields: dict[str, NDArray],
    precision: Literal["float32", "float64"] = "float64",
    compression: Literal["zlib", "lzma"] | None = None,
) -> None:
    """Write points ``x`` (n, dim) with point fields (vectors padded to 3 components,
    tensors of 9 row-major components as they are)
    as a binary VTU, the points and fields in ``precision``, the data blocks
    compressed with ``compression`` (ParaView reads zlib and lzma). The file appears
    atomically (written to a temporary name, then renamed)."""
    dtype = np.float32 if precision == "float32" else np.float64
    pts = _pad3(x, dtype)
    cells = [
        ("vertex", np.arange(len(pts), dtype=np.int32 if len(pts) < 2**31 else np.int64)[:, None])
    ]
    data = {k: _pad3(v, dtype) for k, v in fields.items()}
    with atomic_path(path) as tmp:
        meshio.write(
            tmp,
            meshio.Mesh(pts, cells, point_data=data),
            file_format="vtu",
            binary=True,
            compression=compression,
        )


def write_pvd(path: str | Path, frames: list[tuple[float, str]]) -> None:
    """Write a ParaView collection of (time, relative .vtu file name) entries."""
    lines = [
        '<?xml version="1.0"?>',
        '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
        "  <Collection>",
    ]
    for t, name in frames:
        lines.append(f'    <DataSet timestep="{t!r}" group="" part="0" file={quoteattr(name)}/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines))
