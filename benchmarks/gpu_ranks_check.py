"""Warp under ``mpiexec``: N ranks on the machine's CUDA devices against one process.

    python benchmarks/gpu_ranks_check.py --ranks 2 [--deck DECK] [--set KEY=VALUE ...]

Runs the deck (default: the main job, ``examples/crack_branching_2d/deck.yaml``) with
``solver.backend: warp`` once in one process and once under ``mpiexec -n N`` (rank r
drives CUDA device r mod k, so with one GPU every rank shares it), then compares the
final fields (u, v, damage, bond flags) bit for bit and prints the devices per rank, the
bonds broken and the wall times as JSON (``--out``). On a machine without a CUDA
device Warp's CPU device is used (``--device cpu``): that is what
``tests/unit/test_warp_mpi.py`` checks in the ``mpi`` tier.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def _run(deck: Path, out: Path, ranks: int, sets: list[str], device: str) -> float:
    """Wall seconds of one ``peridynamics run`` (``mpiexec -n ranks`` when ranks > 1)."""
    cmd = [sys.executable, "-m", "peridynamics", "run", str(deck), "--out", str(out),
           "--quiet", "--backend", "warp", "--set", f"solver.device={device}",
           "--set", "output.plot=none"]  # fmt: skip
    for s in sets:
        cmd += ["--set", s]
    if ranks > 1:
        mpiexec = shutil.which("mpiexec")
        if mpiexec is None:
            raise SystemExit("mpiexec not found: pip install '.[mpi]'")
        cmd = [mpiexec, "-n", str(ranks), *cmd]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    t0 = time.perf_counter()
    got = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    if got.returncode != 0:
        raise SystemExit(f"run failed ({' '.join(cmd)}):\n{got.stderr[-4000:]}")
    return time.perf_counter() - t0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--ranks", type=int, default=2)
    p.add_argument("--deck", default=str(ROOT / "examples/crack_branching_2d/deck.yaml"))
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    p.add_argument("--device", default="auto", choices=["auto", "cuda", "cpu"])
    p.add_argument("--out", default="gpu_ranks_check.json")
    a = p.parse_args(argv)
    from peridynamics.io.final_state import read_final_state

    with tempfile.TemporaryDirectory() as tmp:
        one, many = Path(tmp) / "one", Path(tmp) / "many"
        t1 = _run(Path(a.deck), one, 1, a.set, a.device)
        tn = _run(Path(a.deck), many, a.ranks, a.set, a.device)
        f1, fn = read_final_state(one), read_final_state(many)
        r1 = json.loads((one / "summary.json").read_text())["results"]
        rn = json.loads((many / "summary.json").read_text())["results"]
    res = {"deck": a.deck, "sets": a.set, "ranks": a.ranks,
           "devices_one": r1.get("devices_per_rank"), "devices_ranks": rn.get("devices_per_rank"),
           "bonds_broken_one": r1.get("bonds_broken"), "bonds_broken_ranks": rn.get("bonds_broken"),
           "wall_one_s": t1, "wall_ranks_s": tn}  # fmt: skip
    for k in ("u", "v", "damage", "intact"):
        x, y = np.asarray(f1[k]), np.asarray(fn[k])
        res[f"{k}_identical"] = bool(x.shape == y.shape and np.array_equal(x, y))
        if x.shape == y.shape and x.dtype.kind == "f":
            res[f"{k}_max_abs_difference"] = float(np.max(np.abs(x - y), initial=0.0))
    Path(a.out).write_text(json.dumps(res, indent=1))
    print(json.dumps(res, indent=1))
    return 0 if all(res[f"{k}_identical"] for k in ("u", "v", "damage", "intact")) else 1


if __name__ == "__main__":
    raise SystemExit(main())
