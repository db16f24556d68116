"""Brazilian disc between rigid platens at three resolutions: splitting strength, where
the crack starts and the load-closure curves.

Usage::

    python examples/bodies/brazilian_disc.py                  # D/dx = 40, 60, 80
    python examples/bodies/brazilian_disc.py --ratios 20 30   # other resolutions
    python examples/bodies/brazilian_disc.py --no-run         # re-analyse finished runs
    python examples/bodies/brazilian_disc.py --horizon 2.5e-3 --ratios 60 80 100 120
                                                               # delta fixed, dx shrinking

Each resolution runs ``brazilian_disc.yaml`` into ``<out>/D<ratio>/`` (spacing D/ratio,
horizon 3.015 spacings: m fixed, delta shrinks with dx). The script writes
``brazilian_disc.json`` (measured numbers) and ``brazilian_disc.png`` into ``<out>``:

* the peak reaction P of the top platen and the splitting strength 2 P / (pi D t)
  (ISRM (1978); ASTM D3967), against the bonds' uniaxial strength f_t;
* the spread of the strength over the resolutions, (max - min) / mean;
* where damage first reaches 0.2 (``output.fracture``): the centre of the damaged
  points' bounding box, its distance from the disc centre / R, and the box's size / R
  (small: one spot, not damage at both platens at once);
* at the end, the damaged points (damage >= 0.35): mean |x - x_c| / R (a crack along
  the loaded diameter has it small) and their vertical extent / D;
* the largest kinetic / strain energy ratio before the peak (quasi-static check).
"""

from __future__ import annotations

import argparse
import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
DECK = HERE / "brazilian_disc.yaml"
DAMAGED = 0.35


def disc_deck(ratio: float, sets: list[str], horizon: float | None = None) -> dict[str, Any]:
    """The deck with spacing D / ratio (and ``--set`` overrides); ``horizon`` (m): a fixed
    delta instead of the deck's 3.015 spacings."""
    from peridynamics.deck import apply_overrides

    data = yaml.safe_load(DECK.read_text())
    d = 2.0 * float(data["geometry"]["holes"][0]["not"]["circle"]["radius"])
    data["discretisation"]["spacing"] = d / ratio
    if horizon is not None:
        data["discretisation"].pop("horizon_factor", None)
        data["discretisation"]["horizon"] = horizon
    data["name"] = f"brazilian_disc_D{ratio:g}"
    data.setdefault("output", {})["fracture"] = {"damage_threshold": 0.2}
    return apply_overrides(data, sets)


def run_case(data: dict[str, Any], out: Path) -> None:
    """Run one deck into ``out``."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import parse_deck

    sim = Simulation.from_deck(parse_deck(data))
    sim.run(out, quiet=True, progress=False)


def analyse(data: dict[str, Any], out: Path) -> dict[str, Any]:
    """Measured numbers of one finished run."""
    summary = json.loads((out / "summary.json").read_text())
    res = summary["results"]
    hole = data["geometry"]["holes"][0]["not"]["circle"]
    center, radius = np.asarray(hole["center"], dtype=float), float(hole["radius"])
    t = float(data["geometry"]["thickness"])
    f_t = float(data["damage"]["tensile_strength"])
    rb = res["rigid_bodies"]
    time = np.asarray(rb["time_s"])
    top = np.asarray(rb["top_platen"]["force_N"])[:, 1]
    closure = -(
        np.asarray(rb["top_platen"]["displacement_m"])[:, 1]
        - np.asarray(rb["bottom_platen"]["displacement_m"])[:, 1]
    )
    k = int(np.argmax(top))
    peak = float(top[k])
    strength = 2.0 * peak / (math.pi * 2.0 * radius * t)
    hist = res["history"]
    ke, se = np.asarray(hist["kinetic_energy_J"]), np.asarray(hist["strain_energy_J"])
    before = np.asarray(hist["time_s"]) <= time[k]
    loaded = before & (se > 0.1 * se[before].max())
    first = res.get("fracture_position_m")
    onset = size = None
    if first is not None:
        box = np.asarray(first, dtype=float)
        onset = float(np.linalg.norm(0.5 * (box[0] + box[1]) - center) / radius)
        size = float(np.max(box[1] - box[0]) / radius)
    final = np.load(out / "final_state.npz")
    x, damage = final["x"], final["damage"]
    crack: dict[str, Any] = {}
    hit = damage >= DAMAGED
    if hit.any():
        crack = {
            "mean_offset_from_loaded_diameter_over_R": float(
                np.mean(np.abs(x[hit, 0] - center[0])) / radius
            ),
            "vertical_extent_over_D": float(np.ptp(x[hit, 1]) / (2 * radius)),
        }
    return {
        "spacing_m": float(data["discretisation"]["spacing"]),
        "n_points": int(res["n_points"]),
        "peak_load_N": peak,
        "closure_at_peak_m": float(closure[k]),
        "splitting_strength_Pa": strength,
        "strength_over_f_t": strength / f_t,
        "first_damage_distance_from_centre_over_R": onset,
        "first_damage_box_size_over_R": size,
        "max_kinetic_to_strain_before_peak": float(np.max(ke[loaded] / se[loaded]))
        if loaded.any()
        else None,
        **crack,
        "wall_s": float(summary["timing"]["wall_s"]),
        "curve": {"closure_m": closure.tolist(), "load_N": top.tolist()},
    }


def figure(cases: dict[str, dict[str, Any]], out: Path, finest: Path) -> None:
    """Load-closure curves of every resolution and the damage of the finest run."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.6))
    for name, c in cases.items():
        cv = c["curve"]
        ax.plot(
            np.asarray(cv["closure_m"]) * 1e6,
            np.asarray(cv["load_N"]) / 1e3,
            label=f"{name}: {c['splitting_strength_Pa'] / 1e6:.2f} MPa",
        )
    ax.set_xlabel("platen closure (um)")
    ax.set_ylabel("top platen reaction (kN)")
    ax.set_title("Brazilian disc: load against closure")
    ax.legend(title="D/dx: 2P/(pi D t)")
    final = np.load(finest / "final_state.npz")
    x = final["x"]
    sc = ax2.scatter(
        x[:, 0] * 1e3, x[:, 1] * 1e3, c=final["damage"], s=2, cmap="jet", vmin=0, vmax=1
    )
    ax2.set_aspect("equal")
    ax2.set_xlabel("x (mm)")
    ax2.set_ylabel("y (mm)")
    ax2.set_title(f"damage at the end, {finest.name}")
    fig.colorbar(sc, ax=ax2, label="damage")
    fig.tight_layout()
    fig.savefig(out / "brazilian_disc.png", dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--ratios", type=float, nargs="+", default=[40.0, 60.0, 80.0])
    p.add_argument("--out", type=Path, default=HERE / "results")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    p.add_argument("--no-run", action="store_true", help="analyse finished runs only")
    p.add_argument("--horizon", type=float, default=None,
                   help="a fixed horizon (m) at every ratio (default 3.015 dx)")  # fmt: skip
    a = p.parse_args(argv)
    a.out.mkdir(parents=True, exist_ok=True)
    cases: dict[str, dict[str, Any]] = {}
    last = a.out
    for ratio in a.ratios:
        data = disc_deck(ratio, a.set, a.horizon)
        out = a.out / f"D{ratio:g}"
        if not a.no_run:
            run_case(data, out)
        cases[f"D{ratio:g}"] = analyse(data, out)
        last = out
    s = np.asarray([c["splitting_strength_Pa"] for c in cases.values()])
    result = {
        "machine": os.environ.get("PERIDYNAMICS_MACHINE", ""),
        "cases": cases,
        "strength_spread_over_mean": float(np.ptp(s) / s.mean()),
    }
    (a.out / "brazilian_disc.json").write_text(json.dumps(result, indent=1))
    figure(cases, a.out, last)
    for name, c in cases.items():
        print(
            f"{name}: P = {c['peak_load_N'] / 1e3:.2f} kN, 2P/(pi D t) = "
            f"{c['splitting_strength_Pa'] / 1e6:.3f} MPa ({c['strength_over_f_t']:.3f} f_t), "
            f"first damage at {c['first_damage_distance_from_centre_over_R']} R"
        )
    print(f"spread (max - min) / mean = {result['strength_spread_over_mean']:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
