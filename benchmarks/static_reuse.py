"""Time per bond-breaking event of the static solver, with and without re-use of the
factorisation (Woodbury correction) — the same deck, the same events, one process.

Usage::

    python benchmarks/static_reuse.py                      # DCB, dx = 1 mm, 120 solves
    python benchmarks/static_reuse.py --spacing 5e-4 --size 0.2015 --solves 60

Runs ``examples/micropolar/dcb.yaml`` twice (``solver.reuse_factorization`` true and
false) for the same number of solves, checks that both broke the same bonds, and prints
(and writes as JSON with ``--json``) the wall time per breaking event of each, their
ratio, the factorisations and the machine.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from tempfile import TemporaryDirectory

import numpy as np

DECK = Path(__file__).resolve().parents[1] / "examples" / "micropolar" / "dcb.yaml"


def _cpu() -> str:
    from _machine import cpu_model  # benchmarks/ is on sys.path when run as a script

    return cpu_model()


def run(reuse: bool, spacing: float, size: float, solves: int) -> dict:
    """One run; returns timing and the final bond status."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    sets = [
        f"discretisation.spacing={spacing}",
        f"geometry.size=[{size},0.04]",
        f"solver.reuse_factorization={'true' if reuse else 'false'}",
        f"solver.max_solves={solves}",
        "output.crack_paths=[]",
        "output.plot=none",
    ]
    sim = Simulation.from_deck(load_deck(DECK, overrides=sets))
    with TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        summary = sim.run(tmp, quiet=True, progress=False)
        wall = time.perf_counter() - t0
        intact = np.load(Path(tmp) / "final_state.npz")["intact"]
    r = summary["results"]
    return {
        "reuse_factorization": reuse,
        "wall_s": wall,
        "solves": r["solves"],
        "breaking_events": r["breaking_events"],
        "factorizations": r["factorizations"],
        "factorization_s": r["factorization_s"],
        "time_per_event_s": r["time_per_event_s"],
        "intact": intact,
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spacing", type=float, default=1.0e-3)
    ap.add_argument("--size", type=float, default=0.203, help="beam length incl. clamp (m)")
    ap.add_argument("--solves", type=int, default=120)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    runs = [run(flag, args.spacing, args.size, args.solves) for flag in (True, False)]
    a, b = runs[0].pop("intact"), runs[1].pop("intact")
    # mirror-symmetric bonds have equal stretches up to round-off, so the two runs may
    # pick different members of a tie: count the differences, not just equality
    same = bool(np.array_equal(a, b))
    for r, intact in zip(runs, (a, b), strict=True):
        r["broken_directed_bonds"] = int(np.count_nonzero(intact == 0))
    out = {
        "machine": f"{_cpu()}, {__import__('os').cpu_count()} cores",
        "spacing_m": args.spacing,
        "runs": runs,
        "same_bonds_broken": same,
        "bonds_broken_differently": int(np.count_nonzero(a != b)),
        "speedup_per_event": runs[1]["time_per_event_s"] / runs[0]["time_per_event_s"],
    }
    print(json.dumps(out, indent=2))
    if args.json:
        args.json.write_text(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
