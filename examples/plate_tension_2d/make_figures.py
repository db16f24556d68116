"""Figure and measured numbers of the plate in uniaxial tension: explicit and ADR.

Usage::

    python examples/plate_tension_2d/make_figures.py             # decks as shipped
    python examples/plate_tension_2d/make_figures.py --publish   # ... and copy PNG and JSON here
    python examples/plate_tension_2d/make_figures.py --out results/quick \
        --set discretisation.spacing=1e-3                        # both decks coarser
    python examples/plate_tension_2d/make_figures.py --no-run    # re-analyse the last runs

Runs ``deck.yaml`` (explicit dynamics, tractions ramped over 60 us, run to 80 us) into
``<out>/explicit/`` and ``adr.yaml`` (the same plate with constant tractions solved for
static equilibrium by adaptive dynamic relaxation) into ``<out>/adr/``; ``--set``
overrides apply to both. Writes ``<out>/plate_tension_2d.json`` (the measured numbers) and
``<out>/plate_tension_2d.png``.

The reference is the static plane-stress solution of the continuum: uniaxial stress
sigma, so the loaded rows (the outermost columns of points, L - dx apart) separate by
sigma (L - dx) / E and the top and bottom rows (H - dx apart) approach by
nu sigma (H - dx) / E with nu = 1/3, the Poisson ratio of 2-D bond-based PMB in plane
stress. Measured:

* explicit: the elongation and the lateral contraction, averaged over the records after
  the ramp (t > 60 us, where the plate oscillates about its static state), their ratios
  to the static values, and the half range of that oscillation;
* ADR: the converged elongation and contraction and their ratios, the iterations and the
  final residual;
* the explicit mean over the ADR value (the model's own static state).

``--publish`` copies the PNG and the JSON into this folder (the committed files); it is
refused together with ``--set``, so the committed numbers are those of the shipped decks.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
CASE = "plate_tension_2d"
RUNS = {"explicit": "deck.yaml", "adr": "adr.yaml"}


def run(out: Path, deck_file: str, sets: list[str], do_run: bool) -> tuple[dict, dict]:
    """Run (or re-read) one deck into ``out``; returns summary.json's content and the data
    of the static reference (with the overrides applied)."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    deck = load_deck(HERE / deck_file, overrides=sets)
    sim = Simulation.from_deck(deck)
    right = next(bc for bc in deck.boundary_conditions if bc.set == "right")
    ramp = getattr(right, "time_function", None)

    def row(name: str, axis: int) -> float:
        return float(sim.cloud.x[sim.cloud.node_set(name), axis].mean())

    ref = {
        "E_Pa": float(deck.material.youngs_modulus),
        "nu": 1.0 / 3.0,
        "sigma_Pa": float(right.value[0]),
        # between the probed rows of points: L - dx and H - dx on a fitting grid
        "gauge_length_m": row("right", 0) - row("left", 0),
        "gauge_height_m": row("top_edge", 1) - row("bottom_edge", 1),
        "spacing_m": float(deck.discretisation.spacing),
        "ramp_end_s": float(getattr(ramp, "end", 0.0)) if ramp is not None else 0.0,
    }
    if do_run:
        sim.run(out, quiet=True, progress=False)
    return json.loads((out / "summary.json").read_text()), ref


def _gaps(summary: dict[str, Any]) -> tuple[Any, Any, Any]:
    """Times, elongation (right - left) and lateral change (top - bottom) of the probes."""
    p = summary["results"]["probes"]
    t = np.asarray(p["right_ux"]["time_s"])
    elong = np.asarray(p["right_ux"]["values"]) - np.asarray(p["left_ux"]["values"])
    lateral = np.asarray(p["top_uy"]["values"]) - np.asarray(p["bottom_uy"]["values"])
    return t, elong, lateral


def analyse(explicit: dict[str, Any], adr: dict[str, Any], ref: dict[str, float]) -> dict:
    """The measured numbers against the static solution (module docstring)."""
    strain = ref["sigma_Pa"] / ref["E_Pa"]
    elong_ref = strain * ref["gauge_length_m"]
    lateral_ref = -ref["nu"] * strain * ref["gauge_height_m"]
    t, elong, lateral = _gaps(explicit)
    late = t > ref["ramp_end_s"]
    _, a_elong, a_lateral = _gaps(adr)
    ra, re = adr["results"], explicit["results"]
    e_mean, l_mean = float(elong[late].mean()), float(lateral[late].mean())
    res: dict[str, Any] = {
        "n_points": re["n_points"],
        "spacing_m": re["spacing_m"],
        "horizon_m": re["horizon_m"],
        "gauge_length_m": ref["gauge_length_m"],
        "gauge_height_m": ref["gauge_height_m"],
        "static_elongation_m": elong_ref,
        "static_lateral_m": lateral_ref,
        "explicit_time_step_s": re["time_step_s"],
        "explicit_steps": re["steps"],
        "explicit_records_after_ramp": int(late.sum()),
        "explicit_mean_elongation_m": e_mean,
        "explicit_elongation_ratio": e_mean / elong_ref,
        "explicit_elongation_half_range_relative": float(np.ptp(elong[late]) / 2 / elong_ref),
        "explicit_mean_lateral_m": l_mean,
        "explicit_lateral_ratio": l_mean / lateral_ref,
        "explicit_lateral_half_range_relative": float(np.ptp(lateral[late]) / 2 / -lateral_ref),
        "explicit_max_kinetic_to_strain_energy": re["max_kinetic_to_strain_energy"],
        "adr_elongation_m": float(a_elong[-1]),
        "adr_elongation_ratio": float(a_elong[-1] / elong_ref),
        "adr_lateral_m": float(a_lateral[-1]),
        "adr_lateral_ratio": float(a_lateral[-1] / lateral_ref),
        "adr_converged": ra["converged"],
        "adr_iterations": ra["iterations"],
        "adr_residual": ra["residual"],
        "explicit_over_adr_elongation": e_mean / float(a_elong[-1]),
        "explicit_over_adr_lateral": l_mean / float(a_lateral[-1]),
        "explicit_run_wall_s": explicit["timing"]["wall_s"],
        "adr_run_wall_s": adr["timing"]["wall_s"],
    }
    res["_curves"] = (t, elong, lateral, late, ref)
    return res


def figure(res: dict[str, Any], path: Path) -> None:
    """Elongation and lateral contraction of the explicit run against the static values."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t, elong, lateral, late, ref = res["_curves"]
    us = t * 1e6
    ramp_end = ref["ramp_end_s"]
    load = np.clip(t / ramp_end, 0.0, 1.0) if ramp_end > 0 else np.ones_like(t)
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.9), gridspec_kw={"width_ratios": [1, 1, 0.8]})
    panels = [
        (
            ax[0],
            elong,
            "elongation",
            res["static_elongation_m"],
            "right - left u_x (µm)",
            "elongation of the loaded rows",
        ),
        (
            ax[1],
            lateral,
            "lateral",
            res["static_lateral_m"],
            "top - bottom u_y (µm)",
            "lateral contraction (ν = 1/3)",
        ),
    ]
    for a, y, key, static, ylabel, title in panels:
        a.plot(us, load * static * 1e6, "k--", lw=1, label="static solution at the current load")
        a.plot(us, y * 1e6, "o-", ms=3, lw=1.2, color="C0", label="PD, explicit (ramp to 60 µs)")
        a.set(xlabel="time (µs)", ylabel=ylabel, title=title)
        a.legend(fontsize=8, loc="upper left" if key == "elongation" else "lower left")
        ratio = y[late] / static
        c = "C0" if key == "elongation" else "C2"
        ax[2].plot(us[late], ratio, "o-", ms=3, color=c, label=f"{key}, explicit")
        ax[2].axhline(
            res[f"explicit_{key}_ratio"],
            color=c,
            ls=":",
            lw=1,
            label=f"  mean {res[f'explicit_{key}_ratio']:.4f}",
        )
        ax[2].axhline(
            res[f"adr_{key}_ratio"],
            color=c,
            ls="--",
            lw=1.5,
            label=f"{key}, ADR {res[f'adr_{key}_ratio']:.4f}",
        )
    ax[2].axhline(1.0, color="k", lw=1, label="static solution")
    ax[2].set(xlabel="time (µs)", ylabel="PD / static solution", title="after the ramp")
    ax[2].legend(fontsize=7, ncol=1, loc="upper left")
    lo = min(ax[2].get_ylim()[0], 0.975)
    ax[2].set_ylim(lo, 1.0 + 1.2 * (1.0 - lo))
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle(
        f"plane-stress plate, σ = {ref['sigma_Pa'] / 1e6:g} MPa, "
        f"Δx = {ref['spacing_m'] * 1e3:g} mm ({res['n_points']} points)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("results") / CASE)
    ap.add_argument("--set", action="append", default=[], help="deck override key=value")
    ap.add_argument("--no-run", action="store_true", help="re-analyse the runs in --out")
    ap.add_argument("--publish", action="store_true", help=f"copy {CASE}.png/.json into {HERE}")
    args = ap.parse_args(argv)
    if args.publish and args.set:
        ap.error("--publish copies the numbers of the shipped decks: not with --set")
    t0 = time.perf_counter()
    got = {
        name: run(args.out / name, deck, list(args.set), not args.no_run)
        for name, deck in RUNS.items()
    }
    res = analyse(got["explicit"][0], got["adr"][0], got["explicit"][1])
    figure(res, args.out / f"{CASE}.png")
    del res["_curves"]
    res["script_wall_s"] = time.perf_counter() - t0
    (args.out / f"{CASE}.json").write_text(json.dumps(res, indent=2) + "\n")
    print(json.dumps(res, indent=2))
    if args.publish:
        for ext in ("png", "json"):
            shutil.copy2(args.out / f"{CASE}.{ext}", HERE / f"{CASE}.{ext}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
