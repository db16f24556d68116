"""Run every shipped example deck with two source trees and compare their ``results``.

Usage::

    python benchmarks/compare_results.py run SRC_DIR OUT_DIR [--only PATTERN] [--skip PATTERN]
    python benchmarks/compare_results.py compare OUT_A OUT_B

``run`` executes ``python -m peridynamics run`` for each deck under ``examples/`` with
``PYTHONPATH=SRC_DIR`` (so an old commit's ``src`` can be checked out beside this one);
``compare`` walks the ``results`` of each pair of ``summary.json`` files and reports, per
deck, whether they are equal bit for bit or the largest relative difference (and where).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def decks(only: str | None, skip: str | None = None) -> list[Path]:
    found = sorted(ROOT.glob("examples/**/*.yaml"))
    return [
        d for d in found
        if (only is None or only in str(d)) and (skip is None or skip not in str(d))
    ]  # fmt: skip


def run(src: str, out: Path, only: str | None, skip: str | None = None) -> None:
    env = dict(os.environ, PYTHONPATH=str(Path(src).resolve()))
    for deck in decks(only, skip):
        name = str(deck.relative_to(ROOT / "examples")).replace("/", "__").removesuffix(".yaml")
        t0 = time.perf_counter()
        rc = subprocess.call(
            [sys.executable, "-m", "peridynamics", "run", str(deck), "--out", str(out / name),
             "--quiet"],
            env=env, cwd=deck.parent, stdout=subprocess.DEVNULL,
        )  # fmt: skip
        print(f"{name}: exit {rc}, {time.perf_counter() - t0:.1f} s", flush=True)


def _leaves(obj: object, path: str = ""):
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _leaves(v, f"{path}.{k}" if path else str(k))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _leaves(v, f"{path}[{i}]")
    else:
        yield path, obj


def compare(a: Path, b: Path) -> int:
    worst_all = 0.0
    for sa in sorted(a.glob("*/summary.json")):
        sb = b / sa.parent.name / "summary.json"
        if not sb.exists():
            print(f"{sa.parent.name}: missing in {b}")
            worst_all = float("inf")
            continue
        ra = dict(_leaves(json.loads(sa.read_text())["results"]))
        rb = dict(_leaves(json.loads(sb.read_text())["results"]))
        missing = sorted(set(ra) ^ set(rb))
        worst, where = 0.0, ""
        for key in set(ra) & set(rb):
            x, y = ra[key], rb[key]
            if x == y:
                continue
            if isinstance(x, int | float) and isinstance(y, int | float):
                rel = abs(x - y) / max(abs(x), abs(y), 1e-300)
            else:
                rel = float("inf")
            if rel > worst:
                worst, where = rel, key
        worst_all = max(worst_all, worst)
        verdict = "bit for bit" if worst == 0 else f"max rel. diff {worst:.3g} at {where}"
        extra = f"; keys only in one: {missing[:6]}" if missing else ""
        print(f"{sa.parent.name}: {verdict}{extra}")
    print(f"largest relative difference over all decks: {worst_all:.3g}")
    return 0


if __name__ == "__main__":
    cmd = sys.argv[1]
    if cmd == "run":
        only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None
        skip = sys.argv[sys.argv.index("--skip") + 1] if "--skip" in sys.argv else None
        run(sys.argv[2], Path(sys.argv[3]), only, skip)
    else:
        sys.exit(compare(Path(sys.argv[2]), Path(sys.argv[3])))
