"""Run a deck in float64 and in float32 (``solver.precision``) and count the bonds that
break differently.

Usage (from the repository root)::

    python benchmarks/precision_compare.py examples/crack_branching_2d/deck.yaml \
        --out /tmp/precision [--set key=value ...] [--json out.json]

Both runs go through ``python -m peridynamics run`` (the same command a user runs), one
after the other, and are timed. Compared: the final ``intact`` flags of
``final_state.npz`` (directed bonds broken in one run and intact in the other, each
direction counted), the final damage field, and every scalar of ``results`` in
``summary.json`` (relative difference).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np


def run(deck: str, out: Path, precision: str, sets: list[str]) -> float:
    cmd = [sys.executable, "-m", "peridynamics", "run", deck, "--out", str(out), "--quiet"]
    for s in [*sets, f"solver.precision={precision}"]:
        cmd += ["--set", s]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True)
    return time.perf_counter() - t0


def scalars(tree: object, prefix: str = "") -> dict[str, float]:
    out: dict[str, float] = {}
    if isinstance(tree, dict):
        for k, v in tree.items():
            out.update(scalars(v, f"{prefix}{k}."))
    elif isinstance(tree, (int, float)) and not isinstance(tree, bool):
        out[prefix[:-1]] = float(tree)
    return out


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("deck")
    p.add_argument("--out", type=Path, default=Path("precision_compare"))
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--json", type=Path)
    a = p.parse_args()
    wall = {pr: run(a.deck, a.out / pr, pr, a.set) for pr in ("float64", "float32")}
    s64, s32 = (np.load(a.out / pr / "final_state.npz") for pr in ("float64", "float32"))
    i64, i32 = s64["intact"].astype(bool), s32["intact"].astype(bool)
    broken64, broken32 = int((~i64).sum()), int((~i32).sum())
    only64 = int((~i64 & i32).sum())
    only32 = int((i64 & ~i32).sum())
    r64, r32 = (
        scalars(json.loads((a.out / pr / "summary.json").read_text())["results"])
        for pr in ("float64", "float32")
    )
    rel = {
        k: abs(r32[k] - v) / abs(v) if v else abs(r32[k] - v)
        for k, v in r64.items()
        if k in r32 and np.isfinite(v) and np.isfinite(r32[k])
    }
    report = {
        "deck": a.deck,
        "sets": a.set,
        "wall_s": wall,
        "directed_bonds": int(i64.size),
        "broken_float64": broken64,
        "broken_float32": broken32,
        "broken_only_in_float64": only64,
        "broken_only_in_float32": only32,
        "differ_share_of_broken": (only64 + only32) / max(broken64, 1),
        "damage_max_abs_difference": float(np.abs(s64["damage"] - s32["damage"]).max()),
        "results_relative_difference": dict(sorted(rel.items(), key=lambda kv: -kv[1])),
    }
    print(json.dumps({k: v for k, v in report.items() if k != "results_relative_difference"}))
    for k, v in list(report["results_relative_difference"].items())[:12]:
        print(f"  {k}: {r64[k]:.6g} (float64) {r32[k]:.6g} (float32) rel {v:.3g}")
    if a.json:
        a.json.write_text(json.dumps(report, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
