"""SED-PD (2021) flawed specimens: damage maps at several load steps, crack initiation at
the flaw tips (step, position, direction) and, for two flaws, the coalescence steps.

    python examples/rock_compression/analyse.py [--decks flaw30_m10 flaw45 flaw60
        double_flaw45] [--m-study] [--out DIR] [--every 10] [--set KEY=VALUE ...]
        [--tag NAME]

Writes ``<deck>[_tag]_stages.png``, ``weibull_shape_study[_tag].png`` (with
``--m-study``) and ``flaw_results[_tag].json``. Definitions:

* new damage: phi - phi(t = 0) (the flaw itself damages the points along it);
* initiation at a tip: the first recorded step with at least 3 points within 2 delta of
  the tip whose damage rose by 0.2 or more;
* initial direction: mean direction from the tip to the newly damaged points within
  3 delta, at the first step with at least 10 of them (angle from +x, and the angle to
  the flaw line and to the loading axis y);
* coalescence: a cluster of newly damaged points (rise >= 0.3) touching both flaw zones
  (points within 2 delta of each flaw); first and second coalescence are the first steps
  with one and with two separate such clusters.
"""

from __future__ import annotations

import argparse
import json
import sys
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

from peridynamics.analysis.flaws import (  # noqa: E402
    angle_between_lines,
    bridges,
    initiation_direction,
)
from peridynamics.app.run import Simulation  # noqa: E402
from peridynamics.deck import load_deck  # noqa: E402

DECKS = ("flaw30_m10", "flaw45", "flaw60", "double_flaw45")
PAPER = {
    "flaw30_m10": "wing and shear cracks dominate; anti-wing cracks suppressed",
    "flaw45": "wing cracks start perpendicular to the flaw, turn to the loading axis and "
    "stop at about the flaw length; then coplanar shear and anti-wing cracks",
    "flaw60": "large anti-wing cracks, which may merge with the shear cracks",
    "double_flaw45": "stage 1: wing cracks link the inner tips (first coalescence); "
    "stage 2: shear cracks close a failure ring; stage 3: macro shear crack",
}


def show_damage(ax, x: np.ndarray, phi: np.ndarray, spacing: float) -> None:
    """Damage of a grid of points as an image (compact PNGs; one pixel per point)."""
    lo = x.min(axis=0)
    ij = np.rint((x - lo) / spacing).astype(int)
    img = np.full(ij.max(axis=0) + 1, np.nan)
    img[ij[:, 0], ij[:, 1]] = phi
    hi = lo + (np.array(img.shape) - 1) * spacing
    ext = [(lo[0] - spacing / 2) * 1e3, (hi[0] + spacing / 2) * 1e3,
           (lo[1] - spacing / 2) * 1e3, (hi[1] + spacing / 2) * 1e3]  # fmt: skip
    ax.imshow(img.T, origin="lower", extent=ext, cmap="jet", vmin=0, vmax=1,
              interpolation="nearest")  # fmt: skip


def segment_distance(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of points (n, 2) to the segment a-b."""
    ab = b - a
    t = np.clip(((x - a) @ ab) / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(x - (a + t[:, None] * ab), axis=1)


def analyse(name: str, sets: list[str], every: int, out: Path, tag: str = "") -> dict:
    deck = load_deck(HERE / f"{name}.yaml", sets)
    sim = Simulation.from_deck(deck)
    solver, model = sim.solver, sim.model
    x = model.cloud.x
    delta = model.bonds.horizon
    flaws = [np.asarray(c.points, dtype=float) for c in deck.precracks]
    s = solver.init()
    phi0 = model.point_damage(s.intact)
    steps, fields = [0], [phi0.astype(np.float32)]
    while s.step < sim.n_steps:
        solver.step(s)
        if s.step % every == 0 or s.step == sim.n_steps:
            steps.append(s.step)
            fields.append(model.point_damage(s.intact).astype(np.float32))
    phis = np.array(fields)

    tips = []
    for k, (a, b) in enumerate(flaws):
        flaw_deg = float(np.degrees(np.arctan2(b[1] - a[1], b[0] - a[0])))
        for label, tip in (("lower", a if a[1] < b[1] else b), ("upper", b if a[1] < b[1] else a)):
            near = np.linalg.norm(x - tip, axis=1)
            entry: dict = {"flaw": k, "tip": label, "position_m": tip.tolist()}
            for i, phi in enumerate(phis):
                rise = phi - phi0
                if np.count_nonzero((near <= 2 * delta) & (rise >= 0.2)) >= 3:
                    entry["initiation_step"] = steps[i]
                    break
            for i, phi in enumerate(phis):
                rise = phi - phi0
                if np.count_nonzero((near <= 3 * delta) & (rise >= 0.2)) >= 10:
                    d = initiation_direction(x, phi, phi0, tip, 3 * delta)
                    if d is not None:
                        entry["direction_step"] = steps[i]
                        entry["direction_deg"] = d
                        entry["angle_to_flaw_deg"] = angle_between_lines(d, flaw_deg)
                        entry["angle_to_loading_axis_deg"] = angle_between_lines(d, 90.0)
                    break
            tips.append(entry)

    rise_any = [np.flatnonzero(phi - phi0 >= 0.2) for phi in phis]
    first = next((i for i, r in enumerate(rise_any) if r.size), None)
    first_new = None
    if first is not None:
        pts = x[rise_any[first]]
        all_tips = np.array([t["position_m"] for t in tips])
        dist = np.min(np.linalg.norm(pts[:, None, :] - all_tips[None], axis=2), axis=1)
        first_new = {
            "step": steps[first],
            "points": int(pts.shape[0]),
            "max_distance_to_nearest_tip_m": float(dist.max()),
            "at_tips": bool(dist.max() <= 2 * delta),
        }

    result = {"paper": PAPER.get(name, ""), "first_new_damage": first_new, "tips": tips}
    if len(flaws) == 2:
        zone_a = segment_distance(x, *flaws[0]) <= 2 * delta
        zone_b = segment_distance(x, *flaws[1]) <= 2 * delta
        counts = [bridges(x, phi, phi0, zone_a, zone_b, model.cloud.spacing, 0.3) for phi in phis]
        result["bridges_per_step"] = dict(zip(steps, counts, strict=True))
        result["first_coalescence_step"] = next(
            (st for st, c in zip(steps, counts, strict=True) if c >= 1), None
        )
        result["second_coalescence_step"] = next(
            (st for st, c in zip(steps, counts, strict=True) if c >= 2), None
        )

    n_steps = steps[-1]
    stages = [int(round(f * n_steps / every)) * every for f in (0.55, 0.7, 0.85, 1.0)]
    fig, axes = plt.subplots(1, 4, figsize=(14, 6))
    for ax, st in zip(axes, stages, strict=True):
        i = steps.index(min(steps, key=lambda v, st=st: abs(v - st)))
        show_damage(ax, x, phis[i], model.cloud.spacing)
        for a, b in flaws:
            ax.plot([a[0] * 1e3, b[0] * 1e3], [a[1] * 1e3, b[1] * 1e3], "w-", lw=1)
        ax.set_title(f"step {steps[i]}", fontsize=9)
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
    axes[0].set_ylabel("y (mm)")
    fig.suptitle(f"{name}{tag}: damage")
    fig.tight_layout()
    fig.savefig(out / f"{name}{tag}_stages.png", dpi=100)
    plt.close(fig)
    return result


def m_study(sets: list[str], out: Path, tag: str = "") -> dict:
    """Final damage of flaw30_m<M> for the six Weibull moduli (SED-PD (2021), section 3.2)."""
    shapes = (2, 6, 10, 20, 50, 100)
    fig, axes = plt.subplots(1, 6, figsize=(16, 5.5))
    res = {}
    for ax, m in zip(axes, shapes, strict=True):
        sim = Simulation.from_deck(load_deck(HERE / f"flaw30_m{m}.yaml", sets))
        s = sim.solver.init()
        sim.solver.run(s, sim.n_steps)
        x, phi = sim.model.cloud.x, sim.model.point_damage(s.intact)
        res[m] = float(np.mean(phi >= 0.3))
        show_damage(ax, x, phi, sim.model.cloud.spacing)
        ax.set_title(f"m = {m}: {100 * res[m]:.2f} % damaged", fontsize=9)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle(f"flaw at 30 degrees, step {s.step}: Weibull shape study{tag}")
    fig.tight_layout()
    fig.savefig(out / f"weibull_shape_study{tag}.png", dpi=100)
    plt.close(fig)
    return res


def main(argv: list[str] | None = None) -> int:
    """Analyse the decks and write flaw_results.json."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--decks", nargs="+", default=list(DECKS))
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--every", type=int, default=10, help="record damage every N steps")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--tag", default="", help="suffix of the output files (variants)")
    ap.add_argument("--m-study", action="store_true", help="also the six Weibull moduli")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    tag = f"_{args.tag}" if args.tag else ""
    results: dict = {
        name: analyse(name, args.set, args.every, args.out, tag) for name in args.decks
    }
    if args.m_study:
        results["damaged_area_fraction_by_m"] = m_study(args.set, args.out, tag)
    (args.out / f"flaw_results{tag}.json").write_text(json.dumps(results, indent=2))
    brief = {
        k: {kk: vv for kk, vv in v.items() if kk != "bridges_per_step"}
        if isinstance(v, dict) and "tips" in v
        else v
        for k, v in results.items()
    }
    print(json.dumps(brief, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
