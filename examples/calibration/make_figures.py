"""The calibration example end to end: synthetic data, the fit, the numbers.

Usage::

    python examples/calibration/make_figures.py                 # as shipped (~1 min)
    python examples/calibration/make_figures.py --publish       # ... and copy fit.png
                                                                #     and the JSON here
    python examples/calibration/make_figures.py --out results/quick --jobs 1

1. ``make_data.py``: ``plate.yaml`` at E = 70 GPa, nu = 0.3, its curves with 1 % noise
   -> ``<out>/data.csv``;
2. ``peridynamics calibrate plate.yaml calibration.yml`` (the data path pointed at
   ``<out>/data.csv``) -> ``<out>/calibration/`` (report.md, report.json, fit.png, ...);
3. ``<out>/calibration_example.json``: the fitted values, their relative errors against
   the truth, whether the 95 % intervals contain it, the runs and the wall time.

``--publish`` copies ``fit.png`` and the JSON into this folder (refused with ``--set``).
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
TRUTH = {"material.youngs_modulus": 70.0e9, "material.poisson_ratio": 0.3}


def run(out: Path, sets: list[str], jobs: int | None) -> dict:
    """Data, calibration and the measured numbers (module docstring)."""
    import yaml

    sys.path.insert(0, str(HERE))
    from make_data import make_data

    from peridynamics.cli import main

    t0 = time.perf_counter()
    data = make_data(out, sets)
    spec = yaml.safe_load((HERE / "calibration.yml").read_text())
    for target in spec["targets"]:
        target["measured"]["file"] = str(data.resolve())
    spec_file = out / "calibration.yml"
    spec_file.write_text(yaml.safe_dump(spec, sort_keys=False))
    args = ["calibrate", str(HERE / "plate.yaml"), str(spec_file),
            "--out", str(out / "calibration"), "--quiet"]  # fmt: skip
    for s in sets:
        args += ["--set", s]
    if jobs is not None:
        args += ["--jobs", str(jobs)]
    if main(args) != 0:
        raise SystemExit("the calibration failed (its message is above)")
    report = json.loads((out / "calibration" / "report.json").read_text())
    rows = {}
    for p in report["uncertainty"]["parameters"]:
        true = TRUTH[p["key"]]
        rows[p["name"]] = {
            "true": true, "fitted": p["value"], "relative_error": p["value"] / true - 1.0,
            "std_error": p["std_error"], "interval_95": p["interval"],
            "interval_contains_truth": p["interval"][0] <= true <= p["interval"][1],
        }  # fmt: skip
    numbers = {
        "parameters": rows,
        "correlation": report["uncertainty"]["correlation"],
        "misfit_rms": report["misfit"]["rms"],
        "runs": report["runs"]["runs"],
        "runs_read_back": report["runs"]["runs_read_back"],
        "calibration_wall_s": report["wall_s"],
        "total_wall_s": time.perf_counter() - t0,
        "sets": sets,
    }
    (out / "calibration_example.json").write_text(json.dumps(numbers, indent=1) + "\n")
    return numbers


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="results/calibration_example")
    p.add_argument("--set", action="append", default=[], metavar="KEY.PATH=VALUE")
    p.add_argument("--jobs", type=int)
    p.add_argument("--publish", action="store_true")
    a = p.parse_args()
    if a.publish and a.set:
        p.error("--publish is refused with --set (the committed numbers are the shipped deck's)")
    out = Path(a.out)
    numbers = run(out, a.set, a.jobs)
    print(json.dumps(numbers, indent=1))
    if a.publish:
        shutil.copy(out / "calibration" / "fit.png", HERE / "fit.png")
        shutil.copy(out / "calibration_example.json", HERE / "calibration_example.json")


if __name__ == "__main__":
    main()
