"""``mpiexec -n 2 peridynamics ensemble``: the realisations spread over the ranks are the
runs of a serial ensemble (the seed, not the rank, determines a realisation), and a
problem on the ranks gives one report and one exit code."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest

from peridynamics.app.ensemble import assign
from tests.helpers import EXAMPLES, cli, mpiexec

DECK = EXAMPLES / "rock_compression" / "flaw30_m2.yaml"
# 20 x 40 points (dx = 2.5 mm, 5 x the paper's), the paper's duration: about 1 s a run
SMALL = [
    "--set", "discretisation.spacing=0.0025",
    "--set", "solver.time_step=1.4e-6",
    "--set", "solver.steps=300",
    "--set", "output.plot=none",
]  # fmt: skip
ENV = {"NUMBA_NUM_THREADS": "1"}


MPIEXEC, WHY = mpiexec()
needs_mpi = pytest.mark.skipif(MPIEXEC is None, reason=WHY)


def _ensemble(*args: str, ranks: int = 2) -> subprocess.CompletedProcess:
    """``[mpiexec -n RANKS] python -m peridynamics ensemble ARGS`` on the source tree."""
    return cli("ensemble", *args, env=ENV, timeout=120, ranks=ranks)


def test_round_robin() -> None:
    assert [assign(5, 2, r) for r in range(2)] == [[0, 2, 4], [1, 3]]
    assert [assign(2, 3, r) for r in range(3)] == [[0], [1], []]
    assert assign(3, 1, 0) == [0, 1, 2]


@pytest.mark.mpi
@needs_mpi
def test_mpi_ensemble_matches_serial(tmp_path: Path) -> None:
    par, ser = tmp_path / "mpi", tmp_path / "serial"
    proc = _ensemble(str(DECK), "--n", "3", "--seed0", "4", "--out", str(par), *SMALL)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "3 realisation(s) over 2 MPI ranks" in proc.stdout
    for rank, seed in ((0, 4), (1, 5), (0, 6)):  # realisation k on rank k % 2
        assert f"rank {rank}: seed {seed}: peak stress" in proc.stdout
    assert proc.stdout.count("wrote ") == 1  # rank 0 reports
    serial = _ensemble(str(DECK), "--n", "3", "--seed0", "4", "--out", str(ser), "--quiet",
                       *SMALL, ranks=1)  # fmt: skip
    assert serial.returncode == 0, serial.stderr
    rep = json.loads((par / "ensemble.json").read_text())
    ref = json.loads((ser / "ensemble.json").read_text())
    assert rep["ranks"] == 2 and "ranks" not in ref
    assert rep["n"] == 3 and rep["seeds"] == ref["seeds"] == [4, 5, 6]
    for key in ("peak_stress_Pa", "damaged_area_fraction"):
        # the same runs: equal numbers, not merely close ones
        assert [r[key] for r in rep["runs"]] == [r[key] for r in ref["runs"]]
        assert rep[key] == ref[key]
    assert all((par / f"seed_{s}" / "summary.json").is_file() for s in (4, 5, 6))


@pytest.mark.mpi
@needs_mpi
def test_mpi_ensemble_problem_one_report(tmp_path: Path) -> None:
    # every member goes unstable within 10 steps: both ranks stop, rank 0 reports the
    # first seed's problem once, and every rank exits 3 (so does mpiexec)
    bad = ["--set", "solver.time_step=1e-5", "--set", "solver.allow_unstable=true"]
    proc = _ensemble(str(DECK), "--n", "3", "--out", str(tmp_path), "--quiet", *SMALL, *bad)
    assert proc.returncode == 3, proc.stdout + proc.stderr
    assert proc.stderr.count("went unstable") == 1 and "error (seed 0)" in proc.stderr
    assert not (tmp_path / "ensemble.json").exists()
    proc = _ensemble(str(DECK), "--n", "0")
    assert proc.returncode == 2 and proc.stderr.count("--n must be >= 1") == 1
