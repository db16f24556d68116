"""``mpiexec -n 2 python script.py``: a script's Simulation decomposes over the ranks as
``peridynamics run`` does, gives the serial fields bit for bit, runs callbacks on rank 0
with the whole body in view and returns the result on every rank."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from peridynamics.io.final_state import read_final_state
from tests.helpers import mpiexec, subprocess_env

MPIEXEC, WHY = mpiexec()
pytestmark = [pytest.mark.mpi, pytest.mark.skipif(MPIEXEC is None, reason=WHY)]

SCRIPT = """
import json, sys
import peridynamics as pd

overrides = {"discretisation.spacing": 1.0e-3, "discretisation.horizon": 4.0e-3,
             "solver.end_time": 2.0e-5, "output.plot": "none"}
seen = []
sim = pd.Simulation(pd.Deck.example("crack_branching_2d"), overrides, out=sys.argv[1],
                    callbacks=[lambda s: seen.append(len(s.u))])
result = sim.run()
from mpi4py import MPI
rank = MPI.COMM_WORLD.Get_rank()
with open(sys.argv[1] + f"_rank{rank}.json", "w") as fh:
    json.dump({"steps": result.results["steps"], "seen": seen[:1], "n": sim.n_points}, fh)
"""


def _script(tmp_path: Path, out: Path, ranks: int) -> None:
    path = tmp_path / "script.py"
    path.write_text(SCRIPT)
    cmd = [sys.executable, str(path), str(out)]
    if ranks > 1:
        cmd = [str(MPIEXEC), "-n", str(ranks), *cmd]
    got = subprocess.run(cmd, env=subprocess_env({"NUMBA_NUM_THREADS": "1"}),
                         capture_output=True, text=True, timeout=300)  # fmt: skip
    assert got.returncode == 0, got.stderr[-3000:]


def test_a_script_under_mpiexec_gives_the_serial_fields(tmp_path):
    _script(tmp_path, tmp_path / "serial", 1)
    _script(tmp_path, tmp_path / "mpi", 2)
    a, b = read_final_state(tmp_path / "serial"), read_final_state(tmp_path / "mpi")
    for key in ("u", "v", "damage", "intact", "x"):
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    ranks = [json.loads((tmp_path / f"mpi_rank{r}.json").read_text()) for r in (0, 1)]
    assert ranks[0]["steps"] == ranks[1]["steps"] > 0  # every rank returns the result
    assert ranks[0]["seen"] == [ranks[0]["n"]]  # the callback saw the whole body on rank 0
    assert ranks[1]["seen"] == []  # and ran on rank 0 only
