"""Peak memory per rank of a decomposed 3-D PMB run against the serial run.

Run from the repository root (needs the ``[mpi]`` extra)::

    python benchmarks/mpi_memory.py                       # 100^3 points, 1 2 4 8 ranks
    python benchmarks/mpi_memory.py --side 60 --ranks 1 2 --json out.json

A cube of ``side^3`` points (spacing 1 mm, horizon 3.015 spacings, PMB with critical
stretch, pulled apart at two faces) runs ``--steps`` explicit steps under
``mpiexec -n N peridynamics run`` for every N of ``--ranks`` (N = 1 is the plain serial
run). Every rank's peak resident memory is read from ``summary.json``
(``timing.peak_rss_gib_per_rank``, taken after every output is written); the serial
run's from ``getrusage`` in its own process. The same runs of a 10^3 cube give the
**fixed part** of a process at each N (interpreter, imports, compiled kernels, MPI):
what a rank holds whatever the model's size. The table gives, for each N, the largest
rank's peak, the serial peak / N, their ratio, and the ratio of what lies above the
fixed part (largest - fixed(N)) / ((serial - fixed(1)) / N): the part that should fall
as 1/N. Ranks beyond the cores oversubscribe: memory, not speed, is the point.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import yaml

DECK = {
    "name": "memory_cube",
    "geometry": {"type": "box", "size": [0.1, 0.1, 0.1]},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
    "material": {"model": "pmb", "youngs_modulus": 70e9, "density": 2700.0},
    "damage": {"model": "critical_stretch", "critical_stretch": 1e-3},
    "node_sets": {
        "low": {"edge": {"normal": [-1.0, 0.0, 0.0], "layers": 3}},
        "high": {"edge": {"normal": [1.0, 0.0, 0.0], "layers": 3}},
    },
    "boundary_conditions": [
        {"type": "velocity", "set": "low", "components": {"x": -1.0}},
        {"type": "velocity", "set": "high", "components": {"x": 1.0}},
    ],
    "solver": {"type": "explicit", "steps": 5},
    "output": {"plot": "none", "bonds": False, "crack_length": False, "history_every": 5},
}

BASELINE = (
    "import resource, numpy, numba, mpi4py.MPI as M, peridynamics.app.run; "
    "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20)"
)
SERIAL = (
    "import resource, sys; from peridynamics.cli import main; rc = main(sys.argv[1:]); "
    "print('PEAK', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20); sys.exit(rc)"
)


def _mpiexec() -> str:
    here = Path(sys.executable).parent / "mpiexec"
    found = str(here) if here.is_file() else shutil.which("mpiexec")
    if found is None:
        raise SystemExit("no mpiexec (pip install '.[mpi]')")
    return found


def measure(side: int, ranks: list[int], steps: int, work: Path) -> dict:
    """Peak memory (GiB) per rank count: ``{N: [per rank]}`` plus the baseline."""
    out = _measure(side, ranks, steps, work)
    if side > 10:
        tiny = _measure(10, ranks, steps, work / "tiny")
        out["fixed_gib"] = {n: max(p) for n, p in tiny["peaks_gib"].items()}
    return out


def _measure(side: int, ranks: list[int], steps: int, work: Path) -> dict:
    work.mkdir(parents=True, exist_ok=True)
    deck = {**DECK, "geometry": {"type": "box", "size": [side * 1e-3] * 3}}
    deck["solver"] = {"type": "explicit", "steps": steps}
    path = work / "deck.yaml"
    path.write_text(yaml.safe_dump(deck))
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    base = float(subprocess.run([sys.executable, "-c", BASELINE], env=env, check=True,
                                capture_output=True, text=True).stdout)  # fmt: skip
    out: dict = {"side": side, "points": side**3, "baseline_gib": base, "peaks_gib": {}}
    for n in ranks:
        folder = work / f"n{n}"
        run = ["run", str(path), "--out", str(folder), "--quiet"]
        if n == 1:
            done = subprocess.run([sys.executable, "-c", SERIAL, *run], env=env,
                                  capture_output=True, text=True)  # fmt: skip
            peaks = [float(done.stdout.split("PEAK")[-1])] if done.returncode == 0 else []
        else:
            cmd = [_mpiexec(), "-n", str(n), sys.executable, "-m", "peridynamics", *run]
            done = subprocess.run(cmd, env=env, capture_output=True, text=True)
            if done.returncode != 0:
                raise SystemExit(done.stderr[-3000:])
            summary = json.loads((folder / "summary.json").read_text())
            peaks = summary["timing"]["peak_rss_gib_per_rank"]
            out.setdefault("set_up", {})[n] = summary["timing"].get("set_up")
            out.setdefault("to_root", {})[n] = summary["timing"].get("to_root")
        if done.returncode != 0:
            raise SystemExit(done.stderr[-3000:])
        out["peaks_gib"][n] = peaks
        print(f"{n} rank(s): peak per rank {[f'{p:.3f}' for p in peaks]} GiB", flush=True)
    return out


def table(res: dict) -> str:
    """Markdown table of a :func:`measure` result."""
    serial = res["peaks_gib"].get(1, [None])[0]
    fixed = res.get("fixed_gib", {})
    lines = [
        "| ranks | peak per rank (GiB) | largest | serial / N | ratio | fixed part "
        "| ratio above it |",
        "|---|---|---|---|---|---|---|",
    ]  # fmt: skip
    for n, peaks in res["peaks_gib"].items():
        big = max(peaks)
        each = ", ".join(f"{p:.3f}" for p in peaks)
        if serial is None or 1 not in fixed or n not in fixed:
            lines.append(f"| {n} | {each} | {big:.3f} | - | - | - | - |")
            continue
        share = (serial - fixed[1]) / int(n)
        lines.append(
            f"| {n} | {each} | {big:.3f} | {serial / int(n):.3f} | {big / (serial / int(n)):.2f} "
            f"| {fixed[n]:.3f} | {(big - fixed[n]) / share:.2f} |"
        )
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--side", type=int, default=100, help="points along each side")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 8])
    ap.add_argument("--steps", type=int, default=5)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        res = measure(args.side, args.ranks, args.steps, Path(tmp))
    print(table(res))
    if args.json is not None:
        args.json.write_text(json.dumps(res, indent=2))


if __name__ == "__main__":
    main()
