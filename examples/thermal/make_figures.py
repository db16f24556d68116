"""Temperature field of examples/thermal and its centre line against the series.

Usage: python make_figures.py [OUT]: runs deck.yaml (the temperature is a State field;
the run folder's final_state.npz does not hold it yet), writes OUT/thermal_plate.png
and prints the largest difference on the centre line (K).
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

T0, T1, K, RHO, C = 293.15, 373.15, 237.0, 2700.0, 900.0
A, B = 0.006, 0.094  # the mirror planes bounding the body (m)


def series(x: np.ndarray, t: float) -> np.ndarray:
    """1 - theta of the 1-D bar [A, B] with both ends stepped to 1 (Carslaw & Jaeger)."""
    length, alpha = B - A, K / (RHO * C)
    n = np.arange(1, 4000, 2)[:, None]
    decay = np.exp(-((n * np.pi / length) ** 2) * alpha * t)
    return np.sum(4 / (n * np.pi) * np.sin(n * np.pi * (x - A) / length) * decay, axis=0)


def main(out: Path, *overrides: str) -> float:
    """Run the deck (``--set`` style ``overrides``), draw the figure; return the largest
    centre-line difference (K)."""
    from peridynamics.build.simulation import SimulationSetup
    from peridynamics.deck import load_deck
    from peridynamics.solvers.base import run_solver

    deck = load_deck(Path(__file__).with_name("deck.yaml"), list(overrides))
    setup = SimulationSetup.from_deck(deck)
    state = run_solver(setup.solver)
    x, temp, t = setup.cloud.x, state["T"], state.t
    out.mkdir(parents=True, exist_ok=True)
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(10, 4))
    body = np.all((x > A) & (x < B), axis=1)  # not the fictitious (mirrored) layer
    sc = ax0.scatter(x[body, 0] * 1e3, x[body, 1] * 1e3, c=temp[body] - 273.15, s=4, cmap="inferno")
    fig.colorbar(sc, ax=ax0, label="T (°C)")
    ax0.set(aspect="equal", xlabel="x (mm)", ylabel="y (mm)", title=f"t = {t:.2f} s")
    y0 = x[np.argmin(np.abs(x[:, 1] - 0.5 * (A + B))), 1]  # the row nearest the centre
    row = np.abs(x[:, 1] - y0) < 1e-9
    row &= (x[:, 0] > A) & (x[:, 0] < B)
    xs, ts = x[row, 0], temp[row]
    order = np.argsort(xs)
    exact = T1 - (T1 - T0) * series(xs, t) * series(np.full_like(xs, y0), t)
    ax1.plot(xs[order] * 1e3, ts[order] - 273.15, "o", ms=3, label="peridynamics")
    ax1.plot(xs[order] * 1e3, exact[order] - 273.15, "-", label="series")
    ax1.set(xlabel="x (mm)", ylabel="T (°C)", title="centre line")
    ax1.legend()
    fig.tight_layout()
    fig.savefig(out / "thermal_plate.png", dpi=120)
    err = float(np.max(np.abs(ts - exact)))
    print(f"largest centre-line difference: {err:.3g} K")
    return err


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "out"), *sys.argv[2:])
