"""Benchmark the explicit PMB step of two source trees side by side, in one run.

Usage::

    python benchmarks/compare_commits.py OLD_SRC NEW_SRC [--dims 2 3] [--rounds 3]
        [--size default] [--steps 20]

Each round runs ``peridynamics.app.bench.run_case`` (``peridynamics.bench`` in trees
before the ``app`` package) for every dimension in a fresh process,
first with ``PYTHONPATH=OLD_SRC`` then with ``NEW_SRC`` (alternating, so slow drifts of
the machine hit both), and prints the best seconds per step of each tree and the speed
ratio new/old (> 1: the new tree is faster).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

_SNIPPET = (
    "import json, sys, importlib.util as u; "
    "b = 'peridynamics.app.bench' if u.find_spec('peridynamics.app') else 'peridynamics.bench'; "
    "m = __import__(b, fromlist=['run_case']); CASES, run_case = m.CASES, m.run_case; "
    "d = int(sys.argv[1]); r = run_case(d, CASES[sys.argv[2]][d], steps=int(sys.argv[3])); "
    "print(json.dumps(r.as_dict()))"
)


def one(src: str, dim: int, size: str, steps: int) -> dict:
    env = dict(os.environ, PYTHONPATH=str(Path(src).resolve()))
    out = subprocess.check_output(
        [sys.executable, "-c", _SNIPPET, str(dim), size, str(steps)], env=env, text=True
    )
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    old, new = sys.argv[1], sys.argv[2]
    args = sys.argv[3:]
    dims = [2, 3]
    if "--dims" in args:
        i = args.index("--dims") + 1
        dims = []
        while i < len(args) and not args[i].startswith("--"):
            dims.append(int(args[i]))
            i += 1
    rounds = int(args[args.index("--rounds") + 1]) if "--rounds" in args else 3
    size = args[args.index("--size") + 1] if "--size" in args else "default"
    steps = int(args[args.index("--steps") + 1]) if "--steps" in args else 20
    for dim in dims:
        best = {"old": float("inf"), "new": float("inf")}
        bonds = 0
        for _ in range(rounds):
            for tag, src in (("old", old), ("new", new)):
                r = one(src, dim, size, steps)
                best[tag] = min(best[tag], r["seconds_per_step"])
                bonds = r["bonds"]
        ratio = best["old"] / best["new"]
        print(
            f"{dim}-D ({bonds} bonds): old {best['old'] * 1e3:.2f} ms/step "
            f"({bonds / best['old']:.3g} bonds/s), new {best['new'] * 1e3:.2f} ms/step "
            f"({bonds / best['new']:.3g} bonds/s); speed new/old = {ratio:.3f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
