"""The windowed set-up of a decomposed run (:mod:`peridynamics.build.windowed`): on 3
ranks, without any rank making the whole cloud, the owned points are the serial cloud's
rows bit for bit and split it, the node sets (an edge layer, a nearest point, boxes,
references, complements) hold the serial members, and the boundary conditions (a
traction on a layer, a velocity, a fixed set) give every owned point the serial run's
values, for a regular and a jittered grid; an empty node set is the serial error on every
rank; a jittered run on 3 ranks is the serial run bit for bit. ``mpi`` tier."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import fields
from pathlib import Path

import numpy as np
import pytest
import yaml

from peridynamics.build.cloud import build_cloud
from peridynamics.build.loads import build_conditions
from peridynamics.deck.reader import load_deck
from tests.helpers import mpiexec, subprocess_env

MPIEXEC, WHY = mpiexec()
pytestmark = [pytest.mark.skipif(MPIEXEC is None, reason=WHY), pytest.mark.mpi]

DECK = {
    "name": "windowed",
    "geometry": {"type": "rectangle", "size": [0.03, 0.0205], "thickness": 1e-3,
                 "holes": [{"circle": {"center": [0.012, 0.01], "radius": 0.003}}]},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
    "material": {"model": "lps", "youngs_modulus": 70e9, "density": 2700.0, "poisson_ratio": 0.3},
    "notches": [{"start": [0.025, 0.0], "end": [0.025, 0.006], "width": 1.1e-3}],
    "node_sets": {
        "top": {"edge": {"normal": [0.0, 1.0], "layers": 2}},
        "left": {"edge": {"normal": [-1.0, 0.0]}},
        "gauge": {"point": [0.0201, 0.0151]},
        "corner": {"all_of": [{"set": "top"},
                              {"not": {"box": {"min": [0.005, -1], "max": [1, 1]}}}]},
    },
    "boundary_conditions": [
        {"type": "traction", "set": "top", "value": [0.0, 2.0e6]},
        {"type": "fixed", "set": "left"},
        {"type": "velocity", "set": "gauge", "components": {"x": 1.0}},
    ],
    "solver": {"type": "explicit", "steps": 2},
    "output": {"plot": "none"},
}  # fmt: skip

SCRIPT = """
import sys, pickle
from dataclasses import fields
import numpy as np
from mpi4py import MPI
from peridynamics.deck.reader import load_deck
import peridynamics.build.decomposed as decomposed
seen = {}
built_here = decomposed.conditions
def conditions(*args):
    seen["conds"] = built_here(*args)
    return seen["conds"]
decomposed.conditions = conditions
import peridynamics.geometry.jitter as jitter
jitter.BLOCK_POINTS = int(sys.argv[3])
deck = load_deck(sys.argv[1])
comm = MPI.COMM_WORLD
try:
    parts = decomposed.build_distributed(deck, comm)
except Exception as exc:
    pickle.dump({"error": str(exc)}, open(f"{sys.argv[2]}/rank{comm.rank}.pkl", "wb"))
    sys.exit(0)
cloud, n = parts["cloud"], parts["communicator"].n_owned
gid = np.asarray(cloud.global_ids)
sets = {k: gid[v[v < n]] for k, v in cloud.node_sets.items()}
body, kin, _ = seen["conds"]
conds = []
for c in [*body, *kin]:
    conds.append((type(c).__name__, {f.name: getattr(c, f.name) for f in fields(c)}, gid))
out = {"ids": gid[:n], "x": cloud.x[:n], "volume": cloud.volume[:n], "sets": sets,
       "conds": conds, "how": parts["set_up"]["how"], "n_global": parts["global_cloud"].n_points,
       "size": cloud.size}
pickle.dump(out, open(f"{sys.argv[2]}/rank{comm.rank}.pkl", "wb"))
"""


def _ranks(tmp_path: Path, deck: dict, ranks: int = 3, block: int = 1 << 17) -> list[dict]:
    import pickle

    (tmp_path / "deck.yaml").write_text(yaml.safe_dump(deck))
    (tmp_path / "dump.py").write_text(SCRIPT)
    cmd = [str(MPIEXEC), "-n", str(ranks), sys.executable, str(tmp_path / "dump.py"),
           str(tmp_path / "deck.yaml"), str(tmp_path), str(block)]  # fmt: skip
    done = subprocess.run(cmd, env=subprocess_env({"NUMBA_NUM_THREADS": "1"}),
                          capture_output=True, text=True, timeout=240)  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    return [pickle.load(open(tmp_path / f"rank{r}.pkl", "rb")) for r in range(ranks)]


@pytest.mark.parametrize("jitter", [0.0, 0.3], ids=["grid", "jittered"])
def test_three_ranks_make_the_serial_points_sets_and_loads(
    tmp_path: Path, jitter: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Also for a jittered grid: positions, Voronoi volumes (blocks of 4 slabs, fewer
    than a rank's share, so blocks are shared between ranks) and the traction of a
    jittered layer."""
    import peridynamics.geometry.jitter as jit

    d = {**DECK, "discretisation": {**DECK["discretisation"], "jitter": jitter, "seed": 4}}
    monkeypatch.setattr(jit, "BLOCK_POINTS", 64)
    got = _ranks(tmp_path, d, block=64)
    deck = load_deck(tmp_path / "deck.yaml")
    serial = build_cloud(deck)
    body, kin, _ = build_conditions(deck, serial)
    assert {g["how"] for g in got} == {"windowed"}
    assert {g["n_global"] for g in got} == {serial.n_points}
    assert {g["size"] for g in got} == {serial.size}  # blow-up checks: the body's size
    ids = np.concatenate([g["ids"] for g in got])
    np.testing.assert_array_equal(np.sort(ids), np.arange(serial.n_points))  # a split
    for g in got:
        np.testing.assert_array_equal(g["x"], serial.x[g["ids"]])
        np.testing.assert_array_equal(g["volume"], serial.volume[g["ids"]])
    for name, members in serial.node_sets.items():
        joined = np.sort(np.concatenate([g["sets"][name] for g in got]))
        np.testing.assert_array_equal(joined, members, err_msg=name)
    # every condition: the serial values of its owned nodes
    for k, ref in enumerate([*body, *kin]):
        ref_f = {f.name: getattr(ref, f.name) for f in fields(ref)}
        rows: dict[int, dict] = {}
        for g in got:
            name, f, gid = g["conds"][k]
            assert name == type(ref).__name__
            value = np.asarray(f.get("value", 0.0))
            for r, node in enumerate(gid[f["nodes"]]):
                rows[int(node)] = value[r] if value.ndim == 2 else value
        assert sorted(rows) == sorted(ref_f["nodes"].tolist())
        ref_value = np.asarray(ref_f.get("value", 0.0))
        for r, node in enumerate(ref_f["nodes"]):
            want = ref_value[r] if ref_value.ndim == 2 else ref_value
            np.testing.assert_array_equal(rows[int(node)], want)


def test_an_empty_set_is_the_serial_error_on_every_rank(tmp_path: Path) -> None:
    deck = {
        **DECK,
        "node_sets": {**DECK["node_sets"], "nowhere": {"box": {"min": [1, 1], "max": [2, 2]}}},
    }
    got = _ranks(tmp_path, deck, ranks=2)
    assert len({g["error"] for g in got}) == 1
    assert got[0]["error"].startswith("node_sets.nowhere: selects no point")


def test_a_jittered_run_on_three_ranks_is_the_serial_run(tmp_path: Path) -> None:
    """The main job's deck jittered (0.3 dx): set up windowed, the run gives the serial
    fields and broken bonds bit for bit."""
    import json

    from peridynamics.io.final_state import read_final_state
    from tests.helpers import EXAMPLES, cli

    args = [str(EXAMPLES / "crack_branching_2d" / "deck.yaml"),
            "--set", "discretisation.spacing=5e-4", "--set", "solver.end_time=16e-6",
            "--set", "output.plot=none", "--set", "discretisation.jitter=0.3",
            "--quiet"]  # fmt: skip
    env = {"NUMBA_NUM_THREADS": "1"}
    assert cli("run", *args, "--out", str(tmp_path / "s"), env=env, timeout=240).returncode == 0
    got = cli("run", *args, "--out", str(tmp_path / "m"), env=env, timeout=240, ranks=3)
    assert got.returncode == 0, got.stderr
    assert "cuts no bond" not in got.stderr  # a rank without the pre-crack is not idle
    fs, fm = read_final_state(tmp_path / "s"), read_final_state(tmp_path / "m")
    for k in ("u", "v", "damage", "x", "intact"):
        np.testing.assert_array_equal(fm[k], fs[k], err_msg=k)
    rs = json.loads((tmp_path / "s" / "summary.json").read_text())
    rm = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert rm["timing"]["set_up"]["how"] == "windowed"
    assert rm["results"]["bonds_broken"] == rs["results"]["bonds_broken"] > 0
