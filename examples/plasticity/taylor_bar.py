"""Taylor bar impact (``taylor_bar.yaml``): a copper cylinder strikes a rigid wall; the
final length and the footprint (impact-face) radius against the finite-element
references of the same bilinear law and the experiment (examples/plasticity/README.md).

Usage::

    python examples/plasticity/taylor_bar.py                        # dx = 0.4 mm
    python examples/plasticity/taylor_bar.py --spacing 0.6e-3 0.4e-3 # a refinement series
    python examples/plasticity/taylor_bar.py --out /tmp/tb --spacing 1.6e-3  # tiny, quick

Each spacing runs the deck (explicit, to ``solver.end_time``) in a temporary folder
(``--keep DIR``: into ``DIR/dx<mm>/``) and reads ``final_state.npz``. Measured, in the
deformed configuration (the wall is the plane z = 0):

* ``final_length_m``: the largest z of a point plus half a spacing (the free end face
  lies half a cell beyond the top points; that end is nearly undeformed);
* ``footprint_radius_m``: the largest distance from the axis of a point of the impact
  layer (the points of the first reference layer), scaled by R0 / r_ref of that point
  (the outer half cell stretched as its point was, hoop stretch r / r_ref);
  ``footprint_radius_centres_m`` is the unscaled largest distance;
* ``kinetic_energy_fraction``: the kinetic energy left at the end over the initial one.

Writes ``taylor_bar.json`` (and ``taylor_bar.png``, the deformed profiles) into
``<out>``; ``--case wilkins`` (the test of Wilkins & Guinan (1973), L0 = 23.47 mm, D0 =
7.62 mm, 210 m/s) ``taylor_bar_wilkins.json`` / ``.png``.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
DECK = HERE / "taylor_bar.yaml"
#: ``--case wilkins``: the OFHC copper test of Wilkins & Guinan (1973) at 210 m/s
#: (L0 = 23.47 mm, D0 = 7.62 mm), the same bilinear law
WILKINS = {"radius": 3.81e-3, "length": 23.47e-3, "velocity": 210.0}


def deck(spacing: float, end_time: float | None = None, case: str = "benchmark") -> dict:
    """The example deck at ``spacing`` (m), optionally to ``end_time`` (s); ``case``
    ``wilkins``: the geometry and velocity of :data:`WILKINS`."""
    data = yaml.safe_load(DECK.read_text())
    data["discretisation"]["spacing"] = spacing
    if end_time is not None:
        data["solver"]["end_time"] = end_time
    if case == "wilkins":
        data["geometry"].update(radius=WILKINS["radius"], length=WILKINS["length"])
        data["boundary_conditions"][0]["value"] = [0.0, 0.0, -WILKINS["velocity"]]
    data["name"] = f"{case}_dx{spacing * 1e3:g}"
    return data


def measure(x: np.ndarray, u: np.ndarray, v: np.ndarray, data: dict[str, Any]) -> dict:
    """Final length, footprint radius and kinetic energy left (see the module docstring)."""
    dx = float(data["discretisation"]["spacing"])
    r0 = float(data["geometry"]["radius"])
    y = x + u
    impact = x[:, 2] < x[:, 2].min() + 0.5 * dx
    r_ref = np.hypot(x[:, 0], x[:, 1])
    r_cur = np.hypot(y[:, 0], y[:, 1])
    k = int(np.flatnonzero(impact)[np.argmax(r_cur[impact])])
    stretch = r_cur[k] / r_ref[k] if r_ref[k] > 0 else 1.0
    v0 = float(np.linalg.norm(data["boundary_conditions"][0]["value"]))
    return {
        "spacing_m": dx,
        "n_points": len(x),
        # the grid's length: the whole layers that fit (geometry.length / dx need not be whole)
        "initial_length_m": float(x[:, 2].max() - x[:, 2].min() + dx),
        "final_length_m": float(y[:, 2].max() + 0.5 * dx),
        "footprint_radius_m": float(r_cur[k] + (r0 - r_ref[k]) * stretch),
        "footprint_radius_centres_m": float(r_cur[k]),
        "max_radius_m": float(r_cur.max()),
        "min_z_m": float(y[:, 2].min()),
        "kinetic_energy_fraction": float(np.mean(np.sum(v * v, axis=1)) / v0**2),
    }


def run(data: dict[str, Any], out: Path, quiet: bool = True) -> tuple[dict[str, Any], np.ndarray]:
    """Run one deck into ``out``; its measures and wall time, and the deformed positions
    (n, 3)."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import parse_deck

    t0 = time.perf_counter()
    Simulation.from_deck(parse_deck(data)).run(out, quiet=quiet, progress=False)
    seconds = time.perf_counter() - t0
    final = np.load(out / "final_state.npz")
    res = measure(final["x"], final["u"], final["v"], data)
    summary = json.loads((out / "summary.json").read_text())["results"]
    res.update(seconds=seconds, steps=int(summary["steps"]),
               time_step_s=float(summary["time_step_s"]))  # fmt: skip
    return res, final["x"] + final["u"]


def figure(cases: list[dict[str, Any]], shapes: list[np.ndarray], png: Path) -> None:
    """Deformed side views (r, z) of the runs."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(cases), figsize=(3.2 * len(cases), 5.0), squeeze=False)
    for ax, c, y in zip(axes[0], cases, shapes, strict=True):
        ax.scatter(np.hypot(y[:, 0], y[:, 1]) * 1e3, y[:, 2] * 1e3, s=1, c="k")
        ax.axhline(c["final_length_m"] * 1e3, lw=0.8, ls="--", c="r")
        ax.axvline(c["footprint_radius_m"] * 1e3, lw=0.8, ls="--", c="r")
        ax.set_aspect("equal")
        ax.set_xlim(0, 9)
        ax.set_ylim(0, 33)
        ax.set_title(f"dx = {c['spacing_m'] * 1e3:g} mm\nL = {c['final_length_m'] * 1e3:.2f}, "
                     f"R = {c['footprint_radius_m'] * 1e3:.2f} mm", fontsize=9)  # fmt: skip
        ax.set_xlabel("r (mm)")
    axes[0, 0].set_ylabel("z (mm)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--spacing", type=float, nargs="+", default=[0.4e-3])
    p.add_argument("--end-time", type=float, default=None)
    p.add_argument("--case", choices=["benchmark", "wilkins"], default="benchmark")
    p.add_argument("--out", type=Path, default=HERE)
    p.add_argument("--keep", type=Path, default=None, help="keep the runs in this folder")
    p.add_argument("--no-figure", action="store_true")
    a = p.parse_args(argv)
    a.out.mkdir(parents=True, exist_ok=True)
    cases, shapes = [], []
    for dx in a.spacing:
        data = deck(dx, a.end_time, a.case)
        with tempfile.TemporaryDirectory() as tmp:
            res, y = run(data, (a.keep or Path(tmp)) / data["name"])
        res["name"] = data["name"]
        cases.append(res)
        shapes.append(y)
        print(f"dx = {dx * 1e3:g} mm, {res['n_points']} points, {res['steps']} steps, "
              f"{res['seconds']:.0f} s: L = {res['final_length_m'] * 1e3:.2f} mm, "
              f"R = {res['footprint_radius_m'] * 1e3:.2f} mm")  # fmt: skip
    stem = "taylor_bar" if a.case == "benchmark" else "taylor_bar_wilkins"
    (a.out / f"{stem}.json").write_text(json.dumps({"cases": cases}, indent=1))
    if not a.no_figure:
        figure(cases, shapes, a.out / f"{stem}.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
