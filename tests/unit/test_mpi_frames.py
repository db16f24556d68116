"""The frames of ``mpiexec -n 2 peridynamics run``, written piece by piece by their ranks
(:mod:`peridynamics.io.observers.frame_pieces`): every frame of the series and every
event frame (``first_damage``, ``fracture``, the kept ``peak_load``) holds the serial
run's points and fields bit for bit, piece r the points rank r owns in global order;
the ``.pvtu`` files declare the arrays of their pieces; no field of a frame is gathered
on rank 0 (``timing.to_root``); a resumed decomposed run writes the same frames as the
uninterrupted one. ``mpi`` tier (``pytest -m mpi``)."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

from peridynamics.io.pvtu import VTK_TYPES
from tests.helpers import EXAMPLES, cli, mpiexec

MPIEXEC, WHY = mpiexec()
pytestmark = [pytest.mark.skipif(MPIEXEC is None, reason=WHY), pytest.mark.mpi]

BRANCHING = [
    str(EXAMPLES / "crack_branching_2d" / "deck.yaml"),
    "--set", "discretisation.spacing=1e-3",
    "--set", "discretisation.horizon=4e-3",
    "--set", "output.plot=none",
    "--set", "output.vtk_every=20",
    "--set", "output.frames_on=[first_damage,fracture]",
]  # fmt: skip
ROCK = [
    str(EXAMPLES / "rock_compression" / "flaw45.yaml"),
    "--set", "discretisation.spacing=1e-3",
    "--set", "solver.steps=300",
    "--set", "output.plot=none",
    "--set", "output.vtk_every=50",
    "--set", "output.frames_on=[peak_load]",
    "--set", "output.frame_precision=float64",
]  # fmt: skip


def _run(*args: str, ranks: int = 1, env: dict[str, str] | None = None):
    env = {"NUMBA_NUM_THREADS": "1", **(env or {})}
    return cli("run", *args, "--quiet", env=env, timeout=240, ranks=ranks)


def _series(folder: Path) -> list[tuple[str, str]]:
    """(timestep, file stem) of each data set of the run's ``.pvd`` series."""
    root = ET.parse(next(folder.glob("*.pvd"))).getroot()
    return [(d.get("timestep", ""), Path(d.get("file", "")).stem) for d in root.iter("DataSet")]


def _pieces(pvtu: Path) -> list[meshio.Mesh]:
    """The pieces of a ``.pvtu`` file (checked against its declarations), rank order."""
    root = ET.parse(pvtu).getroot()
    declared = {
        a.get("Name"): (a.get("type"), int(a.get("NumberOfComponents", "1")))
        for a in root.find("PUnstructuredGrid/PPointData").iter("PDataArray")  # type: ignore[union-attr]
    }
    meshes = [meshio.read(pvtu.parent / str(p.get("Source"))) for p in root.iter("Piece")]
    for m in meshes:
        got = {
            k: (VTK_TYPES[np.asarray(v).dtype], 1 if np.ndim(v) == 1 else np.shape(v)[1])
            for k, v in m.point_data.items()
        }
        assert got == declared, pvtu.name
    return meshes


def _same_frame(serial: Path, pvtu: Path) -> None:
    """A frame's pieces hold the serial frame's points and fields, bit for bit, each
    piece its points in the serial (global) order."""
    whole = meshio.read(serial)
    row = {p.tobytes(): i for i, p in enumerate(whole.points)}  # points are distinct
    pieces = _pieces(pvtu)
    assert len(pieces) == 2
    seen = []
    for m in pieces:
        idx = np.array([row[p.tobytes()] for p in m.points], dtype=np.intp)
        assert np.all(np.diff(idx) > 0), f"{pvtu.name}: a piece out of global order"
        np.testing.assert_array_equal(m.points, whole.points[idx])
        assert list(m.point_data) == list(whole.point_data)
        for k, v in whole.point_data.items():
            np.testing.assert_array_equal(m.point_data[k], v[idx], err_msg=f"{pvtu.name} {k}")
        seen.append(idx)
    assert np.array_equal(np.sort(np.concatenate(seen)), np.arange(len(whole.points)))


def _same_frames(serial: Path, mpi: Path, events: tuple[str, ...]) -> None:
    series = _series(serial)
    assert series and _series(mpi) == series
    for _, stem in series:
        _same_frame(serial / f"{stem}.vtu", mpi / f"{stem}.pvtu")
    for name in events:
        _same_frame(serial / f"event_{name}.vtu", mpi / f"event_{name}.pvtu")


def _to_root(folder: Path) -> dict[str, dict[str, int]]:
    return json.loads((folder / "summary.json").read_text())["timing"]["to_root"]


def test_frames_of_two_ranks_are_the_serial_frames(tmp_path: Path) -> None:
    assert _run(*BRANCHING, "--out", str(tmp_path / "s")).returncode == 0
    mpi = _run(*BRANCHING, "--out", str(tmp_path / "m"), ranks=2)
    assert mpi.returncode == 0, mpi.stderr
    events = json.loads((tmp_path / "m" / "summary.json").read_text())["results"]["events"]
    assert {"first_damage", "fracture"} <= set(events)
    assert events["fracture"]["file"] == "event_fracture.pvtu"
    _same_frames(tmp_path / "s", tmp_path / "m", ("first_damage", "fracture"))
    audit = _to_root(tmp_path / "m")
    assert audit["call:_write_piece"]["requests"] == len(_series(tmp_path / "m")) + 2
    assert audit["call:_write_piece"]["bytes"] == 0  # no field of a frame on rank 0
    assert audit.get("gather:v", {"requests": 0})["requests"] <= 1  # final_state.npz only


def test_kept_peak_frame_and_a_resumed_run(tmp_path: Path) -> None:
    """The peak-load frame every rank keeps is the serial one; a run killed at step 130
    and resumed from its step-100 checkpoint writes the frames of the whole run."""
    assert _run(*ROCK, "--out", str(tmp_path / "s")).returncode == 0
    whole = _run(*ROCK, "--out", str(tmp_path / "m"), ranks=2)
    assert whole.returncode == 0, whole.stderr
    _same_frames(tmp_path / "s", tmp_path / "m", ("peak_load",))
    out = str(tmp_path / "cut")
    crash = {"PERIDYNAMICS_CRASH_AT_STEP": "130", "PERIDYNAMICS_CRASH_RANK": "1"}
    died = _run(*ROCK, "--out", out, "--checkpoint-every", "50", ranks=2, env=crash)
    assert died.returncode != 0
    resumed = _run(*ROCK, "--resume", out, ranks=2)
    assert resumed.returncode == 0, resumed.stderr
    _same_frames(tmp_path / "s", tmp_path / "cut", ("peak_load",))
