"""E, f_t and G_F of a real concrete: the half-notched beam D = 50 mm of Gregoire et al.
(2013) fitted to its measured load-CMOD band (README of this folder).

Usage::

    python examples/calibration/real_gregoire/fit_gregoire.py --out results/real_gregoire
    python examples/calibration/real_gregoire/fit_gregoire.py --publish   # ... and copy here

1. ``beam_d50.yaml`` at the start values (those of pypd's model of the test) ->
   ``<out>/start/``;
2. fit A, all three at once: ``peridynamics calibrate beam_d50.yaml calibration.yml``
   -> ``<out>/calibration/`` (started again over the same folder, a calibration reads
   its runs back);
3. fit B, in two stages: E alone from the initial compliance
   (``calibration_elastic.yml`` on the rows with CMOD <= 6 um, written to
   ``<out>/elastic/elastic_part.csv``), then f_t and G_F with that E
   (``calibration_softening.yml``) -> ``<out>/elastic/``, ``<out>/softening/``;
4. ``<out>/gregoire_d50.json``: fitted values against the start values, 95 % intervals,
   correlations, misfit, peak loads (measured band, start, fitted), runs and wall time;
   ``<out>/gregoire_d50.png``: the measured band, the start and the fitted curves.
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
DATA = HERE / "gregoire2013_d50_load_cmod.csv"
DOCS_IMG = HERE.parents[2] / "docs" / "img"  # --publish copies the figure there too
START = {  # pypd's model of this test (README): E, f_t, G_F
    "material.youngs_modulus": 37.0e9,
    "damage.tensile_strength": 3.9e6,
    "damage.fracture_energy": 143.2,
}
ELASTIC_CMOD_MM = 0.006  # stage 1 of fit B: the measured points up to this CMOD


def measured() -> dict[str, np.ndarray]:
    """The data file's columns (CMOD in mm, loads in N)."""
    rows = [ln for ln in DATA.read_text().splitlines() if ln and not ln.startswith("#")]
    names = rows[0].split(",")
    vals = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    return {n: vals[:, i] for i, n in enumerate(names)}


def curve(folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """CMOD (mm) and load (N) of a run's ``history.csv``."""
    with (folder / "history.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    cmod = [float(r["mouth_right_ux [m]"]) - float(r["mouth_left_ux [m]"]) for r in rows]
    load = [-float(r["reaction [N]"]) for r in rows]
    return np.array(cmod) * 1e3, np.array(load)


def figure(path: Path, out: Path) -> None:
    """Measured band and middle, the start curve and the two fitted curves."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = measured()
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax.fill_between(m["cmod"], m["load_min"] / 1e3, m["load_max"] / 1e3, color="0.8",
                    label="measured band, Grégoire et al. (2013)")  # fmt: skip
    ax.plot(m["cmod"], m["load_mid"] / 1e3, "k.", ms=3, label="middle of the band (fitted)")
    for folder, style, label in (
        (out / "start", ":", "start values (37 GPa, 3.9 MPa, 143 J/m²)"),
        (out / "calibration" / "fitted_run", "-", "fit A: E, f_t, G_F together"),
        (out / "softening" / "fitted_run", "--", "fit B: E from compliance, then f_t, G_F"),
    ):
        if (folder / "history.csv").is_file():
            c, p = curve(folder)
            ax.plot(c, p / 1e3, style, label=label)
    ax.set_xlim(0.0, 0.21)
    ax.set_ylim(bottom=0.0)
    ax.set_xlabel("CMOD [mm]")
    ax.set_ylabel("load [kN]")
    ax.set_title("half-notched beam D = 50 mm: 2-D PMB, bilinear bonds, dx = 5 mm")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def calibrate(spec: Path, out: Path, jobs: int | None, sets: list[str]) -> dict:
    """One ``peridynamics calibrate`` of beam_d50.yaml, then a run at its fitted values
    (``<out>/fitted_run``); returns the report with the fitted values by key."""
    from peridynamics.cli import main

    deck = HERE / "beam_d50.yaml"
    args = ["calibrate", str(deck), str(spec), "--out", str(out), "--quiet"]
    args += [a for s in sets for a in ("--set", s)]
    if jobs is not None:
        args += ["--jobs", str(jobs)]
    if main(args) != 0:
        raise SystemExit(f"the calibration {spec.name} failed (its message is above)")
    report = json.loads((out / "report.json").read_text())
    fitted = {p["key"]: p["value"] for p in report["uncertainty"]["parameters"]}
    sets = sets + [f"{k}={v!r}" for k, v in fitted.items()]
    run = ["run", str(deck), "--out", str(out / "fitted_run"), "--quiet"]
    if main(run + [a for s in sets for a in ("--set", s)]) != 0:
        raise SystemExit("the run at the fitted values failed")
    return report


def summary(reports: list[dict], folder: Path) -> dict:
    """Fitted values against the start values, intervals, misfit, runs, peak load."""
    params = {}
    for report in reports:
        for p in report["uncertainty"]["parameters"]:
            params[p["name"]] = {"start": START[p["key"]], "fitted": p["value"],
                                 "fitted_over_start": p["value"] / START[p["key"]],
                                 "interval_95": p["interval"]}  # fmt: skip
    e, ft, gf = (params[k]["fitted"] for k in ("E", "f_t", "G_F"))
    return {
        "parameters": params,
        "characteristic_length_m": e * gf / ft**2,
        "peak_load_N": float(curve(folder / "fitted_run")[1].max()),
        "correlation": reports[-1]["uncertainty"]["correlation"],
        "misfit_rms": reports[-1]["misfit"]["rms"],
        "stopped": [r["optimiser"]["stopped"] for r in reports],
        "runs": sum(r["runs"]["runs"] for r in reports),
        "calibration_wall_s": sum(r["wall_s"] for r in reports),
    }


def run(out: Path, jobs: int | None = None) -> dict:
    """Start run, fits A and B, numbers and figure (module docstring)."""
    from peridynamics.cli import main

    t0 = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    if main(["run", str(HERE / "beam_d50.yaml"), "--out", str(out / "start"), "--quiet"]) != 0:
        raise SystemExit("the run at the start values failed")
    fit_a = calibrate(HERE / "calibration.yml", out / "calibration", jobs, [])
    elastic = out / "elastic"
    elastic.mkdir(exist_ok=True)
    shutil.copy(HERE / "calibration_elastic.yml", elastic / "calibration_elastic.yml")
    lines = [ln for ln in DATA.read_text().splitlines() if ln and not ln.startswith("#")]
    keep = [lines[0]] + [ln for ln in lines[1:] if float(ln.split(",")[0]) <= ELASTIC_CMOD_MM]
    (elastic / "elastic_part.csv").write_text("\n".join(keep) + "\n")
    stage1 = calibrate(elastic / "calibration_elastic.yml", elastic / "calibration", 1, [])
    e_fit = stage1["uncertainty"]["parameters"][0]["value"]
    stage2 = calibrate(HERE / "calibration_softening.yml", out / "softening", jobs,
                       [f"material.youngs_modulus={e_fit!r}"])  # fmt: skip
    m = measured()
    numbers = {
        "measured_peak_N": {
            "band_min": float(m["load_min"].max()),
            "band_max": float(m["load_max"].max()),
            "middle": float(m["load_mid"].max()),
        },  # fmt: skip
        "start_peak_load_N": float(curve(out / "start")[1].max()),
        "fit_A": summary([fit_a], out / "calibration"),
        "fit_B": summary([stage1, stage2], out / "softening"),
        "total_wall_s": time.perf_counter() - t0,
    }
    (out / "gregoire_d50.json").write_text(json.dumps(numbers, indent=1) + "\n")
    figure(out / "gregoire_d50.png", out)
    return numbers


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="results/real_gregoire")
    p.add_argument("--jobs", type=int)
    p.add_argument("--publish", action="store_true")
    a = p.parse_args()
    numbers = run(Path(a.out), a.jobs)
    print(json.dumps(numbers, indent=1))
    if a.publish:
        for name in ("gregoire_d50.json", "gregoire_d50.png"):
            shutil.copy(Path(a.out) / name, HERE / name)
        shutil.copy(HERE / "gregoire_d50.png", DOCS_IMG / "calibration_real_gregoire.png")


if __name__ == "__main__":
    main()
