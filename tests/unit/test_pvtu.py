"""Parallel VTU output: pieces written by ``write_vtu``, the ``.pvtu`` file of
``write_pvtu`` that names them, and a ``.pvd`` series of ``.pvtu`` files."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Literal

import meshio
import numpy as np
import pytest
from numpy.typing import NDArray

from peridynamics.io.pvtu import piece_name, pvtu_fields, write_pvtu
from peridynamics.io.vtk import write_pvd, write_vtu

N_PIECES = 3
Precision = Literal["float32", "float64"]
Compression = Literal["zlib", "lzma"] | None
FRAME = "frame_0000010.vtu"


def _cloud(n: int = 41) -> tuple[NDArray, dict[str, NDArray]]:
    """A random 2-D point cloud with float64 and float32 fields of 1 and 2 components."""
    rng = np.random.default_rng(7)
    x = rng.uniform(-1.0, 1.0, (n, 2))
    fields: dict[str, NDArray] = {
        "damage": rng.uniform(0.0, 1.0, n),  # float64, 1 component
        "displacement": rng.normal(size=(n, 2)),  # float64, 2 components
        "theta": rng.normal(size=n).astype(np.float32),  # float32, 1 component
        "velocity": rng.normal(size=(n, 2)).astype(np.float32),  # float32, 2 components
    }
    return x, fields


def _write_set(
    folder: Path, precision: Precision, compression: Compression
) -> tuple[Path, list[NDArray], NDArray, dict[str, NDArray]]:
    """Split the cloud in uneven pieces, one ``write_vtu`` per 'rank', and the pvtu."""
    x, fields = _cloud()
    owned = np.array_split(np.random.default_rng(1).permutation(len(x)), [9, 23])
    names = []
    for rank, idx in enumerate(owned):
        name = piece_name(FRAME, rank)
        piece = {k: v[idx] for k, v in fields.items()}
        write_vtu(folder / name, x[idx], piece, precision=precision, compression=compression)
        names.append(name)
    pvtu = folder / FRAME.replace(".vtu", ".pvtu")
    write_pvtu(pvtu, names, precision, pvtu_fields(fields, precision))
    return pvtu, owned, x, fields


def _ncomp(el: ET.Element) -> int:
    return int(el.get("NumberOfComponents", "1"))


def test_piece_name() -> None:
    assert piece_name("frame_000010.vtu", 3) == "frame_000010_p0003.vtu"
    assert piece_name("frame_000010.pvtu", 0) == "frame_000010_p0000.vtu"
    assert piece_name("event_fracture", 12) == "event_fracture_p0012.vtu"
    assert piece_name("frame_1.vtu", 12345) == "frame_1_p12345.vtu"
    with pytest.raises(ValueError):
        piece_name("frame_1.vtu", -1)


@pytest.mark.parametrize("precision", ["float32", "float64"])
def test_pvtu_fields_cast_like_write_vtu(precision: Precision) -> None:
    _, fields = _cloud()
    decl = pvtu_fields(fields, precision)
    want = np.dtype(precision)
    assert list(decl) == list(fields)
    assert decl == {
        "damage": (want, 1),
        "displacement": (want, 3),
        "theta": (want, 1),
        "velocity": (want, 3),
    }


@pytest.mark.parametrize(
    "precision,compression", [("float32", "zlib"), ("float64", None), ("float32", "lzma")]
)
def test_pvtu_matches_pieces(
    tmp_path: Path, precision: Precision, compression: Compression
) -> None:
    pvtu, owned, x, fields = _write_set(tmp_path, precision, compression)
    root = ET.parse(pvtu).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "PUnstructuredGrid"
    grid = root.find("PUnstructuredGrid")
    assert grid is not None and grid.get("GhostLevel") == "0"
    pdata = {el.get("Name"): el for el in grid.iterfind("PPointData/PDataArray")}
    ppoints = grid.findall("PPoints/PDataArray")
    assert len(ppoints) == 1 and _ncomp(ppoints[0]) == 3
    assert ppoints[0].get("type") == ("Float32" if precision == "float32" else "Float64")
    assert list(pdata) == list(fields)

    sources = [el.get("Source") for el in grid.iterfind("Piece")]
    assert sources == [piece_name(FRAME, r) for r in range(N_PIECES)]
    meshes = []
    for src in sources:
        assert src is not None and not Path(src).is_absolute()
        path = pvtu.parent / src  # (b) every piece lies beside the pvtu file
        assert path.is_file()
        # (a) the declared types are exactly those in the piece's own XML header
        piece = ET.parse(path).getroot().find("UnstructuredGrid/Piece")
        assert piece is not None
        pts = piece.find("Points/DataArray")
        assert pts is not None
        assert pts.get("type") == ppoints[0].get("type") and _ncomp(pts) == 3
        arrays = {el.get("Name"): el for el in piece.iterfind("PointData/DataArray")}
        assert list(arrays) == list(pdata)
        for name, decl in pdata.items():
            assert arrays[name].get("type") == decl.get("type"), name
            assert _ncomp(arrays[name]) == _ncomp(decl), name
        # ... and those meshio reads back
        mesh = meshio.read(path)
        assert meshio.vtu._vtu.numpy_to_vtu_type[mesh.points.dtype] == pts.get("type")
        for name, decl in pdata.items():
            a = mesh.point_data[name]
            assert meshio.vtu._vtu.numpy_to_vtu_type[a.dtype] == decl.get("type")
            assert (1 if a.ndim == 1 else a.shape[1]) == _ncomp(decl)
        meshes.append(mesh)

    # (c) the pieces, concatenated, are the original arrays (cast and padded to 3-D)
    order = np.concatenate(owned)
    dt = np.dtype(precision)
    xyz = np.concatenate([m.points for m in meshes])
    np.testing.assert_array_equal(xyz[:, :2], x[order].astype(dt))
    np.testing.assert_array_equal(xyz[:, 2], 0.0)
    for name, values in fields.items():
        got = np.concatenate([m.point_data[name] for m in meshes])
        want = values[order].astype(dt)
        if want.ndim == 2:
            np.testing.assert_array_equal(got[:, 2], 0.0)
            got = got[:, : want.shape[1]]
        np.testing.assert_array_equal(got, want, err_msg=name)
    assert not list(tmp_path.glob("*.tmp*"))  # written atomically, nothing left over


def test_pvd_lists_pvtu_files(tmp_path: Path) -> None:
    """``write_pvd`` takes any relative file names: a series of ``.pvtu`` frames."""
    frames = [(0.0, "frame_0000000.pvtu"), (2.5e-6, "frame_0000010.pvtu")]
    write_pvd(tmp_path / "run.pvd", frames)
    root = ET.parse(tmp_path / "run.pvd").getroot()
    assert root.get("type") == "Collection"
    got = [(float(el.get("timestep", "nan")), el.get("file")) for el in root.iter("DataSet")]
    assert got == frames


def test_write_pvtu_rejects_bad_declarations(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="VTK XML type"):
        write_pvtu(tmp_path / "a.pvtu", ["a_p0000.vtu"], np.float64, {"z": (np.complex128, 1)})
    with pytest.raises(ValueError, match="NumberOfComponents"):
        write_pvtu(tmp_path / "a.pvtu", ["a_p0000.vtu"], np.float64, {"z": (np.float64, 0)})
    with pytest.raises(ValueError, match="VTK XML type"):
        write_pvtu(tmp_path / "a.pvtu", ["a_p0000.vtu"], np.float16, {})
    assert not (tmp_path / "a.pvtu").exists()


@pytest.mark.parametrize("precision,compression", [("float32", "zlib"), ("float64", None)])
def test_vtk_reads_pvtu(tmp_path: Path, precision: Precision, compression: Compression) -> None:
    """VTK's own reader (ParaView's) opens the set: skipped where VTK is not installed."""
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    pvtu, owned, x, fields = _write_set(tmp_path, precision, compression)
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(str(pvtu))
    reader.Update()
    assert reader.GetErrorCode() == 0
    grid = reader.GetOutput()
    order = np.concatenate(owned)
    dt = np.dtype(precision)
    assert grid.GetNumberOfPoints() == len(x) and grid.GetNumberOfCells() == len(x)
    pts = vtk_to_numpy(grid.GetPoints().GetData())
    assert pts.dtype == dt
    np.testing.assert_array_equal(pts[:, :2], x[order].astype(dt))
    pd = grid.GetPointData()
    for name, values in fields.items():
        a = vtk_to_numpy(pd.GetArray(name))
        assert a.dtype == dt, name
        np.testing.assert_array_equal(a[:, : values.shape[1]] if a.ndim == 2 else a,
                                      values[order].astype(dt), err_msg=name)  # fmt: skip
