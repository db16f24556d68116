"""Lu & Wang (2016), Table 2: fracture time, position and wall time of PD3, PD1->PD3, FDM->PD3,
all measured in one process (median of repeated runs of each time loop).

    python examples/spalling/time_table2.py [--repeats 5] [--spacing 0.01]

``--spacing`` refines the 0.99 m test bar (the time step scales with it) to see how the
ordering changes once the per-step work outgrows the fixed per-step overhead.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
try:
    import peridynamics  # noqa: F401
except ImportError:  # running from a checkout without installing
    sys.path.insert(0, str(HERE.parents[1] / "src"))

import numpy as np  # noqa: E402

from peridynamics.app.run import Simulation  # noqa: E402
from peridynamics.deck import load_deck  # noqa: E402

SCHEMES = {"pd3": "PD3", "pd1_pd3": "PD1→PD3", "fdm_pd3": "FDM→PD3"}
PAPER = {"pd3": (0.478, 2.00), "pd1_pd3": (0.466, 0.95), "fdm_pd3": (0.464, 0.53)}


def time_scheme(kind: str, spacing: float, repeats: int) -> dict:
    """Median wall time of the time loop up to fracture, and what happened."""
    sets = [f"discretisation.spacing={spacing}", f"solver.time_step={2e-6 * spacing / 0.01}"]
    walls = []
    for _ in range(repeats):
        sim = Simulation.from_deck(load_deck(HERE / f"test_bar_{kind}.yaml", sets))
        s = sim.solver.init()
        t0 = time.perf_counter()
        t_f, broken = None, 0
        while s.step < sim.n_steps:
            sim.solver.step(s)
            if s.bonds_broken == broken:  # damage changes only when a bond breaks
                continue
            broken = s.bonds_broken
            phi = sim.model.point_damage(s.intact)
            if phi.max() >= 0.3:
                t_f = s.t
                break
        walls.append(time.perf_counter() - t0)
    x = sim.model.cloud.x[:, 0][phi >= 0.3]
    switch = getattr(sim.solver, "switch_time", None)
    return {
        "scheme": SCHEMES[kind],
        "steps": s.step,
        "fracture_time_ms": t_f * 1e3,
        "fracture_position_m": (float(x.min()), float(x.max())),
        "wall_s": float(np.median(walls)),
        "switch_ms": None if switch is None else switch * 1e3,
    }


def main(argv: list[str] | None = None) -> int:
    """Print the Table 2 comparison as Markdown."""
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--spacing", type=float, default=0.01)
    args = p.parse_args(argv)
    rows = [time_scheme(k, args.spacing, args.repeats) for k in SCHEMES]
    base = rows[0]["wall_s"]
    print(f"test bar, dx = {args.spacing} m, median of {args.repeats} runs each\n")
    print(
        "| scheme | steps | t_F (ms) | x_F (m) | wall (s) | wall / PD3 | paper t_F (ms) |"
        " paper CPU (s) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for k, r in zip(SCHEMES, rows, strict=True):
        lo, hi = r["fracture_position_m"]
        print(
            f"| {r['scheme']} | {r['steps']} | {r['fracture_time_ms']:.3f} | {lo:.2f}–{hi:.2f} |"
            f" {r['wall_s']:.4f} | {r['wall_s'] / base:.2f} | {PAPER[k][0]} | {PAPER[k][1]} |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
