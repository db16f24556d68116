"""VTK output: one .vtu per frame (points as vertex cells) plus a .pvd series for ParaView."""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np
from numpy.typing import NDArray


def _pad3(a: NDArray) -> NDArray:
    a = np.asarray(a, dtype=np.float64)
    if a.ndim == 1:
        return a
    out = np.zeros((a.shape[0], 3))
    out[:, : a.shape[1]] = a
    return out


def write_vtu(path: str | Path, x: NDArray, fields: dict[str, NDArray]) -> None:
    """Write points ``x`` (n, dim) with point fields (vectors padded to 3 components)."""
    pts = _pad3(x)
    cells = [("vertex", np.arange(len(pts), dtype=np.int64)[:, None])]
    data = {k: _pad3(v) for k, v in fields.items()}
    tmp = Path(str(path) + ".tmp.vtu")
    meshio.write(
        tmp,
        meshio.Mesh(pts, cells, point_data=data),
        file_format="vtu",
        binary=True,
        compression=None,
    )
    os.replace(tmp, path)


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
    tmp = Path(str(path) + ".tmp")
    tmp.write_text("\n".join(lines))
    os.replace(tmp, path)
