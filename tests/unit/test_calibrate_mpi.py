"""``mpiexec -n 2 peridynamics calibrate``: rank 0 runs the optimiser, each batch of runs
is divided among the ranks (docs/calibration.md "Running in parallel"). The 2-rank
calibration makes the same runs and fits the same parameters as one process, bit for
bit, with runs on both ranks; interrupted (Ctrl-C to mpiexec: every rank stops, exit
130) it resumes on 2 ranks reading its finished runs back, to the same parameters, and a
third start on one process makes no run at all (resuming on another rank count); bad
input stops every rank with exit 2 and one message. All in the ``mpi`` tier
(``pytest -m mpi``): about 2 min on 2 shared cores."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.helpers import EXAMPLES, cli, mpiexec, subprocess_env

MPIEXEC, WHY = mpiexec()
pytestmark = [pytest.mark.mpi, pytest.mark.skipif(MPIEXEC is None, reason=WHY)]

#: E and nu of the example's LPS plate (examples/calibration/plate.yaml) against
#: hand-written curves near E = 70 GPa, nu = 0.3; max_runs 6 (+ the final Jacobian's 2)
#: keeps it to 8 runs of about 3 s: batches of 1 and 2 runs
CAL = """\
parameters:
  - {key: material.youngs_modulus, bounds: [20.0e9, 200.0e9], scale: log, name: E}
  - {key: material.poisson_ratio, bounds: [0.05, 0.45], name: nu}
targets:
  - name: axial
    simulated: {x: time, y: right_ux}
    measured: {file: data.csv, x: load, y: ux, y_factor: 1.0e-3}
  - name: lateral
    simulated: {x: time, y: top_uy}
    measured: {file: data.csv, x: load, y: uy, y_factor: 1.0e-3}
options: {method: least_squares, jobs: 1, max_runs: 6}
"""
DATA = """\
load,ux,uy
0.25,0.000716,-0.0001070
0.5,0.001425,-0.0002150
0.75,0.002150,-0.0003210
1.0,0.002851,-0.0004300
"""
DECK = EXAMPLES / "calibration" / "plate.yaml"
ENV = {"NUMBA_NUM_THREADS": "1"}  # the runs' results must not depend on thread counts


def _files(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "data.csv").write_text(DATA)
    (folder / "cal.yml").write_text(CAL)
    return folder / "cal.yml"


def _args(cal: Path, out: Path) -> list[str]:
    return ["calibrate", str(DECK), str(cal), "--out", str(out), "--quiet"]


def _report(out: Path) -> dict:
    return json.loads((out / "report.json").read_text())


@pytest.fixture(scope="module")
def one_process(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The calibration on one process (no MPI): its folder."""
    tmp = tmp_path_factory.mktemp("one")
    out = tmp / "cal"
    proc = cli(*_args(_files(tmp), out), env=ENV, process=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return out


def test_two_ranks_make_the_runs_and_the_fit_of_one_process(one_process, tmp_path):
    out = tmp_path / "cal"
    proc = cli(*_args(_files(tmp_path), out), env=ENV, ranks=2, timeout=300)
    assert proc.returncode == 0, proc.stderr
    one, two = _report(one_process), _report(out)
    assert two["parameters"] == one["parameters"]  # bit for bit (floats from JSON)
    assert two["misfit"] == one["misfit"]
    assert two["optimiser"]["starts"] == one["optimiser"]["starts"]
    # the same points in the same order, the same costs and folders
    assert (out / "runs.csv").read_text() == (one_process / "runs.csv").read_text()
    assert sorted(p.name for p in (out / "runs").iterdir()) == sorted(
        p.name for p in (one_process / "runs").iterdir()
    )
    runs = two["runs"]
    assert runs["mpi_ranks"] == 2 and one["runs"]["mpi_ranks"] == 1
    assert runs["runs"] == one["runs"]["runs"] == sum(runs["runs_by_rank"])
    assert min(runs["runs_by_rank"]) >= 1, runs  # rank 1 ran its share


def _completed(out: Path) -> int:
    return sum(1 for p in (out / "runs").glob("*/summary.json")
               if '"completed"' in p.read_text())  # fmt: skip


def test_interrupted_two_rank_calibration_resumes(one_process, tmp_path):
    cal = _files(tmp_path)
    out = tmp_path / "cal"
    cmd = [str(MPIEXEC), "-n", "2", sys.executable, "-m", "peridynamics", *_args(cal, out)]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True, env=subprocess_env(ENV))  # fmt: skip
    try:
        deadline = time.monotonic() + 240
        while (out / "runs").is_dir() is False or _completed(out) < 3:
            assert proc.poll() is None and time.monotonic() < deadline, "no runs"
            time.sleep(0.2)
        proc.send_signal(signal.SIGINT)  # as Ctrl-C: mpiexec passes it to every rank
        _, stderr = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, stderr
    assert "interrupted" in stderr and not (out / "report.json").exists()
    done = _completed(out)
    again = cli(*_args(cal, out), env=ENV, ranks=2, timeout=300)
    assert again.returncode == 0, again.stderr
    resumed = _report(out)
    assert resumed["parameters"] == _report(one_process)["parameters"]
    assert resumed["runs"]["runs_read_back"] >= done >= 3
    total = _report(one_process)["runs"]["runs"]
    assert resumed["runs"]["runs"] + resumed["runs"]["runs_read_back"] == total
    # on another rank count (one process): every run read back, none made
    third = cli(*_args(cal, out), env=ENV, process=True, timeout=300)
    assert third.returncode == 0, third.stderr
    final = _report(out)
    assert final["runs"]["runs"] == 0 and final["runs"]["runs_read_back"] == total
    assert final["parameters"] == resumed["parameters"]


def test_bad_input_on_two_ranks_exits_2_once(tmp_path):
    """Rank 0 validates; the other ranks end with its exit code, nothing is run."""
    cal = _files(tmp_path)
    out = tmp_path / "cal"
    proc = cli(*_args(cal, out), "--restarts", "-1", env=ENV, ranks=2, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("options.restarts") == 1 and not out.exists()
