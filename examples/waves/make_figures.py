"""PD wave dispersion (n.d.) figures and the pulse table of examples/waves/README.md.

    python examples/waves/make_figures.py [--out DIR] [--no-readme]

* ``seed003_fig7_damping.png``: damping ratio |v_i / v| of linear viscosity (eq. 44);
* ``seed003_fig9_10_pulses.png``: sine and square pulses at t = 77.3 us, plain PD,
  linear and polynomial viscosity against the exact solution; the table of L2 errors,
  trailing oscillation and peak ratio is written to README.md between the
  ``<!-- pulse-table -->`` markers and to ``pulse_results.json``;
* ``seed003_blast_<W>kg.png``: displacement and stress along the bar at 50-250 us,
  the stress history at the midpoint A and its energy spectral density, plain PD vs
  polynomial viscosity (Figs 12-19).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
try:
    import peridynamics  # noqa: F401
except ImportError:  # running from a checkout without installing
    sys.path.insert(0, str(HERE.parents[1] / "src"))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from peridynamics.analysis import viscous_1d  # noqa: E402
from peridynamics.analysis.waves import (  # noqa: E402
    dominant_period,
    energy_spectral_density,
    pulse_comparison,
)
from peridynamics.app.run import Simulation  # noqa: E402
from peridynamics.deck import load_deck  # noqa: E402

KINDS = ("plain", "linear", "polynomial")
VISCOUS = ["material.viscosity.linear=0.2", "material.viscosity.quadratic=2.0"]


def fig7(out: Path) -> None:
    nh = np.linspace(0.0, 2.0, 801)
    fig, ax = plt.subplots(figsize=(6, 4))
    for b1 in (0.2, 0.5, 1.0):
        ax.plot(nh, viscous_1d(nh, 3.015, b1).damping_ratio, label=f"b1 = {b1}")
    ax.set_xlabel("N_h = kappa h / (2 pi)")
    ax.set_ylabel("|v_i / v|")
    ax.set_title("Linear viscosity damping ratio (seed 003 eq. 44), delta = 3.015 h")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "seed003_fig7_damping.png", dpi=110)
    plt.close(fig)


def pulses(out: Path) -> dict:
    v0 = float(np.sqrt(193e9 / 8027))
    results: dict = {}
    fig, axes = plt.subplots(2, 1, figsize=(8, 7))
    for ax, shape in zip(axes, ("sine", "square"), strict=True):
        for kind in KINDS:
            sim = Simulation.from_deck(load_deck(HERE / f"pulse_{shape}_{kind}.yaml"))
            s = sim.solver.init()
            sim.solver.run(s, sim.n_steps)
            wc = sim.deck.output.wave_comparison
            x = sim.cloud.x[:, 0]
            exact, results[f"{shape}_{kind}"] = pulse_comparison(
                x, s.u[:, 0], s.t, wc.shape, wc.amplitude, wc.duration, v0,
                wc.source_position, wc.tail_margin,
            )  # fmt: skip
            ax.plot(x, s.u[:, 0] * 1e6, lw=1, label=f"{kind} PD")
        ax.plot(x, exact * 1e6, "k--", lw=1, label="exact")
        ax.set_xlim(0.15, 0.45)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("u (um)")
        ax.set_title(f"{shape} pulse at t = {s.t * 1e6:.1f} us")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "seed003_fig9_10_pulses.png", dpi=110)
    plt.close(fig)
    (out / "pulse_results.json").write_text(json.dumps(results, indent=2))
    return results


def pulse_table(results: dict) -> str:
    rows = [
        "| pulse | model | L2 error vs exact | trailing oscillation | peak / exact peak |",
        "|---|---|---|---|---|",
    ]
    for key, r in results.items():
        shape, kind = key.split("_")
        rows.append(
            f"| {shape} | {kind} | {r['l2_error_vs_exact']:.4f} | "
            f"{r['trailing_oscillation']:.4f} | {r['peak_ratio']:.3f} |"
        )
    return "\n".join(rows)


def blast(out: Path, charge: int) -> dict:
    times = [50e-6, 100e-6, 150e-6, 200e-6, 250e-6]
    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    summary = {}
    for kind, sets in (("plain", []), ("polynomial", VISCOUS)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sim = Simulation.from_deck(load_deck(HERE / f"blast_bar_{charge}kg.yaml", sets))
        s = sim.solver.init()
        x = sim.cloud.x[:, 0]
        mid = (x[:-1] + x[1:]) / 2
        t_hist, s_hist = [], []
        pending = list(times)
        style = "-" if kind == "plain" else "--"
        while s.step < sim.n_steps:
            sim.solver.step(s)
            t_hist.append(s.t)
            s_hist.append(sim.model.section_stress(s.u, s.intact, 0.5))
            if pending and s.t >= pending[0] - 1e-12:
                t = pending.pop(0)
                lab = f"{kind}, {t * 1e6:.0f} us"
                axes[0, 0].plot(x, s.u[:, 0] * 1e6, style, lw=0.8, label=lab)
                sig = [sim.model.section_stress(s.u, s.intact, p) for p in mid[::5]]
                axes[0, 1].plot(mid[::5], np.array(sig) / 1e6, style, lw=0.8, label=lab)
        t_arr, s_arr = np.array(t_hist), np.array(s_hist)
        axes[1, 0].plot(t_arr * 1e6, s_arr / 1e6, style, lw=0.8, label=kind)
        f, esd = energy_spectral_density(t_arr, s_arr)
        axes[1, 1].loglog(f[1:], esd[1:], style, lw=0.8, label=kind)
        rate = np.abs(np.gradient(s_arr, t_arr))
        summary[kind] = {
            "period_s": dominant_period(t_arr, rate, 1e-4),
            "peak_stress_A_Pa": float(s_arr[np.argmax(np.abs(s_arr))]),
            "esd_above_100kHz": float(esd[f > 1e5].sum()),
            "esd_below_20kHz": float(esd[(f > 0) & (f < 2e4)].sum()),
        }
    axes[0, 0].set(xlabel="x (m)", ylabel="u (um)", title="displacement along the bar")
    axes[0, 1].set(xlabel="x (m)", ylabel="stress (MPa)", title="stress along the bar")
    axes[1, 0].set(xlabel="t (us)", ylabel="stress at A (MPa)", title="stress history at A")
    axes[1, 1].set(xlabel="f (Hz)", ylabel="ESD (Pa^2 s^2)", title="energy spectral density")
    for ax in axes.ravel():
        ax.legend(fontsize=6)
    fig.suptitle(f"Steel bar, {charge} kg TNT at 0.5 m from both ends")
    fig.tight_layout()
    fig.savefig(out / f"seed003_blast_{charge}kg.png", dpi=110)
    plt.close(fig)
    return summary


def main(argv: list[str] | None = None) -> int:
    """Write all figures; update the README table unless ``--no-readme``."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--no-readme", action="store_true")
    ap.add_argument("--skip-blast", action="store_true")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    fig7(args.out)
    results = pulses(args.out)
    table = pulse_table(results)
    print(table)
    if not args.no_readme:
        readme = HERE / "README.md"
        text = readme.read_text()
        new = re.sub(
            r"<!-- pulse-table -->.*<!-- /pulse-table -->",
            f"<!-- pulse-table -->\n{table}\n<!-- /pulse-table -->",
            text,
            flags=re.S,
        )
        readme.write_text(new)
    if not args.skip_blast:
        blasts = {f"{w}kg": blast(args.out, w) for w in (1, 80)}
        (args.out / "blast_results.json").write_text(json.dumps(blasts, indent=2))
        print(json.dumps(blasts, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
