"""Figure and measured numbers of the crack-branching example (Ha & Bobaru (2010)).

Usage::

    python examples/crack_branching_2d/make_figures.py                # the deck as shipped
    python examples/crack_branching_2d/make_figures.py --publish      # also copy into this folder
    python examples/crack_branching_2d/make_figures.py --out results/cb_small \
        --set discretisation.spacing=5e-4 --set discretisation.horizon=2e-3
    python examples/crack_branching_2d/make_figures.py --no-run       # re-analyse a run

Runs ``deck.yaml`` into ``<out>/`` (default ``results/crack_branching_2d``) and writes
``crack_branching_2d.json`` (the measured numbers) and ``crack_branching_2d.png`` there
(``--publish`` copies both into this folder):

* the Rayleigh speed of the model as run: the exact root of the Rayleigh equation for
  plane stress with nu = 1/3 (bond-based PMB) and E times the interior modulus ratio of
  the uncorrected model, 0.855 at delta = 4 dx as measured by static solves
  (docs/deck.md, ``surface_correction``; the constant of
  ``tests/regression/test_examples.py``); also with the ratio the library's crack-path
  observer uses (the median energy density under a uniform uniaxial *strain* over the
  continuum value, :func:`peridynamics.io.observers.crack_paths.effective_modulus_ratio`: 0.877
  here) and with the nominal E;
* from ``summary.json`` (``output.crack_tip``, damage >= 0.35 along the ligament from the
  pre-crack tip): the time the crack starts, the tip position and speed histories, the
  largest tip speed (centred difference over +-3 records), the mean speed between 12 and
  40 us (least-squares slope of the tip position), the branching point and the number of
  branches, the broken-bond crack length;
* from ``final_state.npz``: where the two branch tips end (the lowest and highest cracked
  point within one horizon of the farthest one) and the half-angle of the branches seen
  from the branching point.

The figure: the final damage field over the reference configuration (top), the tip
position (bottom left) and the tip speed against the Rayleigh speeds (bottom right).
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
CASE = "crack_branching_2d"
#: the window of the mean tip speed, s
MEAN_SPEED_WINDOW = (12.0e-6, 40.0e-6)
#: interior modulus / E of the uncorrected PMB model in plane stress by delta / dx, measured
#: by static solves of a plate in uniaxial tension (docs/deck.md, surface_correction)
STATIC_MODULUS_RATIO = {4.0: 0.855, 3.015: 0.842}


def rayleigh_speeds(sim: Any) -> dict[str, float | None]:
    """Rayleigh speeds (m/s, exact root, plane stress, nu = 1/3) of the model as run, from
    two measures of its interior modulus, and of the nominal E."""
    from peridynamics.analysis.crack_speed import rayleigh_speed
    from peridynamics.io.observers.crack_paths import effective_modulus_ratio

    mat = sim.model.material
    plane = sim.cloud.plane or "stress"
    energy = effective_modulus_ratio(sim.model)
    m = round(sim.model.bonds.horizon / sim.cloud.spacing, 3)
    static = STATIC_MODULUS_RATIO.get(m) if plane == "stress" else None

    def c_r(ratio: float | None) -> float | None:
        if ratio is None:
            return None
        return rayleigh_speed(ratio * mat.youngs_modulus, None, mat.density, plane, "exact")

    return {
        "modulus_ratio_static": static,
        "rayleigh_speed_model_m_per_s": c_r(static),
        "modulus_ratio_energy": energy,
        "rayleigh_speed_energy_ratio_m_per_s": c_r(energy),
        "rayleigh_speed_nominal_E_m_per_s": c_r(1.0),
    }


def run(out: Path, sets: list[str], no_run: bool) -> tuple[dict[str, Any], dict[str, float]]:
    """Run the deck into ``out`` (unless ``no_run``); (summary, Rayleigh speeds)."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    deck = load_deck(HERE / "deck.yaml", overrides=sets)
    sim = Simulation.from_deck(deck)
    speeds = rayleigh_speeds(sim)  # before the run: the as-built bonds
    if not no_run:
        sim.run(out, quiet=True, progress=False)
    return json.loads((out / "summary.json").read_text()), speeds


def analyse(out: Path, summary: dict[str, Any], speeds: dict[str, float]) -> dict[str, Any]:
    """The measured numbers (module docstring)."""
    r = summary["results"]
    crack_tip = summary["inputs"]["output"]["crack_tip"]
    origin = np.asarray(crack_tip["origin"], dtype=float)
    thr = float(crack_tip["damage_threshold"])
    t = np.asarray(r["history"]["time_s"])
    pos = np.asarray(r["crack_tip_position_m"])
    speed = np.asarray(r["crack_tip_speed_m_per_s"])
    # the static-solve modulus where it was measured (delta / dx = 4 or 3.015), else the
    # library's energy ratio
    c_r = speeds["rayleigh_speed_model_m_per_s"] or speeds["rayleigh_speed_energy_ratio_m_per_s"]
    c_e = speeds["rayleigh_speed_energy_ratio_m_per_s"]
    moving = np.flatnonzero(pos > 0.0)
    start = float(t[moving[0]]) if len(moving) else None
    win = (t >= MEAN_SPEED_WINDOW[0]) & (t <= MEAN_SPEED_WINDOW[1])
    mean_speed = float(np.polyfit(t[win], pos[win], 1)[0]) if win.sum() >= 2 else None

    state = np.load(out / "final_state.npz")
    x, damage = state["x"], state["damage"]
    horizon = r["horizon_m"]
    cracked = (damage >= thr) & (x[:, 0] > origin[0])
    tip_x = float(origin[0] + pos[-1])
    ends = cracked & (x[:, 0] >= tip_x - horizon)
    y_lo = float(x[ends, 1].min()) if ends.any() else None
    y_hi = float(x[ends, 1].max()) if ends.any() else None
    half_angle = None
    bx = r.get("branching_x_m")
    if r.get("crack_branched") and bx is not None and y_lo is not None and tip_x > bx:
        half_angle = float(np.degrees(np.arctan2(0.5 * (y_hi - y_lo), tip_x - bx)))
    max_speed = float(r["max_crack_tip_speed_m_per_s"])
    return {
        "n_points": r["n_points"],
        "n_bonds": r["n_bonds"],
        "spacing_m": r["spacing_m"],
        "horizon_m": horizon,
        "steps": r["steps"],
        "time_step_s": r["time_step_s"],
        "final_time_s": r["final_time_s"],
        **speeds,
        "first_damage_time_s": r["events"].get("first_damage", {}).get("time_s"),
        "crack_start_time_s": start,
        "crack_tip_position_final_m": float(pos[-1]),
        "crack_tip_x_final_m": tip_x,
        "max_crack_tip_speed_m_per_s": max_speed,
        "rayleigh_speed_compared_m_per_s": c_r,
        "max_speed_over_rayleigh_model": max_speed / c_r,
        "max_speed_over_rayleigh_energy_ratio": max_speed / c_e,
        "max_speed_over_rayleigh_nominal": max_speed / speeds["rayleigh_speed_nominal_E_m_per_s"],
        "mean_speed_window_s": list(MEAN_SPEED_WINDOW),
        "mean_crack_tip_speed_m_per_s": mean_speed,
        "mean_speed_over_rayleigh_model": None if mean_speed is None else mean_speed / c_r,
        "records_above_rayleigh_model": int(np.count_nonzero(speed > c_r)),
        "crack_branched": r["crack_branched"],
        "crack_branches": r["crack_branches"],
        "branching_x_m": bx,
        "branching_distance_m": r.get("branching_distance_m"),
        "branch_tips_y_m": [y_lo, y_hi],
        "branch_half_angle_deg": half_angle,
        "crack_length_m": r.get("crack_length_m"),
        "crack_length_all_bonds_m": r.get("crack_length_all_bonds_m"),
        "max_damage": r["max_damage"],
        "bonds_broken": r["bonds_broken"],
        "_plot": (t, pos, speed, x, damage, origin),
    }


def _damage_image(ax: Any, x: Any, damage: Any, dx: float) -> Any:
    """The damage on the grid as an image (a scatter plot if the points are no grid)."""
    lo = x.min(axis=0)
    idx = np.rint((x - lo) / dx).astype(np.int64)
    shape = idx.max(axis=0) + 1
    if len(np.unique(idx[:, 0] * shape[1] + idx[:, 1])) != len(x):
        return ax.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, c=damage, s=1, cmap="inferno_r")
    grid = np.full((shape[1], shape[0]), np.nan)
    grid[idx[:, 1], idx[:, 0]] = damage
    ext = [(lo[0] - dx / 2) * 1e3, (lo[0] + (shape[0] - 0.5) * dx) * 1e3]
    ext += [(lo[1] - dx / 2) * 1e3, (lo[1] + (shape[1] - 0.5) * dx) * 1e3]
    return ax.imshow(
        grid, origin="lower", extent=ext, cmap="inferno_r", vmin=0, vmax=1, interpolation="none"
    )


def plot(res: dict[str, Any], path: Path) -> None:
    """<case>.png: damage map, tip position, tip speed against the Rayleigh speeds."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t, pos, speed, x, damage, origin = res["_plot"]
    fig = plt.figure(figsize=(10, 7.6))
    gs = fig.add_gridspec(2, 2, height_ratios=[1.15, 1.0])
    ax = fig.add_subplot(gs[0, :])
    im = _damage_image(ax, x, damage, res["spacing_m"])
    fig.colorbar(im, ax=ax, label="damage", shrink=0.85)
    if res["branching_x_m"] is not None:
        ax.plot(res["branching_x_m"] * 1e3, origin[1] * 1e3, "c+", ms=12, mew=2)
    ax.plot(origin[0] * 1e3, origin[1] * 1e3, "c>", ms=7)
    ax.set(
        aspect="equal",
        xlabel="x (mm)",
        ylabel="y (mm)",
        title=(
            f"damage at t = {res['final_time_s'] * 1e6:.1f} us ({res['n_points']} points, "
            f"dx = {res['spacing_m'] * 1e3:g} mm, delta = {res['horizon_m'] * 1e3:g} mm); "
            "> pre-crack tip, + branching point"
        ),
    )
    ax.title.set_fontsize(9)
    a1, a2 = fig.add_subplot(gs[1, 0]), fig.add_subplot(gs[1, 1])
    a1.plot(t * 1e6, (origin[0] + pos) * 1e3, "-", lw=1.2, label="crack tip (damage >= 0.35)")
    if res["branching_x_m"] is not None:
        a1.axhline(res["branching_x_m"] * 1e3, color="C2", ls=":", label="branching x")
    if res["mean_crack_tip_speed_m_per_s"] is not None:
        w = (t >= res["mean_speed_window_s"][0]) & (t <= res["mean_speed_window_s"][1])
        fit = np.polyfit(t[w], pos[w], 1)
        label = f"mean {res['mean_crack_tip_speed_m_per_s']:.0f} m/s (12-40 us)"
        a1.plot(t[w] * 1e6, (origin[0] + np.polyval(fit, t[w])) * 1e3, "k--", lw=0.8, label=label)
    a1.set(xlabel="t (us)", ylabel="x of the crack tip (mm)", title="crack-tip position")
    a1.legend(fontsize=8)
    c_r, c_n = res["rayleigh_speed_compared_m_per_s"], res["rayleigh_speed_nominal_E_m_per_s"]
    c_e = res["rayleigh_speed_energy_ratio_m_per_s"]
    a2.plot(t * 1e6, speed, "-", lw=1.2, label="crack-tip speed (+-3 records)")
    ratio = res["modulus_ratio_static"] or res["modulus_ratio_energy"]
    label = f"Rayleigh speed, model as run ({ratio:.3f} E): {c_r:.0f} m/s"
    a2.axhline(c_r, color="C3", label=label)
    if abs(c_e - c_r) > 1e-6 * c_r:
        label = f"the same, energy ratio ({res['modulus_ratio_energy']:.3f} E): {c_e:.0f} m/s"
        a2.axhline(c_e, color="C1", ls=":", label=label)
    a2.axhline(c_n, color="C3", ls="--", label=f"Rayleigh speed, nominal E: {c_n:.0f} m/s")
    a2.set(xlabel="t (us)", ylabel="speed (m/s)", title="crack-tip speed", ylim=(0, 1.5 * c_n))
    a2.legend(fontsize=7.5, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path(f"results/{CASE}"))
    ap.add_argument("--set", action="append", default=[], help="deck override key=value")
    ap.add_argument("--no-run", action="store_true", help="re-analyse an existing run")
    ap.add_argument("--publish", action="store_true", help="copy the figure into " + str(HERE))
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    summary, speeds = run(args.out, list(args.set), args.no_run)
    res = analyse(args.out, summary, speeds)
    plot(res, args.out / f"{CASE}.png")
    res.pop("_plot")
    res["overrides"] = list(args.set)
    res["timing"] = summary.get("timing", {})
    res["script_wall_s"] = time.perf_counter() - t0
    (args.out / f"{CASE}.json").write_text(json.dumps(res, indent=2) + "\n")
    if args.publish:
        for name in (f"{CASE}.png", f"{CASE}.json"):
            shutil.copyfile(args.out / name, HERE / name)
    print(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
