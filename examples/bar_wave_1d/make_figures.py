"""Figure and measured numbers of the 1-D bar wave (Lu & Wang (2016), Fig. 7 wave test).

Usage::

    python examples/bar_wave_1d/make_figures.py              # -> results/bar_wave_1d/
    python examples/bar_wave_1d/make_figures.py --publish    # ... and copy the PNG and JSON here
    python examples/bar_wave_1d/make_figures.py --out results/quick \
        --set discretisation.spacing=0.01                    # a coarser bar
    python examples/bar_wave_1d/make_figures.py --no-run     # re-analyse the last run

Runs ``deck.yaml`` into ``<out>/`` and writes ``<out>/bar_wave_1d.json`` (the measured
numbers) and ``<out>/bar_wave_1d.png``. The reference is the d'Alembert solution of the
local bar: the triangular stress pulse p(t) applied at x = 0 travels undistorted at
c = sqrt(E / rho), so the particle velocity at the gauge x_g is
v(t) = p(t - x_g / c) / (rho c) and the displacement is its time integral. Measured from
the gauge probes of ``summary.json``:

* the arrival time (first record with |v| >= 10 % of the peak, the probe's
  ``arrival_time_s``) against x_g / c + 0.1 t_rise;
* the time the velocity first reaches half its peak (interpolated) against
  x_g / c + 0.5 t_rise;
* the peak particle velocity and its time against p_m / (rho c) at x_g / c + t_rise;
* the displacement at the end of the run against the integral of the analytic velocity
  (by the end nearly the whole pulse has passed: the momentum it carries);
* the relative L2 error of the whole velocity history against the analytic one.

``--publish`` copies the PNG and the JSON into this folder (the committed files); it is
refused together with ``--set``, so the committed numbers are those of the shipped deck.
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
CASE = "bar_wave_1d"


def run(out: Path, sets: list[str], do_run: bool) -> tuple[dict[str, Any], dict[str, float]]:
    """Run (or re-read) the deck; returns summary.json's content and the data of the
    analytic reference (material, load and gauge position, with the overrides applied)."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    deck = load_deck(HERE / "deck.yaml", overrides=sets)
    sim = Simulation.from_deck(deck)
    load = deck.boundary_conditions[0]
    pulse = load.time_function
    ref = {
        "E_Pa": float(deck.material.youngs_modulus),
        "rho_kg_m3": float(deck.material.density),
        "p_m_Pa": float(load.value[0]) * float(pulse.peak),
        "rise_time_s": float(pulse.rise_time),
        "duration_s": float(pulse.duration),
        "gauge_x_m": float(sim.cloud.x[sim.cloud.node_set("gauge"), 0].mean()),
    }
    if do_run:
        sim.run(out, quiet=True, progress=False)
    return json.loads((out / "summary.json").read_text()), ref


def triangle(t: Any, rise: float, duration: float) -> Any:
    """Unit triangular pulse: 0 at t = 0, 1 at ``rise``, 0 from ``duration`` on."""
    t = np.asarray(t, dtype=float)
    up = np.clip(t / rise, 0.0, None)
    down = (duration - t) / (duration - rise)
    return np.where((t > 0) & (t < duration), np.minimum(up, down), 0.0)


def triangle_integral(t: Any, rise: float, duration: float) -> Any:
    """Integral of :func:`triangle` from 0 to t (s)."""
    t = np.clip(np.asarray(t, dtype=float), 0.0, duration)
    rising = 0.5 * np.minimum(t, rise) ** 2 / rise
    tail = np.clip(t - rise, 0.0, None)
    falling = tail - 0.5 * tail**2 / (duration - rise)
    return rising + falling


def first_crossing(t: Any, v: Any, level: float) -> float | None:
    """Time (linear interpolation) at which v first reaches ``level`` (> 0)."""
    above = np.flatnonzero(v >= level)
    if not len(above) or above[0] == 0:
        return None
    k = above[0]
    return float(t[k - 1] + (level - v[k - 1]) / (v[k] - v[k - 1]) * (t[k] - t[k - 1]))


def analyse(summary: dict[str, Any], ref: dict[str, float]) -> dict[str, Any]:
    """The measured numbers against the analytic reference (module docstring)."""
    r = summary["results"]
    c = float(np.sqrt(ref["E_Pa"] / ref["rho_kg_m3"]))
    rise, dur, xg = ref["rise_time_s"], ref["duration_s"], ref["gauge_x_m"]
    v0 = ref["p_m_Pa"] / (ref["rho_kg_m3"] * c)
    vel = r["probes"]["gauge_velocity"]
    disp = r["probes"]["gauge_displacement"]
    t = np.asarray(vel["time_s"])
    v = np.asarray(vel["values"])
    u = np.asarray(disp["values"])
    v_exact = v0 * triangle(t - xg / c, rise, dur)
    u_exact = v0 * triangle_integral(t - xg / c, rise, dur)
    half = first_crossing(t, v, 0.5 * vel["peak"])
    t_half = xg / c + 0.5 * rise
    res: dict[str, Any] = {
        "n_points": r["n_points"],
        "spacing_m": r["spacing_m"],
        "horizon_m": r["horizon_m"],
        "time_step_s": r["time_step_s"],
        "gauge_x_m": xg,
        "wave_speed_m_per_s": c,
        "travel_time_s": xg / c,
        "arrival_10pct_s": vel["arrival_time_s"],
        "arrival_10pct_reference_s": xg / c + 0.1 * rise,
        "arrival_10pct_delay_s": vel["arrival_time_s"] - (xg / c + 0.1 * rise),
        "half_peak_s": half,
        "half_peak_reference_s": t_half,
        "half_peak_delay_s": None if half is None else half - t_half,
        "front_speed_from_half_peak_m_per_s": None if half is None else xg / (half - 0.5 * rise),
        "peak_velocity_m_per_s": vel["peak"],
        "peak_velocity_reference_m_per_s": v0,
        "peak_velocity_ratio": vel["peak"] / v0,
        "peak_time_s": vel["peak_time_s"],
        "peak_time_reference_s": xg / c + rise,
        "peak_time_delay_s": vel["peak_time_s"] - (xg / c + rise),
        "final_time_s": float(t[-1]),
        "final_displacement_m": float(u[-1]),
        "final_displacement_reference_m": float(u_exact[-1]),
        "final_displacement_ratio": float(u[-1] / u_exact[-1]),
        "velocity_l2_error_relative": float(np.linalg.norm(v - v_exact) / np.linalg.norm(v_exact)),
        "run_wall_s": summary["timing"]["wall_s"],
        "setup_s": summary["timing"]["setup_s"],
    }
    res["_curves"] = (t, v, u, v_exact, u_exact)
    return res


def figure(res: dict[str, Any], path: Path) -> None:
    """Velocity and displacement at the gauge against the analytic pulse."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t, v, u, v_exact, u_exact = res["_curves"]
    us = t * 1e6
    dx, delta = res["spacing_m"], res["horizon_m"]
    at = f"x = {res['gauge_x_m']:g} m"
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.9))
    ax[0].plot(us, v_exact, "k--", lw=1.2, label="d'Alembert, v = p(t - x/c) / (ρc)")
    ax[0].plot(us, v, "-", color="C0", lw=1.5, label="PD")
    ax[0].axvline(res["arrival_10pct_reference_s"] * 1e6, color="k", ls=":", lw=0.8)
    ax[0].plot(
        res["arrival_10pct_s"] * 1e6,
        0.1 * res["peak_velocity_m_per_s"],
        "o",
        color="C3",
        ms=5,
        label=f"PD arrival (10 %): {res['arrival_10pct_s'] * 1e6:.0f} µs",
    )
    ax[0].plot(
        res["peak_time_s"] * 1e6,
        res["peak_velocity_m_per_s"],
        "s",
        color="C3",
        ms=5,
        label=f"PD peak {res['peak_velocity_m_per_s']:.4f} m/s "
        f"({res['peak_velocity_ratio']:.3f} × p_m/(ρc))",
    )
    ax[0].set(
        xlabel="time (µs)",
        ylabel=f"particle velocity at {at} (m/s)",
        title=f"gauge velocity (Δx = {dx * 1e3:g} mm, δ = {delta / dx:g}Δx)",
    )
    ax[1].plot(us, u_exact * 1e6, "k--", lw=1.2, label="d'Alembert")
    ax[1].plot(us, u * 1e6, "-", color="C0", lw=1.5, label="PD")
    ax[1].set(xlabel="time (µs)", ylabel=f"displacement at {at} (µm)", title="gauge displacement")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("results") / CASE)
    ap.add_argument("--set", action="append", default=[], help="deck override key=value")
    ap.add_argument("--no-run", action="store_true", help="re-analyse the run in --out")
    ap.add_argument("--publish", action="store_true", help=f"copy {CASE}.png/.json into {HERE}")
    args = ap.parse_args(argv)
    if args.publish and args.set:
        ap.error("--publish copies the numbers of the shipped deck: not with --set")
    t0 = time.perf_counter()
    summary, ref = run(args.out, list(args.set), not args.no_run)
    res = analyse(summary, ref)
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
