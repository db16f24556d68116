"""S-N law of a uniform bar and da/dN against dK of an edge-cracked plate, by the
remaining-life fatigue law with cycle jumping (docs/theory_fatigue.md).

Usage::

    python examples/fatigue/make_figures.py [--out DIR] [--set KEY=VALUE ...]

Runs ``sn_bar.yaml`` (a chain of equal bonds) at four peak strains and compares the
cycles of its first break with N = 1 / (A1 eps^m1), eps = |1 - R| x strain; runs
``edge_crack.yaml`` (``--set`` overrides go to this deck) and takes from its history
the cycle count N at which the crack tip first reaches each new position a, the growth
rate da/dN between consecutive positions and dK = (1 - R) Y(a/W) sigma sqrt(pi a) with
Y(alpha) = 1.12 - 0.231 alpha + 10.55 alpha^2 - 21.72 alpha^3 + 30.39 alpha^4 (edge crack
in a strip in tension; Tada, Paris & Irwin (2000)); the Paris exponent is the slope of
log da/dN against log dK over 0.2 <= a/W <= 0.7 (the model's is m2). Writes
``DIR/fatigue.json`` (the numbers, the wall time of the plate run) and
``DIR/fatigue.png`` (the two log-log plots).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
STRAINS = (2.0e-4, 5.0e-4, 1.0e-3, 2.0e-3)  # peak strains of the bar
FIT = (0.2, 0.7)  # a/W range of the Paris fit


def edge_crack_y(alpha: np.ndarray) -> np.ndarray:
    """Geometry factor of an edge crack a in a strip of width W in tension, alpha = a/W
    (Tada, Paris & Irwin (2000); within 0.5 % for alpha <= 0.6)."""
    return 1.12 - 0.231 * alpha + 10.55 * alpha**2 - 21.72 * alpha**3 + 30.39 * alpha**4


def sn_curve(out: Path) -> dict[str, Any]:
    """Cycles to the first break of the bar at each peak strain against the S-N law."""
    import peridynamics as pd

    base = pd.Deck.from_file(HERE / "sn_bar.yaml")
    fat = base.damage.fatigue
    r = float(base.solver.load_ratio)
    length = 0.1
    rows = []
    for k, strain in enumerate(STRAINS):
        deck = base.with_([f"boundary_conditions.1.components.x={strain * length!r}"])
        result = pd.Simulation(deck, out=out / f"sn_{k}").run()
        got = float(result.summary["results"]["first_break_cycles"])
        eps = abs(1.0 - r) * strain
        want = 1.0 / (fat.phase_one_a * eps**fat.m1)
        rows.append({"strain": strain, "strain_range": eps, "cycles": got, "sn_law": want})
    return {"a1": fat.phase_one_a, "m1": fat.m1, "load_ratio": r, "points": rows}


def paris(out: Path, sets: list[str]) -> dict[str, Any]:
    """Run the plate and fit the Paris exponent (module docstring)."""
    import peridynamics as pd

    deck = pd.Deck.from_file(HERE / "edge_crack.yaml").with_(sets)
    t0 = time.perf_counter()
    result = pd.Simulation(deck, out=out / "plate").run()
    wall = time.perf_counter() - t0
    res = result.summary["results"]
    h = result.history
    dx = float(deck.discretisation.spacing)
    width = float(deck.geometry.size[0])
    sigma = float(deck.boundary_conditions[0].value[1])
    r = float(deck.solver.load_ratio)
    a0 = float(deck.precracks[0].points[1][0])
    n = h["cycles"].to_numpy()
    a = h["crack_tip"].to_numpy() + 0.5 * dx  # the tip point's cell reaches a + dx/2
    a_k, first = np.unique(a, return_index=True)
    keep = a_k > a0 + dx  # positions the fatigue crack reached
    a_k, n_k = a_k[keep], n[first][keep]
    mid = 0.5 * (a_k[1:] + a_k[:-1])
    dadn = np.diff(a_k) / np.diff(n_k)
    dk = (1.0 - r) * edge_crack_y(mid / width) * sigma * np.sqrt(np.pi * mid)
    sel = (mid / width >= FIT[0]) & (mid / width <= FIT[1]) & np.isfinite(dadn) & (dadn > 0)
    slope, intercept = np.polyfit(np.log(dk[sel]), np.log(dadn[sel]), 1)
    fat = deck.damage.fatigue
    m2 = float(fat.m2)
    # C with the exponent fixed at m2, and the lattice factor beta of
    # C = beta A2 delta^(1 - m2/2) / E^m2 (docs/theory_fatigue.md, "Calibration")
    c_m2 = float(np.exp(np.mean(np.log(dadn[sel]) - m2 * np.log(dk[sel]))))
    delta = float(deck.discretisation.horizon_factor) * dx
    e = float(deck.material.youngs_modulus)  # plane stress: E' = E
    beta = c_m2 * e**m2 / (float(fat.a2) * delta ** (1.0 - 0.5 * m2))
    return {
        "spacing_m": dx,
        "points": int(res["n_points"]),
        "m2": m2,
        "paris_exponent": float(slope),
        "paris_exponent_error": float(slope / m2 - 1.0),
        "paris_c": float(np.exp(intercept)),
        "paris_c_at_m2": c_m2,
        "beta": beta,
        "fit_a_over_w": list(FIT),
        "fit_points": int(sel.sum()),
        "cycles": float(res["cycles"]),
        "increments": int(res["increments"]),
        "solves": int(res["solves"]),
        "end": res["end"],
        "wall_s": wall,
        "a_m": mid.tolist(),
        "dadn_m_per_cycle": dadn.tolist(),
        "dk_pa_sqrt_m": dk.tolist(),
        "width_m": width,
    }


def draw(sn: dict[str, Any], pr: dict[str, Any], path: Path) -> None:
    """S-N points against the law; da/dN against dK with the fitted line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    eps = np.array([p["strain_range"] for p in sn["points"]])
    got = np.array([p["cycles"] for p in sn["points"]])
    ee = np.geomspace(eps.min() / 1.5, eps.max() * 1.5, 50)
    ax1.loglog(got, eps, "o", label="peridynamic bar (first break)")
    ax1.loglog(1.0 / (sn["a1"] * ee ** sn["m1"]), ee, "-", label="N = 1/(A1 eps^m1)")
    ax1.set(xlabel="cycles to failure N", ylabel="cyclic bond strain eps", title="S-N")
    ax1.legend(fontsize=8)
    dk, dadn = np.array(pr["dk_pa_sqrt_m"]), np.array(pr["dadn_m_per_cycle"])
    alpha = np.array(pr["a_m"]) / pr["width_m"]
    fit = (alpha >= FIT[0]) & (alpha <= FIT[1]) & (dadn > 0)
    rest = ~fit & (dadn > 0)
    ax2.loglog(dk[fit] / 1e6, dadn[fit], "o", ms=4, label="peridynamic plate (fitted)")
    ax2.loglog(dk[rest] / 1e6, dadn[rest], "o", ms=4, mfc="none", label="outside the fit")
    kk = np.geomspace(dk[fit].min(), dk[fit].max(), 50)
    ax2.loglog(kk / 1e6, pr["paris_c"] * kk ** pr["paris_exponent"], "-",
               label=f"fit a/W {FIT[0]}-{FIT[1]}: slope {pr['paris_exponent']:.2f} "
               f"(m2 = {pr['m2']:g})")  # fmt: skip
    ax2.set(xlabel="dK (MPa sqrt(m))", ylabel="da/dN (m/cycle)", title="crack growth")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    """Run both decks, write the JSON and the figure; print the headline numbers."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=HERE)
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = p.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    sn = sn_curve(args.out / "runs")
    pr = paris(args.out / "runs", args.set)
    (args.out / "fatigue.json").write_text(json.dumps({"sn": sn, "paris": pr}, indent=1))
    draw(sn, pr, args.out / "fatigue.png")
    worst = max(abs(q["cycles"] / q["sn_law"] - 1.0) for q in sn["points"])
    print(f"S-N: largest relative error {worst:.2e}; Paris exponent "
          f"{pr['paris_exponent']:.3f} (m2 = {pr['m2']:g}, {pr['fit_points']} points), "
          f"beta {pr['beta']:.4f}; "
          f"plate: {pr['increments']} jumps to N = {pr['cycles']:.4g} "
          f"in {pr['wall_s']:.1f} s")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
