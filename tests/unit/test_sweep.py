"""`peridynamics sweep`: cases from grids and files, the layout and sweep.csv, failed
cases, resume, --jobs, bad input (exit 2) and MPI (mpiexec -n 2).

The sweep is called in this process (``cli.main``); its cases run as subprocesses of a
tiny 1-D bar (10 or 20 points, 20 steps).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from peridynamics.app.sweep import assign
from peridynamics.app.sweep_cases import Case, build_cases, split_values
from peridynamics.app.sweep_report import flatten_scalars
from peridynamics.cli import main
from tests.helpers import cli, mpiexec

DECK = """\
name: tiny_bar
geometry: {type: bar, length: 0.1, area: 1.0e-4}
discretisation: {spacing: 0.005, horizon_factor: 3.0}
material: {youngs_modulus: 20.0e9, density: 2620.0}
node_sets:
  left: {point: [0.0]}
boundary_conditions:
  - type: traction
    set: left
    value: [8.9e6]
    time_function: {type: triangular_pulse, peak: 1.0, rise_time: 4.0e-6, duration: 1.2e-5}
solver: {steps: 20}
output: {vtk_every: 100}
"""
GRID = [
    "--grid",
    "discretisation.spacing=0.005,1e-2",
    "--grid",
    "discretisation.horizon_factor=3,4",
]
#: columns that differ between two runs of the same case
TIMES = ("case", "folder", "status", "exit_code", "wall_s")


def read_csv(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


def same_results(a: dict[str, str], b: dict[str, str]) -> bool:
    keys = [k for k in a if k in b and k not in TIMES and not k.startswith("timing.")]
    return all(a[k] == b[k] for k in keys) and len(keys) > 10


@pytest.fixture(scope="module")
def grid_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A 2 x 2 grid (spacing x horizon factor) run with --jobs 2: (deck, output folder)."""
    root = tmp_path_factory.mktemp("sweep")
    deck = root / "deck.yaml"
    deck.write_text(DECK)
    out = root / "grid"
    assert main(["sweep", str(deck), *GRID, "--jobs", "2", "--out", str(out), "--quiet"]) == 0
    return deck, out


def test_grid_product_layout_and_values(grid_run: tuple[Path, Path]) -> None:
    _, out = grid_run
    rows = read_csv(out / "sweep.csv")
    folders = sorted(p.name for p in out.iterdir() if p.is_dir())
    assert folders == sorted(r["folder"] for r in rows)
    assert "case_horizon_factor=3_spacing=0.005" in folders and len(folders) == 4
    seen = set()
    for row in rows:
        assert row["status"] == "completed" and row["exit_code"] == "0"
        spacing = float(row["discretisation.spacing"])
        factor = float(row["discretisation.horizon_factor"])
        seen.add((spacing, factor))
        # the override took effect in the run: points, horizon, the deck it ran
        assert int(row["n_points"]) == round(0.1 / spacing)
        assert float(row["horizon_m"]) == pytest.approx(factor * spacing)
        summary = json.loads((out / row["folder"] / "summary.json").read_text())
        assert summary["inputs"]["discretisation"]["spacing"] == spacing
        assert summary["results"]["n_points"] == int(row["n_points"])
        assert float(row["wall_s"]) > 0 and "max_damage" in row
        assert (out / row["folder"] / "run.log").is_file()
    assert seen == {(0.005, 3.0), (0.005, 4.0), (0.01, 3.0), (0.01, 4.0)}
    info = json.loads((out / "sweep.json").read_text())
    assert info["keys"] == ["discretisation.spacing", "discretisation.horizon_factor"]
    assert [c["case"] for c in info["cases"]] == [0, 1, 2, 3]
    assert info["counts"] == {"completed": 4} and info["finished"]
    assert (out / "sweep.png").stat().st_size > 1000


def test_rerun_skips_done_cases(grid_run: tuple[Path, Path], capsys: pytest.CaptureFixture) -> None:
    deck, out = grid_run
    before = {p: p.stat().st_mtime_ns for p in out.glob("*/summary.json")}
    assert main(["sweep", str(deck), *GRID, "--out", str(out)]) == 0
    assert "done before" in capsys.readouterr().out
    assert {p: p.stat().st_mtime_ns for p in out.glob("*/summary.json")} == before
    rows = read_csv(out / "sweep.csv")
    assert [r["status"] for r in rows] == ["skipped-done"] * 4
    assert all(float(r["wall_s"]) > 0 and r["n_points"] for r in rows)


@pytest.mark.long
def test_failed_cases_are_recorded_and_jobs_1_matches_jobs_2(
    grid_run: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    """A csv of cases: one as in the grid, one unstable, one refused at run time."""
    deck, grid = grid_run
    cases = tmp_path / "cases.csv"
    cases.write_text(
        "discretisation.spacing,discretisation.horizon_factor,boundary_conditions.0.value,"
        'solver.time_step\n0.01,3,,\n0.01,3,"[1e16]",\n0.01,3,,1e-3\n'
    )
    out = tmp_path / "cases"
    code = main(["sweep", str(deck), "--cases", str(cases), "--out", str(out), "--quiet"])
    assert code == 4
    assert "2 of 3 case(s) did not complete (1 failed, 1 unstable)" in capsys.readouterr().err
    rows = read_csv(out / "sweep.csv")
    assert [r["status"] for r in rows] == ["completed", "unstable", "failed"]
    assert [r["exit_code"] for r in rows] == ["0", "3", "2"]
    assert rows[0]["folder"] == "case_horizon_factor=3_spacing=0.01"  # as in the grid
    same = next(r for r in read_csv(grid / "sweep.csv") if r["folder"] == rows[0]["folder"])
    assert same_results(rows[0], same)  # --jobs 1 and --jobs 2 give the same values
    failed = json.loads((out / "sweep.json").read_text())["cases"][2]
    assert any("time_step" in line for line in failed["stderr_tail"])


@pytest.mark.long
def test_interrupted_case_resumes_from_checkpoint(
    grid_run: tuple[Path, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    deck, grid = grid_run
    args = ["sweep", str(deck), "--grid", "discretisation.spacing=0.01", "--grid",
            "discretisation.horizon_factor=3", "--out", str(tmp_path), "--quiet"]  # fmt: skip
    monkeypatch.setenv("PERIDYNAMICS_CRASH_AT_STEP", "12")  # a power cut after step 12
    assert main([*args, "--checkpoint-every", "5"]) == 4
    (row,) = read_csv(tmp_path / "sweep.csv")
    assert (row["status"], row["exit_code"]) == ("failed", "137")
    assert (tmp_path / row["folder"] / "checkpoint.npz").is_file()
    monkeypatch.delenv("PERIDYNAMICS_CRASH_AT_STEP")
    assert main(args) == 0
    (row,) = read_csv(tmp_path / "sweep.csv")
    assert row["status"] == "completed"
    assert json.loads((tmp_path / "sweep.json").read_text())["cases"][0]["resumed"]
    assert "--resume" in (tmp_path / row["folder"] / "run.log").read_text()
    same = next(r for r in read_csv(grid / "sweep.csv") if r["folder"] == row["folder"])
    assert same_results(row, same)  # bitwise the uninterrupted run's results


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--grid", "discretisation.spacing"], "--grid 'discretisation.spacing': write KEY"),
        (["--grid", "discretisation.spasing=1e-3"], "discretisation.spasing: unknown key"),
        (["--grid", "discretisation.spacing=1e-3,,2e-3"], "an empty value"),
        (["--grid", "discretisation.spacing=[1"], "is not valid YAML"),
        (["--grid", "discretisation.spacing=-1,0.01"], "1 of 2 case(s) invalid"),
        (["--grid", "solver.steps=1,1"], "a value is given twice"),
        (["--grid", "solver.steps=5", "--set", "solver.steps=4"], "--set solver.steps"),
        (["--grid", "discretisation.spacing=1e-9"], "the model is too large"),
        (["--grid", "solver.steps=5", "--jobs", "0"], "--jobs must be >= 1"),
        ([], "give the values to sweep"),
        (["--cases", "cases.yaml"], "--cases cases.yaml: a YAML list of mappings"),
        (["--cases", "missing.csv"], "cannot read the file"),
    ],
)
def test_bad_input_exits_2_naming_the_option(
    args: list[str], message: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture,
) -> None:  # fmt: skip
    monkeypatch.chdir(tmp_path)
    Path("deck.yaml").write_text(DECK)
    Path("cases.yaml").write_text("discretisation.spacing: 0.01\n")
    assert main(["sweep", "deck.yaml", *args, "--out", "out"]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not Path("out").exists()  # nothing was run


def test_values_names_and_assignment() -> None:
    assert split_values("[1e6, 2],3,'a,b',{x: 1}") == ["[1e6, 2]", "3", "'a,b'", "{x: 1}"]
    cases, keys = build_cases(
        ["discretisation.spacing=1e-3,0.5e-3", "geometry.size.0=0.1"], None, []
    )
    assert keys == ["discretisation.spacing", "geometry.size.0"]
    assert [c.values["discretisation.spacing"] for c in cases] == [0.001, 0.0005]
    assert cases[1].folder == "case_spacing=0.0005_size.0=0.1"
    equal = assign([Case(n, ()) for n in range(5)], 2)
    assert [[c.index for c in r] for r in equal] == [[0, 2, 4], [1, 3]]
    costly = [Case(n, (), cost=c) for n, c in enumerate([1.0, 8.0, 1.0, 1.0])]
    assert [[c.index for c in r] for r in assign(costly, 2)] == [[1], [0, 2, 3]]
    flat = flatten_scalars({"a": 1, "b": {"c": 2.5, "d": [1]}, "e": None, "f": True, "g": "x"})
    assert flat == {"a": 1, "b.c": 2.5, "e": None, "f": 1}


@pytest.mark.mpi
@pytest.mark.skipif(mpiexec()[0] is None, reason=mpiexec()[1])
def test_mpi_spreads_cases_over_ranks(grid_run: tuple[Path, Path], tmp_path: Path) -> None:
    deck, grid = grid_run
    proc = cli(
        "sweep", str(deck), "--grid", "discretisation.spacing=0.005,0.01", "--grid",
        "discretisation.horizon_factor=3", "--out", str(tmp_path), "--quiet",
        timeout=120, ranks=2,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    rows = read_csv(tmp_path / "sweep.csv")
    assert [r["status"] for r in rows] == ["completed", "completed"]
    assert [int(r["n_points"]) for r in rows] == [20, 10]
    info = json.loads((tmp_path / "sweep.json").read_text())
    assert info["mpi_ranks"] == 2 and {c["rank"] for c in info["cases"]} == {0, 1}
    ref = {r["folder"]: r for r in read_csv(grid / "sweep.csv")}
    assert all(same_results(r, ref[r["folder"]]) for r in rows)
