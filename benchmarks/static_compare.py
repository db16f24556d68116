"""Run the small micropolar regression cases (the overrides of
``tests/regression/test_micropolar_examples.py``) and store what a change of the linear
solver must not change: the bond status, the load-displacement probes, the solves.

Usage::

    python benchmarks/static_compare.py OUT.npz [dcb l_panel l_panel5]
    python benchmarks/static_compare.py --diff A.npz B.npz

Run it once per solver (``PERIDYNAMICS_DIRECT_SOLVER=superlu`` or ``pardiso``, or an
older checkout on ``PYTHONPATH``) and compare the two files with ``--diff``: broken
directed bonds of each, bonds broken differently, the largest relative difference of
every probe over the solves both runs made. ``l_panel5`` is the paper-size deck at
dx = 5 mm (the paper's horizon factor; 7 600 points).
"""

from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path
from tempfile import TemporaryDirectory

import numpy as np

HERE = Path(__file__).resolve().parents[1] / "examples" / "micropolar"
CASES = {
    "dcb": (
        "dcb",
        [
            "discretisation.spacing=1.0e-3", "geometry.size=[0.203,0.04]",
            "boundary_conditions.1.components.y=0.5e-3",
            "boundary_conditions.2.components.y=-0.5e-3", "solver.load_steps=5",
        ],
    ),
    "l_panel": (
        "l_panel",
        [
            "discretisation.spacing=1.0e-2", "discretisation.horizon_factor=3.015",
            "geometry.size=[0.5,0.53]", "geometry.origin=[0.0,-0.03]",
            "node_sets.load.box.max=[0.48,0.26]", "solver.load_steps=10",
            "boundary_conditions.1.components.y=0.6e-3",
        ],
    ),
    "l_panel5": ("l_panel", ["discretisation.spacing=5e-3"]),
}  # fmt: skip


def run(case: str) -> dict[str, np.ndarray]:
    """One case; its bond status, probes (one row per solve) and summary."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    deck, sets = CASES[case]
    sets = [*sets, "output.crack_paths=[]", "output.plot=none"]
    sim = Simulation.from_deck(load_deck(HERE / f"{deck}.yaml", overrides=sets))
    with TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        summary = sim.run(tmp, quiet=True, progress=False)
        wall = time.perf_counter() - t0
        intact = np.load(Path(tmp) / "final_state.npz")["intact"]
        with open(Path(tmp) / "history.csv") as fh:
            rows = list(csv.reader(fh))
    head, body = rows[0], np.array(rows[1:], dtype=float)
    r = summary["results"]
    info = {k: r.get(k) for k in ("solves", "breaking_events", "factorizations")}
    info.update(wall_s=wall, linear_solver=r.get("linear_solver"))
    print(case, json.dumps(info), flush=True)
    return {
        f"{case}_intact": intact,
        f"{case}_history": body,
        f"{case}_columns": np.array(head),
        f"{case}_info": np.array(json.dumps(info)),
    }


def diff(a_path: Path, b_path: Path) -> None:
    """Print the differences of two runs' files."""
    a, b = np.load(a_path), np.load(b_path)
    for case in sorted({k.rsplit("_", 1)[0] for k in a.files if k.endswith("_intact")}):
        if f"{case}_intact" not in b.files:
            continue
        ia, ib = a[f"{case}_intact"], b[f"{case}_intact"]
        ha, hb = a[f"{case}_history"], b[f"{case}_history"]
        cols = list(a[f"{case}_columns"])
        m = min(len(ha), len(hb))
        worst = {}
        for j, name in enumerate(cols):
            x, y = ha[:m, j], hb[:m, j]
            scale = max(float(np.max(np.abs(x))), 1e-300)
            worst[name] = float(np.max(np.abs(x - y)) / scale)
        out = {
            "case": case,
            "broken_a": int(np.count_nonzero(ia == 0)),
            "broken_b": int(np.count_nonzero(ib == 0)),
            "bonds_broken_differently": int(np.count_nonzero(ia != ib)),
            "solves_a": len(ha),
            "solves_b": len(hb),
            "largest_relative_probe_difference": worst,
            "a": json.loads(str(a[f"{case}_info"])),
            "b": json.loads(str(b[f"{case}_info"])),
        }
        print(json.dumps(out, indent=1))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("cases", nargs="*", default=["dcb", "l_panel"])
    ap.add_argument("--diff", type=Path, default=None, help="compare OUT with this file")
    args = ap.parse_args()
    if args.diff is not None:
        diff(args.out, args.diff)
        return 0
    data: dict[str, np.ndarray] = {}
    for case in args.cases:
        data.update(run(case))
    np.savez(args.out, **data)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
