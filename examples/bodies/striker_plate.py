"""Rigid ball on a glass plate (3-D): damage on a regular grid against jittered clouds,
with a measure of grid-axis bias.

Usage::

    python examples/bodies/striker_plate.py                 # grid + jitter seeds 1, 2, 3
    python examples/bodies/striker_plate.py --seeds 1 --set discretisation.spacing=1.25e-3
    python examples/bodies/striker_plate.py --no-run        # re-analyse finished runs

Each cloud runs ``striker_plate.yaml`` into ``<out>/<name>/`` (``grid``: jitter 0;
``jitter_s<seed>``: the deck's jitter with that seed). For the damage of the points in
the bottom layer (the face opposite the impact, where the plate fails in bending), in
the annulus 3 mm <= r <= 15 mm around the impact axis, binned by polar angle into 36
bins (:func:`peridynamics.analysis.anisotropy.damage_anisotropy`):

* A_4 and A_8, the 4- and 8-fold Fourier amplitudes of the binned damage relative to
  its mean (grid-axis bands: large A_4 / A_8), and the phase of the 4-fold part;
* the extent ratio, max / min over the bins of the largest radius with damage >= 0.5;
* the mean damage of the annulus, the ball's rebound velocity and its peak contact force.

Writes ``striker_plate.json`` and ``striker_plate.png`` (bottom-face damage maps and the
binned damage against angle) into ``<out>``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
DECK = HERE / "striker_plate.yaml"
R_MIN, R_MAX, BINS = 0.003, 0.015, 36


def cloud_deck(jitter: float | None, seed: int, sets: list[str]) -> dict[str, Any]:
    """The deck with ``jitter`` (None: the deck's) and ``seed``."""
    from peridynamics.deck import apply_overrides

    data = yaml.safe_load(DECK.read_text())
    if jitter is not None:
        data["discretisation"]["jitter"] = jitter
    data["discretisation"]["seed"] = seed
    data = apply_overrides(data, sets)
    data["name"] = "grid" if not data["discretisation"]["jitter"] else f"jitter_s{seed}"
    return data


def analyse(data: dict[str, Any], out: Path) -> dict[str, Any]:
    """Anisotropy of the bottom-face damage and the ball's numbers."""
    from peridynamics.analysis.anisotropy import damage_anisotropy

    final = np.load(out / "final_state.npz")
    x, damage = final["x"], final["damage"]
    z = x[:, 2]
    dx = float(data["discretisation"]["spacing"])
    bottom = z < z.min() + 0.5 * dx
    center = np.asarray(data["rigid_bodies"][0]["shape"]["sphere"]["center"][:2], dtype=float)
    a = damage_anisotropy(x[bottom], damage[bottom], center, R_MIN, R_MAX, n_bins=BINS)
    res = json.loads((out / "summary.json").read_text())["results"]
    ball = res["rigid_bodies"]["ball"]
    return {
        "jitter": float(data["discretisation"]["jitter"]),
        "seed": int(data["discretisation"]["seed"]),
        "n_points": int(res["n_points"]),
        "A4": a.harmonic_4,
        "A8": a.harmonic_8,
        "phase4_rad": a.phase_4,
        "extent_ratio": a.extent_ratio,
        "mean_damage": a.mean,
        "ball_final_vz_m_s": float(ball["velocity_m_s"][-1][2]),
        "ball_peak_force_N": float(ball["peak_force_N"]),
        "angles": a.angles.tolist(),
        "binned_damage": a.mean_damage.tolist(),
    }


def figure(cases: dict[str, dict[str, Any]], out: Path) -> None:
    """Bottom-face damage of the grid and the first jittered cloud; binned damage."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [n for n in cases if n == "grid"] + [n for n in cases if n != "grid"][:1]
    fig, axes = plt.subplots(1, len(names) + 1, figsize=(4.6 * (len(names) + 1), 4.4))
    for ax, name in zip(axes, names, strict=False):
        final = np.load(out / name / "final_state.npz")
        x, d = final["x"], final["damage"]
        bottom = x[:, 2] < x[:, 2].min() + 0.5e-3
        ax.scatter(x[bottom, 0] * 1e3, x[bottom, 1] * 1e3, c=d[bottom], s=5, cmap="jet",
                   vmin=0, vmax=1)  # fmt: skip
        ax.set_aspect("equal")
        c = cases[name]
        ax.set_title(f"{name}: bottom face\nA4 = {c['A4']:.3f}, A8 = {c['A8']:.3f}")
        ax.set_xlabel("x (mm)")
    axes[0].set_ylabel("y (mm)")
    ax = axes[-1]
    for name, c in cases.items():
        ax.plot(np.degrees(c["angles"]), c["binned_damage"], label=name)
    ax.set_xlabel("polar angle (deg)")
    ax.set_ylabel(f"mean damage, {R_MIN * 1e3:g} <= r <= {R_MAX * 1e3:g} mm")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "striker_plate.png", dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--out", type=Path, default=HERE / "results" / "striker")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    p.add_argument("--no-run", action="store_true", help="analyse finished runs only")
    a = p.parse_args(argv)
    from peridynamics.app.run import Simulation
    from peridynamics.deck import parse_deck

    a.out.mkdir(parents=True, exist_ok=True)
    decks = [cloud_deck(0.0, 0, a.set)] + [cloud_deck(None, s, a.set) for s in a.seeds]
    cases: dict[str, dict[str, Any]] = {}
    for data in decks:
        out = a.out / data["name"]
        if not a.no_run:
            Simulation.from_deck(parse_deck(data)).run(out, quiet=True, progress=False)
        cases[data["name"]] = analyse(data, out)
    jit = [c for n, c in cases.items() if n != "grid"]
    summary = {
        "cases": cases,
        "jittered_A4_mean": float(np.mean([c["A4"] for c in jit])),
        "jittered_A8_mean": float(np.mean([c["A8"] for c in jit])),
    }
    (a.out / "striker_plate.json").write_text(json.dumps(summary, indent=1))
    figure(cases, a.out)
    for name, c in cases.items():
        print(f"{name}: A4 = {c['A4']:.3f}, A8 = {c['A8']:.3f}, extent ratio = "
              f"{c['extent_ratio']:.2f}, mean damage {c['mean_damage']:.3f}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
