"""J-integral, crack opening and K_I of the static centre-cracked LPS plate.

Usage::

    python examples/fracture_mechanics/make_figures.py [--out DIR] [--set KEY=VALUE ...]

Runs ``deck.yaml`` from Python (``peridynamics.Simulation``), then on the solved
fields: J on three rectangular contours (half sizes 4, 5 and 6 x 7 dx) around each tip
(:func:`peridynamics.analysis.j_integral`), the opening profile along the crack
(:func:`peridynamics.analysis.crack_opening`) and K_I from it by displacement
extrapolation (:func:`peridynamics.analysis.k_from_opening`, window one horizon to a
behind the tip) and with the effective tip fitted
(:func:`peridynamics.analysis.k_and_tip_from_opening`, same window), all against
K = sigma sqrt(pi a) sqrt(sec(pi a / W)) (Feddersen's finite-width correction).
Writes ``DIR/fracture_mechanics.json`` (the numbers) and ``DIR/fracture_mechanics.png``
(the opening against the near-tip LEFM one of the reference K and against Griffith's
ellipse scaled by Feddersen's factor, and J on the contours).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
SIGMA, WIDTH = 10e6, 0.08  # applied stress (Pa), plate width (m)


def measure(out: Path, sets: list[str]) -> dict[str, Any]:
    """Run the deck with ``sets`` overrides and return the measured numbers and the
    profile of the right-hand crack half."""
    import peridynamics as pd
    from peridynamics.analysis import (
        crack_opening,
        j_integral,
        k_and_tip_from_opening,
        k_from_opening,
    )
    from peridynamics.evaluation import stress as st

    deck = pd.Deck.from_file(HERE / "deck.yaml").with_(sets)
    sim = pd.Simulation(deck, out=out / "run")
    sim.run()
    model, state = sim.model, sim.state
    (x0, y0), (x1, _) = deck.precracks[0].points[:2]
    dx = float(deck.discretisation.spacing)
    delta = float(deck.discretisation.horizon_factor) * dx
    a, mid = 0.5 * (x1 - x0), 0.5 * (x0 + x1)
    e = float(deck.material.youngs_modulus)  # plane stress: E' = E
    k_ref = SIGMA * np.sqrt(np.pi * a / np.cos(np.pi * a / WIDTH))
    sigma = st.point_stress(model, state)[:, :2, :2]
    grad = st.displacement_gradient(model, state)
    x, u = model.cloud.x[:, :2], state.u[:, :2]
    halves = [(h1 * dx, h2 * dx) for h1, h2 in ((4, 4), (5, 5), (6, 7))]
    rec: dict[str, Any] = {"spacing_m": dx, "a_m": a, "k_ref": k_ref, "points": len(x)}
    rec["j_over_k2_e"], profile = {}, None
    window = (delta, a)
    for side, sign in (("right", 1.0), ("left", -1.0)):
        tip = (mid + sign * a, y0)
        rec["j_over_k2_e"][side] = [
            j_integral(x, grad, sigma, tip, h, dx, direction=(sign, 0.0)) / (k_ref**2 / e)
            for h in halves
        ]
        s, cod = crack_opening(x, u, [(mid, y0), tip], dx)
        k_lin, _, _ = k_from_opening(a - s, cod, e, window)
        k_fit, shift = k_and_tip_from_opening(a - s, cod, e, window)
        rec[f"k_extrapolated_over_k_{side}"] = k_lin / k_ref
        rec[f"k_tip_fitted_over_k_{side}"] = k_fit / k_ref
        rec[f"tip_shift_m_{side}"] = shift
        profile = profile or [(a - s).tolist(), cod.tolist()]
    rec["window_m"], rec["contours_m"], rec["profile"] = list(window), halves, profile
    rec["youngs_modulus"] = e
    return rec


def draw(rec: dict[str, Any], path: Path) -> None:
    """The opening of the right half against 8 K/E sqrt(r / 2 pi) and against
    4 sigma_eff/E sqrt(a^2 - x^2) (sigma_eff = K / sqrt(pi a)), and J / (K^2/E) on the
    contours of both tips."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from peridynamics.analysis import lefm_opening

    r, cod = (np.asarray(v) for v in rec["profile"])
    e, k_ref = rec["youngs_modulus"], rec["k_ref"]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    rr = np.linspace(0.0, r.max(), 200)
    ax1.plot(r * 1e3, cod * 1e6, "o", ms=4, label="peridynamic (LPS), bins of dx")
    ax1.plot(rr * 1e3, lefm_opening(rr, k_ref, e) * 1e6, "-", label="8K/E sqrt(r/2pi), K ref")
    a = rec["a_m"]
    griffith = 4 * k_ref / np.sqrt(np.pi * a) / e * np.sqrt(np.clip(a**2 - (a - rr) ** 2, 0, None))
    ax1.plot(rr * 1e3, griffith * 1e6, "--", label="Griffith x Feddersen (approx.)")
    ax1.axvspan(rec["window_m"][0] * 1e3, rec["window_m"][1] * 1e3, color="0.9")
    ax1.set(xlabel="r behind the tip (mm)", ylabel="opening (um)", title="crack opening")
    ax1.legend(fontsize=8)
    size = [2 * h1 * 1e3 for h1, _ in rec["contours_m"]]
    for side, mark in (("right", "o"), ("left", "x")):
        ax2.plot(size, rec["j_over_k2_e"][side], mark, label=f"{side} tip")
    ax2.axhline(1.0, color="k", lw=0.8)
    ax2.set(xlabel="contour width (mm)", ylabel="J / (K^2/E)", title="J-integral",
            ylim=(0.9, 1.1))  # fmt: skip
    ax2.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    """Run, measure, write the JSON and the figure; print the headline numbers."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=HERE)
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = p.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    rec = measure(args.out, args.set)
    (args.out / "fracture_mechanics.json").write_text(json.dumps(rec, indent=1))
    draw(rec, args.out / "fracture_mechanics.png")
    j = rec["j_over_k2_e"]["right"] + rec["j_over_k2_e"]["left"]
    print(f"J/(K^2/E) {min(j):.4f} - {max(j):.4f}; K_I/K extrapolated "
          f"{rec['k_extrapolated_over_k_right']:.4f}, tip fitted "
          f"{rec['k_tip_fitted_over_k_right']:.4f}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
