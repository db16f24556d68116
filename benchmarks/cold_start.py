"""Cold and warm start of a run: how much of it is Numba compiling kernels.

``python benchmarks/cold_start.py [--python PY] [--deck DECK] [--runs N] [--set K=V ...]``
runs ``peridynamics run DECK`` ``N`` times (default 2) in fresh processes of the
interpreter ``PY`` (default this one; point it at a brand-new venv's ``bin/python`` to
time an installed copy) against one new, empty Numba cache directory (given through
``PERIDYNAMICS_CACHE_DIR`` and ``NUMBA_CACHE_DIR``, so it also works for versions
before the package chose its own cache directory): the first run is cold (every kernel
it calls is compiled and saved), the later ones warm (loaded from the cache). Per run it
prints the wall and CPU (user + sys) seconds, the seconds spent in Numba compiles
(top-level compiles only, nested ones counted once) and the kernels compiled and loaded.
``--cache-dir DIR`` uses (and keeps) DIR instead; ``--json`` prints JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import cpu_model  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DECK = ROOT / "examples" / "crack_branching_2d" / "deck.yaml"

#: runs in the child: the command with a listener on Numba's compile events
CHILD = r"""
import json, sys, time
import peridynamics  # sets the cache directory (when this version does) before numba
from numba.core import event

compiles, depth, start = [], [0], [0.0, 0.0]

class Listener(event.Listener):
    def on_start(self, ev):
        if depth[0] == 0:
            start[:] = [time.perf_counter(), time.process_time()]
        depth[0] += 1

    def on_end(self, ev):
        depth[0] -= 1
        if depth[0] == 0:
            fn = ev.data["dispatcher"].py_func
            compiles.append([f"{fn.__module__}.{fn.__qualname__}",
                             time.perf_counter() - start[0],
                             time.process_time() - start[1]])

event.register("numba:compile", Listener())
from peridynamics.cli import main
code = main(sys.argv[2:])

from numba.core.registry import CPUDispatcher
loaded = sorted(
    f"{m}.{name}" for m, mod in list(sys.modules.items()) if m.startswith("peridynamics.")
    for name, obj in list(vars(mod).items())
    if isinstance(obj, CPUDispatcher) and obj.overloads and obj.__module__ == m
)
kernel_modules = sorted(m for m in sys.modules if m.startswith("peridynamics.kernels."))
with open(sys.argv[1], "w") as f:
    json.dump({"code": code, "compiles": compiles, "used": loaded,
               "kernel_modules": kernel_modules}, f)
"""


def one_run(python: str, deck: Path, out: Path, cache: Path, sets: list[str]) -> dict:
    """One ``peridynamics run`` in a fresh process; its timings and kernels."""
    env = dict(os.environ, PERIDYNAMICS_CACHE_DIR=str(cache), NUMBA_CACHE_DIR=str(cache))
    report = out / "cold_start_child.json"
    argv = ["run", str(deck), "--out", str(out), "--quiet"]
    for s in sets:
        argv += ["--set", s]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([python, "-c", CHILD, str(report), *argv], env=env, check=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    child = json.loads(report.read_text())
    return {
        "wall_s": wall,
        "cpu_s": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime),
        "compile_wall_s": sum(c[1] for c in child["compiles"]),
        "compile_cpu_s": sum(c[2] for c in child["compiles"]),
        "compiled": [c[0] for c in child["compiles"]],
        "used": child["used"],
        "kernel_modules": child["kernel_modules"],
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--python", default=sys.executable)
    p.add_argument("--deck", type=Path, default=DECK)
    p.add_argument("--runs", type=int, default=2)
    p.add_argument("--cache-dir", type=Path)
    p.add_argument("--set", action="append", default=[], dest="sets")
    p.add_argument("--json", action="store_true")
    a = p.parse_args()
    with tempfile.TemporaryDirectory(prefix="pd-cold-") as tmp:
        cache = a.cache_dir or Path(tmp) / "cache"
        runs = []
        for i in range(a.runs):
            out = Path(tmp) / f"run{i}"
            out.mkdir()
            runs.append(one_run(a.python, a.deck.resolve(), out, cache, a.sets))
    result = {"machine": cpu_model(), "cores": os.cpu_count(), "runs": runs}
    if a.json:
        print(json.dumps(result, indent=1))
        return
    print(f"{result['machine']}, {result['cores']} cores; {a.deck}")
    for i, r in enumerate(runs):
        kind = "cold" if i == 0 and a.cache_dir is None else "warm"
        print(
            f"run {i + 1} ({kind}): {r['wall_s']:.1f} s wall, {r['cpu_s']:.1f} s CPU, "
            f"compiling {r['compile_wall_s']:.1f} s wall ({r['compile_cpu_s']:.1f} s CPU) "
            f"in {len(r['compiled'])} kernel(s); {len(r['used'])} kernel(s) used, "
            f"{len(r['kernel_modules'])} kernel module(s) imported"
        )
    print("compiled:", ", ".join(runs[0]["compiled"]) or "-")
    print("used:", ", ".join(runs[0]["used"]))
    print("kernel modules imported:", ", ".join(runs[0]["kernel_modules"]))


if __name__ == "__main__":
    main()
