"""Measure the interior E and nu of the bond-based model on a grid, by static solves.

Usage::

    python benchmarks/lattice_moduli.py [--dims 2 3] [--m 2 3.015 4 5]

A plate (plane stress) or a box under a uniaxial traction on two faces is solved by
adaptive dynamic relaxation (``solver: {type: adr}``) with the deck defaults (truncated
partial volumes, surface correction on) and, for comparison, without the correction;
E and nu come from a least-squares fit of the displacement of the points farther than
one horizon (3-D) or two (2-D) from every face. Prints one table row per case, used for
the table in docs/theory_bond_based.md.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from tempfile import TemporaryDirectory

import numpy as np

from peridynamics.app.run import Simulation
from peridynamics.deck import parse_deck

E, SIGMA = 70e9, 1e6


def measure(dim: int, m: float, corrected: bool, out: Path) -> tuple[float, float, int, float]:
    dx = 1e-3
    thick = int(np.ceil(max(14, 5 * m)))
    n = (int(np.ceil(max(40, 12 * m))), thick) + ((thick,) if dim == 3 else ())
    size = [k * dx for k in n]
    geometry = (
        {"type": "rectangle", "size": size, "thickness": 1e-3}
        if dim == 2
        else {"type": "box", "size": size}
    )
    normal = [1.0] + [0.0] * (dim - 1)
    value = [SIGMA] + [0.0] * (dim - 1)
    deck = {
        "name": f"lattice_{dim}d",
        "geometry": geometry,
        "discretisation": {"spacing": dx, "horizon_factor": m, "surface_correction": corrected},
        "material": {"youngs_modulus": E, "density": 2700.0},
        "node_sets": {
            "left": {"edge": {"normal": [-c for c in normal]}},
            "right": {"edge": {"normal": normal}},
        },
        "boundary_conditions": [
            {"type": "traction", "set": "right", "value": value},
            {"type": "traction", "set": "left", "value": [-v for v in value]},
        ],
        "solver": {"type": "adr", "tolerance": 1e-10},
        "output": {"plot": "none"},
    }
    sim = Simulation.from_deck(parse_deck(deck))
    t0 = time.perf_counter()
    sim.run(out, quiet=True)
    wall = time.perf_counter() - t0
    u = np.load(out / "final_state.npz")["u"]
    x = sim.cloud.x
    margin = (2.0 if dim == 2 else 1.0) * m * dx
    lo, hi = x.min(axis=0), x.max(axis=0)
    inner = np.all((x > lo + margin) & (x < hi - margin), axis=1)
    a = np.column_stack([x[inner], np.ones(int(inner.sum()))])
    exx = np.linalg.lstsq(a, u[inner, 0], rcond=None)[0][0]
    eyy = np.linalg.lstsq(a, u[inner, 1], rcond=None)[0][1]
    return SIGMA / exx / E, -eyy / exx, sim.cloud.n_points, wall


def main() -> None:
    args = sys.argv[1:]

    def values(flag: str, default: list[float]) -> list[float]:
        if flag not in args:
            return default
        i, got = args.index(flag) + 1, []
        while i < len(args) and not args[i].startswith("--"):
            got.append(float(args[i]))
            i += 1
        return got

    dims = [int(d) for d in values("--dims", [2, 3])]
    ms = values("--m", [2.0, 3.015, 4.0, 5.0])
    print(
        "| dim | m = delta/dx | points | E/E0 corrected | nu corrected | E/E0 uncorrected "
        "| nu uncorrected | wall (s) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    with TemporaryDirectory() as tmp:
        for dim in dims:
            for m in ms:
                ec, nc, n, w1 = measure(dim, m, True, Path(tmp) / "c")
                eu, nu_, _, w2 = measure(dim, m, False, Path(tmp) / "u")
                print(
                    f"| {dim} | {m:g} | {n} | {ec:.4f} | {nc:.4f} | {eu:.4f} | {nu_:.4f} "
                    f"| {w1 + w2:.1f} |",
                    flush=True,
                )


if __name__ == "__main__":
    main()
