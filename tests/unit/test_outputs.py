"""Research outputs: history.csv, derived probes, frames at times and events, compact
VTU frames, several figure kinds, 3-D slices, stress-strain from first contact."""

from __future__ import annotations

import copy
import csv
import json
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import meshio
import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.deck import DeckError, parse_deck

PLATE: dict[str, Any] = {
    "name": "plate",
    "geometry": {"type": "rectangle", "size": [0.04, 0.02], "thickness": 1e-3},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
    "material": {"model": "pmb", "youngs_modulus": 65e9, "density": 2235.0},
    "damage": {"fracture_energy": 204.0},
    "node_sets": {
        "top": {"edge": {"normal": [0.0, 1.0]}},
        "bottom": {"edge": {"normal": [0.0, -1.0]}},
        "mouth_top": {"point": [0.0, 0.0115]},
        "mouth_bottom": {"point": [0.0, 0.0085]},
    },
    "precracks": [{"points": [[0.0, 0.01], [0.015, 0.01]]}],
    "boundary_conditions": [
        {"type": "traction", "set": "top", "value": [0.0, 20e6]},
        {"type": "traction", "set": "bottom", "value": [0.0, -20e6]},
    ],
    "solver": {"end_time": 8e-6},
    "output": {
        "history_every": 5,
        "probes": [
            {"name": "uy_top", "quantity": "displacement", "set": "mouth_top", "component": "y"},
            {"name": "uy_bot", "quantity": "displacement", "set": "mouth_bottom", "component": "y"},
            {"name": "cmod", "quantity": "difference", "of": ["uy_top", "uy_bot"]},
            {"name": "both", "quantity": "sum", "of": ["uy_top", "uy_bot", "cmod"]},
            {"name": "load", "quantity": "reaction_force", "set": "top", "component": "y",
             "reduce": "sum"},
        ],
    },
}  # fmt: skip


def deck_with(**output: Any) -> dict[str, Any]:
    d = copy.deepcopy(PLATE)
    d["output"].update(output)
    return d


def run(d: dict[str, Any], out: Path) -> dict[str, Any]:
    return Simulation.from_deck(parse_deck(d)).run(out, quiet=True, progress=False)


@pytest.fixture(scope="module")
def plate_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, Any]]:
    out = tmp_path_factory.mktemp("plate")
    d = deck_with(
        frames_at=[2e-6, 2.01e-6, 5e-6],
        frames_on=["first_damage", "fracture", "peak_load"],
        plot=["damage", "deformed", "probes", "energies"],
        png_frames=True,
    )
    return out, run(d, out)


def test_derived_probes_are_the_difference_and_the_sum_at_every_record(plate_run) -> None:
    _, summary = plate_run
    p = {k: np.asarray(v["values"]) for k, v in summary["results"]["probes"].items()}
    assert np.array_equal(p["cmod"], p["uy_top"] - p["uy_bot"])
    assert np.allclose(p["both"], p["uy_top"] + p["uy_bot"] + p["cmod"], rtol=0, atol=1e-20)
    assert p["cmod"][-1] > 0  # the crack mouth opens


def test_history_csv_has_one_column_per_history_with_units(plate_run) -> None:
    out, summary = plate_run
    with open(out / "history.csv") as fh:
        rows = list(csv.reader(fh))
    header, body = rows[0], np.array(rows[1:], dtype=float)
    for col in ("time [s]", "kinetic_energy [J]", "strain_energy [J]", "max_damage [-]",
                "uy_top [m]", "cmod [m]", "load [N]", "crack_length [m]"):  # fmt: skip
        assert col in header
    r = summary["results"]
    assert np.array_equal(body[:, header.index("time [s]")], r["history"]["time_s"])
    assert np.array_equal(body[:, header.index("cmod [m]")], r["probes"]["cmod"]["values"])
    crack = body[:, header.index("crack_length [m]")]
    assert np.array_equal(crack, r["crack_length_history_m"]) and crack[-1] > 0
    assert "history.csv" in summary["files"]


def test_frames_at_times_are_the_first_steps_at_or_after_them(plate_run) -> None:
    out, summary = plate_run
    pvd = ET.parse(out / "plate.pvd").getroot()
    times = [float(e.get("timestep")) for e in pvd.iter("DataSet")]
    dt = summary["results"]["time_step_s"]
    assert times[0] == 0.0 and times[-1] == pytest.approx(summary["results"]["final_time_s"])
    inner = times[1:-1]
    # 2e-6 and 2.01e-6 fall into the same step: one frame; then 5e-6
    assert len(inner) == 2
    for t_frame, t_asked in zip(inner, [2e-6, 5e-6], strict=True):
        assert t_asked <= t_frame + 1e-15 < t_asked + dt * (1 + 1e-9)
    assert len(list((out / "png").glob("frame_*.png"))) == len(times)


def test_first_damage_event_is_the_step_of_the_first_broken_bond(plate_run, tmp_path) -> None:
    out, summary = plate_run
    ev = summary["results"]["events"]["first_damage"]
    k = ev["step"]
    assert (out / ev["file"]).exists()
    before = run({**deck_with(), "solver": {"steps": k - 1}}, tmp_path / "a")
    at = run({**deck_with(), "solver": {"steps": k}}, tmp_path / "b")
    assert before["results"]["bonds_broken"] == 0 < at["results"]["bonds_broken"]
    frame = meshio.read(out / ev["file"])
    final = np.load(tmp_path / "b" / "final_state.npz")
    assert np.array_equal(frame.point_data["damage"], final["damage"].astype(np.float32))


def test_fracture_event_ignores_points_the_precrack_damaged(plate_run) -> None:
    ev = plate_run[1]["results"]["events"]
    assert ev["fracture"]["step"] > ev["first_damage"]["step"]


def test_peak_load_event_holds_the_largest_load(plate_run) -> None:
    out, summary = plate_run
    ev = summary["results"]["events"]["peak_load"]
    load = np.asarray(summary["results"]["probes"]["load"]["values"])
    assert ev["load"] == load[np.argmax(np.abs(load))]
    frame = meshio.read(out / "event_peak_load.vtu")
    assert frame.point_data["displacement"].dtype == np.float32


def test_several_figure_kinds_in_one_run(plate_run) -> None:
    out, summary = plate_run
    for kind in ("damage", "deformed", "probes", "energies"):
        assert (out / f"plate_{kind}.png").stat().st_size > 10_000
        assert f"plate_{kind}.png" in summary["files"]


def test_compact_frames_read_back_and_are_smaller(plate_run, tmp_path) -> None:
    out, _ = plate_run
    wide = run(deck_with(frame_precision="float64", frame_compression="none"), tmp_path)
    name = f"frame_{wide['results']['steps']:07d}.vtu"
    small, big = meshio.read(out / name), meshio.read(tmp_path / name)
    assert small.points.dtype == np.float32 and big.points.dtype == np.float64
    assert np.array_equal(small.point_data["damage"], big.point_data["damage"].astype(np.float32))
    np.testing.assert_allclose(
        small.point_data["displacement"], big.point_data["displacement"], rtol=1e-6, atol=1e-12
    )
    assert (out / name).stat().st_size < 0.5 * (tmp_path / name).stat().st_size


def test_three_d_damage_figure_shows_slices(tmp_path) -> None:
    from peridynamics.io.figures import slice_masks

    d = {
        "name": "cube",
        "geometry": {"type": "box", "size": [0.006, 0.005, 0.004]},
        "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
        "material": {"model": "pmb", "youngs_modulus": 65e9, "density": 2235.0},
        "solver": {"steps": 2},
        "output": {"plot": ["damage", "deformed"],
                   "slices": [{"axis": "z"}, {"axis": "x", "position": 0.0021}]},
    }  # fmt: skip
    summary = run(d, tmp_path)
    assert {"cube_damage.png", "cube_deformed.png"} <= set(summary["files"])
    x = np.load(tmp_path / "final_state.npz")["x"]
    spec = parse_deck(d).output.slices
    (_, _, mz), (_, _, mx) = slice_masks(x, 1e-3, list(spec))
    assert mz.sum() == 6 * 5 and np.ptp(x[mz, 2]) == 0  # one layer of the grid
    assert mx.sum() == 5 * 4 and np.allclose(x[mx, 0], 0.0025)  # the nearest layer


@pytest.mark.long
def test_stress_strain_from_first_contact_removes_the_travel_before_contact(tmp_path) -> None:
    gap, v = 2e-4, 2.0
    d = {
        "name": "block",
        "geometry": {"type": "rectangle", "size": [0.01, 0.01], "thickness": 0.01},
        "discretisation": {"spacing": 5e-4, "horizon_factor": 3.015},
        "material": {"model": "pmb", "youngs_modulus": 30e9, "density": 2500.0},
        "node_sets": {"base": {"edge": {"normal": [0.0, -1.0]}}},
        "boundary_conditions": [{"type": "fixed", "set": "base"}],
        "contact": {},
        "rigid_bodies": [
            {"name": "platen", "shape": {"box": {"min": [-0.002, 0.01 + gap],
                                                  "max": [0.012, 0.012 + gap]}},
             "velocity": [0.0, -v]},
        ],
        "solver": {"end_time": 3e-4},
        "output": {"history_every": 5, "stress_strain": {
            "body": "platen", "direction": [0.0, -1.0], "area": 1e-4, "length": 0.01,
            "zero_at": "first_contact"}},
    }  # fmt: skip
    r = run(d, tmp_path)["results"]
    offset = r["stress_strain"]["strain_offset"]
    # the top points sit half a spacing below the surface; the platen touches them
    # within a contact distance (at most one spacing) of closing that gap
    to_points = gap + 0.5 * 5e-4
    assert (to_points - 5e-4) / 0.01 <= offset <= to_points / 0.01
    assert offset > 0.01 * to_points / 0.01  # a travel was removed
    strain = np.asarray(r["stress_strain"]["strain"])
    stress = np.asarray(r["stress_strain"]["stress_Pa"])
    assert np.all(stress[strain <= 0] <= 0.01 * r["peak_stress_Pa"])
    assert r["strain_at_peak"] == pytest.approx(strain[np.argmax(stress)])


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"probes": [{"name": "d", "quantity": "difference", "of": ["a", "b"]}]},
         "output.probes.0.of"),
        ({"probes": [{"name": "d", "quantity": "difference", "of": ["a"]}]}, "output.probes.0"),
        ({"probes": [{"name": "d", "quantity": "displacement", "of": ["a", "b"]}]},
         "output.probes.0"),
        ({"probes": [{"name": "r", "quantity": "reaction_force", "body": "nope"}]},
         "output.probes.0.body"),
        ({"probes": [], "frames_on": ["peak_load"]}, "output.frames_on"),
        ({"slices": [{"axis": "z"}]}, "output.slices"),
        ({"plot": ["stress_strain"]}, "output.plot"),
        ({"load_probe": "nope"}, "output.load_probe"),
        ({"frames_on": ["sometime"]}, "output.frames_on"),
        ({"plot": "contour"}, "output.plot"),
    ],
)  # fmt: skip
def test_bad_output_keys_are_named(change: dict[str, Any], key: str) -> None:
    with pytest.raises(DeckError) as err:
        parse_deck(deck_with(**change))
    assert key in str(err.value), str(err.value)


def test_one_d_refuses_two_d_figures() -> None:
    bar = {
        "name": "bar",
        "geometry": {"type": "bar", "length": 0.1},
        "discretisation": {"spacing": 0.01, "horizon_factor": 3.0},
        "material": {"youngs_modulus": 1e9, "density": 1000.0},
        "solver": {"steps": 2},
    }
    for output, key in (({"png_frames": True}, "output.png_frames"),
                        ({"plot": ["deformed"]}, "output.plot")):  # fmt: skip
        with pytest.raises(DeckError) as err:
            parse_deck({**bar, "output": output})
        assert key in str(err.value)


def test_summary_lists_events_and_frames(plate_run) -> None:
    out, summary = plate_run
    saved = json.loads((out / "summary.json").read_text())
    assert set(saved["results"]["events"]) == {"first_damage", "fracture", "peak_load"}
    assert "frames" not in saved["results"]  # the .pvd lists them
