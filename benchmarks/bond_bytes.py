"""Bytes per directed bond of the package's PMB model, array by array.

Run from the repository root::

    python benchmarks/bond_bytes.py                  # 1-D 1e6, 2-D 1000^2, 3-D 60^3
    python benchmarks/bond_bytes.py --cases 3:100 --json out.json

Builds the model of ``peridynamics bench`` (:func:`peridynamics.app.bench._model`), an
``ExplicitSolver`` and its state, takes two steps, then walks the objects reachable from
the solver (attributes, dataclass fields, dicts, lists, tuples) and lists every NumPy
array with one entry per directed bond (first axis = number of bonds), each memory
block once. ``bench`` is the figure ``peridynamics bench`` reports (the bond list's
stored and held arrays + the model's stiffness + the state's intact flags); ``reachable`` is every
per-bond array found. Each case runs in its own process, so its peak RSS (set-up
included) is its own.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

CASES = {1: 1_000_000, 2: 1000, 3: 60}


def _walk(root, n_bonds: int, max_depth: int = 6) -> dict[str, object]:
    """Per-bond arrays reachable from ``root``: {dotted path: array}, each block once."""
    from collections import deque

    import numpy as np

    found: dict[str, object] = {}
    blocks: set[tuple[int, int]] = set()
    seen: set[int] = set()
    stack = deque([(root, type(root).__name__, 0)])  # breadth first: shortest paths
    while stack:
        obj, path, depth = stack.popleft()
        if id(obj) in seen or depth > max_depth:
            continue
        seen.add(id(obj))
        if isinstance(obj, np.ndarray):
            if obj.ndim >= 1 and obj.shape[0] == n_bonds:
                base = obj
                while isinstance(base.base, np.ndarray):
                    base = base.base
                key = (base.__array_interface__["data"][0], base.nbytes)
                if key not in blocks:
                    blocks.add(key)
                    found[path] = obj
            continue
        if isinstance(obj, dict):
            items = [(f"{path}[{k!r}]", v) for k, v in obj.items()]
        elif isinstance(obj, (list, tuple)):
            items = [(f"{path}[{i}]", v) for i, v in enumerate(obj)]
        elif not isinstance(obj, type) and (
            hasattr(obj, "__dict__") or hasattr(type(obj), "__slots__")
        ):
            items = [(f"{path}.{k}", v) for k, v in getattr(obj, "__dict__", {}).items()]
            for k in getattr(type(obj), "__slots__", ()):
                if hasattr(obj, k):
                    items.append((f"{path}.{k}", getattr(obj, k)))
        else:
            continue
        if type(obj).__module__.split(".")[0] not in ("peridynamics", "builtins"):
            continue  # do not wander into NumPy / Numba internals
        stack.extend((v, p, depth + 1) for p, v in items)
    return found


def measure(dim: int, n_side: int) -> dict:
    """Bytes per directed bond of one case (run in a fresh process)."""
    import time

    import numpy as np
    from _load import peak_rss_gib

    from peridynamics.app.bench import _model
    from peridynamics.solvers import ExplicitSolver

    t0 = time.perf_counter()
    model = _model(dim, n_side)
    build_s = time.perf_counter() - t0
    solver = ExplicitSolver(model)
    state = solver.init()
    solver.run(state, 2)
    b = model.bonds
    nb = b.n_bonds
    # walk first: reading a derived array of the bond list (bond_i, bond_xi, ...) would
    # make it; only what the run made itself is held
    reach = _walk({"state": state, "solver": solver}, nb)
    peak = peak_rss_gib()
    bench_arrays = {
        "Bonds.bond_j": b.bond_j,
        "Bonds.bond_intact": b.bond_intact,
        **{f"Bonds.{k} (derived, held)": v for k, v in b._arrays.items()},
        "PMBForceModel.stiffness": model.stiffness,
        "State.intact": state.intact,
    }
    per_point = sum(
        a.nbytes
        for a in _walk({"solver": solver, "state": state}, model.n_points).values()
        if isinstance(a, np.ndarray)
    )
    return {
        "dim": dim,
        "n_side": n_side,
        "points": model.n_points,
        "directed_bonds": nb,
        "bonds_per_point": nb / model.n_points,
        "bench_arrays": {
            k: {"dtype": str(a.dtype), "shape": list(a.shape), "bytes_per_bond": a.nbytes / nb}
            for k, a in bench_arrays.items()
        },
        "bench_bytes_per_bond": sum(a.nbytes for a in bench_arrays.values()) / nb,
        "reachable_arrays": {
            k: {"dtype": str(a.dtype), "shape": list(a.shape), "bytes_per_bond": a.nbytes / nb}
            for k, a in reach.items()
        },
        "reachable_bytes_per_bond": sum(a.nbytes for a in reach.values()) / nb,
        "per_point_arrays_bytes_per_bond": per_point / nb,
        "build_s": build_s,
        "peak_rss_gib": peak,
        "peak_rss_bytes_per_bond": peak * 2**30 / nb,
    }


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cases", default=",".join(f"{d}:{s}" for d, s in CASES.items()))
    p.add_argument("--json", type=Path)
    p.add_argument("--one", help=argparse.SUPPRESS)  # internal: run one case, print JSON
    a = p.parse_args(argv)
    if a.one:
        d, s = (int(v) for v in a.one.split(":"))
        print(json.dumps(measure(d, s)))
        return 0
    out = []
    for spec in a.cases.split(","):
        r = subprocess.run(
            [sys.executable, __file__, "--one", spec], capture_output=True, text=True, check=True
        )
        c = json.loads(r.stdout.strip().splitlines()[-1])
        out.append(c)
        print(
            f"\n{c['dim']}-D {c['n_side']}^{c['dim']}: {c['directed_bonds']} directed bonds "
            f"({c['bonds_per_point']:.2f} per point); bench {c['bench_bytes_per_bond']:.1f} "
            f"B/bond, all per-bond arrays reachable {c['reachable_bytes_per_bond']:.1f} B/bond, "
            f"per-point arrays {c['per_point_arrays_bytes_per_bond']:.1f} B/bond; peak RSS "
            f"{c['peak_rss_gib']:.2f} GiB = {c['peak_rss_bytes_per_bond']:.0f} B/bond; "
            f"build {c['build_s']:.1f} s"
        )
        for k, v in c["reachable_arrays"].items():
            print(f"  {k:60s} {v['dtype']:8s} {v['bytes_per_bond']:5.1f}")
    if a.json:
        a.json.write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
