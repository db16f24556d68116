"""The synthetic "measured" data of the calibration example: ``plate.yaml`` run at the
true values (E = 70 GPa, nu = 0.3, or ``--set``), its curves with multiplicative
Gaussian noise of ``--noise`` (1 %) and a fixed seed.

Usage::

    python examples/calibration/make_data.py --out results/calibration_example

Writes ``<out>/truth/`` (the run) and ``<out>/data.csv``: ``load [-]`` (the load
factor), ``ux [mm]`` (the right edge's mean u_x) and ``uy [mm]`` (the top edge's mean
u_y), in millimetres as a test machine would record them; ``calibration.yml``
converts them with ``y_factor: 1.0e-3``.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def make_data(out: Path, sets: list[str], noise: float = 0.01, seed: int = 7) -> Path:
    """Run the deck at the true values into ``out/truth`` and write ``out/data.csv``."""
    from peridynamics.cli import main

    out.mkdir(parents=True, exist_ok=True)
    args = ["run", str(HERE / "plate.yaml"), "--out", str(out / "truth"), "--quiet"]
    for s in sets:
        args += ["--set", s]
    if main(args) != 0:
        raise SystemExit(f"the run of the true values failed; see {out / 'truth'}")
    with (out / "truth" / "history.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    rng = np.random.default_rng(seed)
    data = out / "data.csv"
    with data.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["load [-]", "ux [mm]", "uy [mm]"])
        for row in rows[1:]:  # the unloaded first record carries no information
            ux = float(row["right_ux [m]"]) * 1e3 * (1.0 + noise * rng.normal())
            uy = float(row["top_uy [m]"]) * 1e3 * (1.0 + noise * rng.normal())
            w.writerow([repr(float(row["time [s]"])), repr(ux), repr(uy)])
    return data


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="results/calibration_example")
    p.add_argument("--set", action="append", default=[], metavar="KEY.PATH=VALUE")
    p.add_argument("--noise", type=float, default=0.01, help="relative noise (0.01: 1 %%)")
    p.add_argument("--seed", type=int, default=7)
    a = p.parse_args()
    print(make_data(Path(a.out), a.set, a.noise, a.seed))


if __name__ == "__main__":
    main()
