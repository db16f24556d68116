"""Three-parameter synthetic recovery: E, f_t and G_F of a notched plate with bilinear
softening bonds from its load-displacement curve with 1 % noise.

Usage::

    python examples/calibration/recovery_softening.py --out results/recovery_softening
    python examples/calibration/recovery_softening.py --publish   # ... and copy the JSON here

1. ``notched_softening.yaml`` at the true values (E = 30 GPa, f_t = 3 MPa,
   G_F = 100 J/m^2): the reaction of the pulled edge against its displacement, each
   load multiplied by 1 + 0.01 N(0, 1) (seed 11) -> ``<out>/softening_data.csv`` (kN,
   mm);
2. ``peridynamics calibrate notched_softening.yaml notched_softening.yml`` from the
   middles of the log bounds -> ``<out>/calibration/``;
3. ``<out>/recovery_softening.json``: fitted values, relative errors, 95 % intervals
   and whether they contain the truth, runs and wall time.
"""

from __future__ import annotations

import argparse
import csv
import json
import shutil
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
TRUTH = {
    "material.youngs_modulus": 30.0e9,
    "damage.tensile_strength": 3.0e6,
    "damage.fracture_energy": 100.0,
}


def run(out: Path, jobs: int | None = None, noise: float = 0.01, seed: int = 11) -> dict:
    """Data, calibration and numbers (module docstring)."""
    import yaml

    from peridynamics.cli import main

    t0 = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    deck = HERE / "notched_softening.yaml"
    if main(["run", str(deck), "--out", str(out / "truth"), "--quiet"]) != 0:
        raise SystemExit("the run of the true values failed")
    with (out / "truth" / "history.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    rng = np.random.default_rng(seed)
    data = out / "softening_data.csv"
    with data.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["pull [mm]", "load [kN]"])
        for row in rows[1:]:
            load = float(row["reaction [N]"]) * 1e-3 * (1.0 + noise * rng.normal())
            w.writerow([repr(float(row["pull [m]"]) * 1e3), repr(load)])
    spec = yaml.safe_load((HERE / "notched_softening.yml").read_text())
    spec["targets"][0]["measured"]["file"] = str(data.resolve())
    spec_file = out / "notched_softening.yml"
    spec_file.write_text(yaml.safe_dump(spec, sort_keys=False))
    args = ["calibrate", str(deck), str(spec_file), "--out", str(out / "calibration"), "--quiet"]
    if jobs is not None:
        args += ["--jobs", str(jobs)]
    if main(args) != 0:
        raise SystemExit("the calibration failed (its message is above)")
    report = json.loads((out / "calibration" / "report.json").read_text())
    rows_out = {}
    for p in report["uncertainty"]["parameters"]:
        true = TRUTH[p["key"]]
        rows_out[p["name"]] = {
            "true": true, "fitted": p["value"], "relative_error": p["value"] / true - 1.0,
            "interval_95": p["interval"],
            "interval_contains_truth": p["interval"][0] <= true <= p["interval"][1],
        }  # fmt: skip
    numbers = {
        "parameters": rows_out,
        "correlation": report["uncertainty"]["correlation"],
        "misfit_rms": report["misfit"]["rms"],
        "stopped": report["optimiser"]["stopped"],
        "runs": report["runs"]["runs"],
        "runs_read_back": report["runs"]["runs_read_back"],
        "calibration_wall_s": report["wall_s"],
        "total_wall_s": time.perf_counter() - t0,
    }
    (out / "recovery_softening.json").write_text(json.dumps(numbers, indent=1) + "\n")
    return numbers


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="results/recovery_softening")
    p.add_argument("--jobs", type=int)
    p.add_argument("--publish", action="store_true")
    a = p.parse_args()
    numbers = run(Path(a.out), a.jobs)
    print(json.dumps(numbers, indent=1))
    if a.publish:
        shutil.copy(Path(a.out) / "recovery_softening.json", HERE / "recovery_softening.json")
        shutil.copy(Path(a.out) / "calibration" / "fit.png", HERE / "recovery_softening.png")


if __name__ == "__main__":
    main()
