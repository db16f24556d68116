"""Kalthoff-Winkler refinement study: run the deck at several spacings, extract the crack
paths and measure the initial crack angle, the path length and the tip speed.

Usage (from the repository root)::

    python examples/kalthoff_winkler/refinement.py                       # 2.5, 1.25, 0.625 mm
    python examples/kalthoff_winkler/refinement.py --spacings 2.5e-3     # one coarse run
    python examples/kalthoff_winkler/refinement.py --out results/kw_16 \
        --set 'boundary_conditions.0.components={x: 16.5}'

Each run goes through ``peridynamics.app.run.Simulation`` into ``OUT/dx_<mm>``; the
paths come from ``final_state.npz`` (damage) and the cloud of ``build_cloud(deck)``
(reference positions), with ``peridynamics.analysis.crack_path``. Damage frames every
``--frame-interval`` seconds give the path-length history and the tip speed. Writes
``OUT/refinement.json`` and ``OUT/refinement_paths.png``.

Measured quantities, per notch (upper: tip (50, 25) mm; lower: (50, -25) mm):

* the crack is the damaged cluster (damage >= 0.35, points damaged at t = 0 by the
  notches excluded) grown from the notch tip, restricted to the far side of the notch
  line (y >= 25 mm for the upper notch), where the Kalthoff-Winkler crack runs; the
  cracks of both tips are extracted together, so a crack joining them is split;
* the initial angle: the chord from the notch tip to the point of the path at arc length
  ``--initial-length`` (default 20 mm), from the notch direction (+x); the lower crack's
  angle is reported with its sign flipped (mirror image);
* the path length and the tip speed from the length history, flagged above the Rayleigh
  speed of the model as run (bond-based PMB, plane stress, nu = 1/3);
* for comparison, the old tip: the farthest damaged point from the notch tip
  (``peridynamics.analysis.crack.crack_tip``) and its speed.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.analysis.crack import crack_tip, tip_speed
from peridynamics.analysis.crack_path import extract_crack_paths
from peridynamics.analysis.crack_polyline import CrackPath
from peridynamics.analysis.crack_speed import rayleigh_speed, tip_speed_from_paths
from peridynamics.app.run import Simulation
from peridynamics.build.cloud import build_cloud
from peridynamics.deck import RectangleGeometry, load_deck
from peridynamics.solvers.explicit import ExplicitSolver

HERE = Path(__file__).resolve().parent
DECK = HERE / "deck.yaml"
SPACINGS = (2.5e-3, 1.25e-3, 6.25e-4)
NOTCH_TIPS = (np.array([0.05, 0.025]), np.array([0.05, -0.025]))  # m
THRESHOLD = 0.35
EXPERIMENT_DEG = 70.0  # Kalthoff & Winkler (1988); Kalthoff (2000)
ANGLE_LENGTHS = (0.005, 0.01, 0.02, 0.03)  # m, extra chord lengths reported


def machine() -> dict[str, Any]:
    """CPU model and core count of this machine (``lscpu`` where there is one), versions."""
    model = platform.processor() or platform.machine()
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
    except (OSError, subprocess.CalledProcessError):
        pass
    from peridynamics import __version__

    info = {
        "cpu": model,
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "peridynamics": __version__,
    }
    try:  # the commit the working tree started from (read only)
        head = subprocess.run(
            ["git", "rev-parse", "HEAD"], capture_output=True, text=True, check=True, cwd=HERE
        )
        info["commit"] = head.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        pass
    return info


def _frames(out: Path, name: str) -> list[tuple[float, Path]]:
    """(time s, .vtu path) of every frame of the run's ParaView series."""
    root = ET.parse(out / f"{name}.pvd").getroot()
    return sorted(
        (float(ds.attrib["timestep"]), out / ds.attrib["file"]) for ds in root.iter("DataSet")
    )


def _vtu_damage(path: Path) -> NDArray[np.float64]:
    import meshio

    return np.asarray(meshio.read(path).point_data["damage"], dtype=np.float64).reshape(-1)


def paths_of(
    x: NDArray[np.float64],
    damage: NDArray[np.float64],
    pre: NDArray[np.bool_],
    dx: float,
    initial_length: float,
) -> list[CrackPath]:
    """The upper and lower notch cracks of one damage field (see the module docstring).

    Parameters
    ----------
    x : ndarray, shape (n, 2)
        Reference positions, m.
    damage : ndarray, shape (n,)
        Point damage.
    pre : ndarray of bool, shape (n,)
        Points damaged (>= threshold) by the notches at t = 0.
    dx : float
        Spacing, m.
    initial_length : float
        Arc length of the initial chord, m.
    """
    far_side = (x[:, 1] >= NOTCH_TIPS[0][1]) | (x[:, 1] <= NOTCH_TIPS[1][1])
    return extract_crack_paths(
        x,
        damage,
        list(NOTCH_TIPS),
        dx,
        THRESHOLD,
        exclude=pre,
        within=far_side,
        initial_length=initial_length,
        reference_direction=[1.0, 0.0],
    )


def _chord_angle(v: NDArray[np.float64], s: float) -> float:
    """Angle (deg, from +x) of the chord from a polyline's first vertex to its point at
    arc length ``s`` (m)."""
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(v, axis=0), axis=1))])
    end = np.array([np.interp(min(s, arc[-1]), arc, v[:, j]) for j in range(2)])
    d = end - v[0]
    return float(np.degrees(np.arctan2(d[1], d[0])))


def _crack_summary(p: CrackPath, sign: float) -> dict[str, Any]:
    return {
        "initial_angle_deg": sign * p.initial_angle_deg,
        "initial_length_m": p.initial_length,
        "angle_over_deg": {f"{s * 1e3:g}mm": sign * p.angle_over(s) for s in ANGLE_LENGTHS},
        "length_m": p.length,
        "tip_m": p.tip.tolist(),
        "n_branches": p.n_branches,
        "branch_lengths_m": p.branch_lengths.tolist(),
        "vertices_m": p.vertices.tolist(),
        "branches_m": [b.tolist() for b in p.branches[1:]],
    }


def run_one(
    dx: float,
    out: Path,
    overrides: list[str],
    frame_interval: float,
    initial_length: float,
    keep_frames: bool = False,
) -> dict[str, Any]:
    """Run the deck at spacing ``dx`` (m) into ``out`` and measure its cracks."""
    sets = [f"discretisation.spacing={dx!r}", "output.fields=[damage]", *overrides]
    probe = Simulation.from_deck(load_deck(DECK, [*sets, "output.vtk_every=1"]))
    assert isinstance(probe.solver, ExplicitSolver)
    every = max(1, round(frame_interval / probe.solver.dt))
    deck = load_deck(DECK, [*sets, f"output.vtk_every={every}"])
    sim = Simulation.from_deck(deck)
    if out.exists():
        shutil.rmtree(out)
    t0 = time.perf_counter()
    summary = sim.run(out, quiet=True, progress=False)
    wall = time.perf_counter() - t0

    x = build_cloud(deck).x
    pre = sim.model.point_damage(sim.model.bonds.bond_intact) >= THRESHOLD
    final = np.load(out / "final_state.npz")
    up, lo = paths_of(x, final["damage"], pre, dx, initial_length)
    # every crack leaving the upper notch tip, on both sides of the notch line
    free = extract_crack_paths(
        x,
        final["damage"],
        list(NOTCH_TIPS),
        dx,
        THRESHOLD,
        exclude=pre,
        initial_length=initial_length,
    )[0]

    mat = deck.material
    geo = deck.geometry
    assert isinstance(geo, RectangleGeometry)
    c_r = rayleigh_speed(mat.youngs_modulus, None, mat.density, geo.plane)
    times, lengths, old = [], [], []
    for t, f in _frames(out, deck.name):  # over frames
        dmg = _vtu_damage(f)
        pu, pl = paths_of(x, dmg, pre, dx, initial_length)
        times.append(t)
        lengths.append([pu.length, pl.length])
        old.append(crack_tip(x, dmg, NOTCH_TIPS[0], None, THRESHOLD, pre))
        if not keep_frames:
            f.unlink()
    t_arr, l_arr = np.array(times), np.array(lengths)
    speeds, flags = [], []
    for j in range(2):
        v, fl = tip_speed_from_paths(t_arr, l_arr[:, j], rayleigh_speed=c_r, window=5)
        speeds.append(v)
        flags.append(fl)
    v_old = tip_speed(t_arr, np.array(old))
    grew = l_arr[:, 0] > 0
    res = summary["results"]
    rec: dict[str, Any] = {
        "spacing_m": dx,
        "horizon_m": res["horizon_m"],
        "n_points": res["n_points"],
        "n_bonds": res["n_bonds"],
        "steps": res["steps"],
        "time_step_s": res.get("time_step_s"),
        "final_time_s": res["final_time_s"],
        "wall_s": wall,
        "loop_wall_s": summary["timing"]["wall_s"],
        "setup_s": summary["timing"]["setup_s"],
        "overrides": overrides,
        "rayleigh_speed_m_per_s": c_r,
        "upper": _crack_summary(up, 1.0),
        "lower": _crack_summary(lo, -1.0),
        "upper_both_sides": {
            "n_branches": free.n_branches,
            "branch_lengths_m": free.branch_lengths.tolist(),
            "branch_initial_angles_deg": [_chord_angle(b, initial_length) for b in free.branches],
        },
        "initiation_time_s": float(t_arr[grew][0]) if grew.any() else None,
        "history": {
            "time_s": t_arr.tolist(),
            "length_upper_m": l_arr[:, 0].tolist(),
            "length_lower_m": l_arr[:, 1].tolist(),
            "speed_upper_m_per_s": speeds[0].tolist(),
            "speed_lower_m_per_s": speeds[1].tolist(),
            "old_tip_distance_m": old,
        },
        "max_speed_m_per_s": float(max(speeds[0].max(), speeds[1].max())),
        "records_above_rayleigh": int(flags[0].sum() + flags[1].sum()),
        "old_tip_max_speed_m_per_s": float(v_old.max()),
    }
    return rec


def plot(report: dict[str, Any], path: Path, out: Path) -> None:
    """Crack paths of every resolution (over the finest run's final damage), the path
    length histories and the tip speeds."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = report["runs"]
    fig, ax = plt.subplots(1, 3, figsize=(15, 6.5), gridspec_kw={"width_ratios": [1, 1.2, 1.2]})
    finest = min(runs, key=lambda r: r["spacing_m"])
    fin_dir = out / _dirname(finest["spacing_m"])
    deck = load_deck(
        DECK, [f"discretisation.spacing={finest['spacing_m']!r}", *finest["overrides"]]
    )
    x = build_cloud(deck).x
    dmg = np.load(fin_dir / "final_state.npz")["damage"]
    sc = ax[0].scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, c=dmg, s=0.3, cmap="Greys", vmin=0, vmax=1)
    fig.colorbar(sc, ax=ax[0], shrink=0.6, label=f"damage (dx = {finest['spacing_m'] * 1e3:g} mm)")
    colours = plt.get_cmap("viridis")(np.linspace(0.0, 0.85, len(runs)))
    for r, c in zip(runs, colours, strict=True):
        lab = f"dx = {r['spacing_m'] * 1e3:g} mm: {r['upper']['initial_angle_deg']:.1f} deg"
        for side in ("upper", "lower"):
            v = np.array(r[side]["vertices_m"]) * 1e3
            ax[0].plot(v[:, 0], v[:, 1], "-", color=c, lw=2, label=lab if side == "upper" else None)
            for b in r[side]["branches_m"]:
                b = np.array(b) * 1e3
                ax[0].plot(b[:, 0], b[:, 1], ":", color=c, lw=1.2)
        h = r["history"]
        t = np.array(h["time_s"]) * 1e6
        ax[1].plot(t, np.array(h["length_upper_m"]) * 1e3, "-", color=c, label=lab.split(":")[0])
        ax[1].plot(t, np.array(h["old_tip_distance_m"]) * 1e3, "--", color=c, lw=0.8)
        ax[2].plot(t, h["speed_upper_m_per_s"], "-", color=c, label=lab.split(":")[0])
    ang = np.radians(EXPERIMENT_DEG)
    for s in (1.0, -1.0):
        tip = NOTCH_TIPS[0] * [1, s] * 1e3
        end = tip + 30.0 * np.array([np.cos(ang), s * np.sin(ang)])
        exp_lab = "70 deg (experiment)" if s > 0 else None
        ax[0].plot([tip[0], end[0]], [tip[1], end[1]], "r--", lw=1, label=exp_lab)
    ax[0].set(xlabel="x (mm)", ylabel="y (mm)", title="crack paths (dotted: branches)")
    ax[0].set_aspect("equal")
    ax[0].legend(fontsize=7, loc="center left")
    ax[1].set(xlabel="t (us)", ylabel="mm", title="upper crack: path (solid), old tip (dashed)")
    ax[1].legend(fontsize=8)
    c_r = runs[0]["rayleigh_speed_m_per_s"]
    ax[2].axhline(c_r, color="r", ls="--", lw=1, label=f"c_R = {c_r:.0f} m/s")
    ax[2].set(xlabel="t (us)", ylabel="m/s", title="upper crack: tip speed from the path")
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _dirname(dx: float) -> str:
    return f"dx_{dx * 1e3:g}mm"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--spacings",
        type=float,
        nargs="+",
        default=list(SPACINGS),
        help="grid spacings, m (125 mm / dx must be a whole number)",
    )
    ap.add_argument("--out", type=Path, default=Path("results/kalthoff_winkler_refinement"))
    ap.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="deck override, as peridynamics run --set",
    )
    ap.add_argument("--frame-interval", type=float, default=2.0e-6, help="s between frames")
    ap.add_argument("--initial-length", type=float, default=0.02, help="m (initial chord)")
    ap.add_argument("--keep-frames", action="store_true", help="keep the VTK frames")
    args = ap.parse_args(argv)
    for dx in args.spacings:
        n = 0.125 / dx
        if abs(n - round(n)) > 1e-6 * n:
            ap.error(f"spacing {dx}: 125 mm / dx must be a whole number (no point on a notch)")
    args.out.mkdir(parents=True, exist_ok=True)
    runs = []
    for dx in sorted(args.spacings, reverse=True):
        r = run_one(
            dx,
            args.out / _dirname(dx),
            args.overrides,
            args.frame_interval,
            args.initial_length,
            args.keep_frames,
        )
        runs.append(r)
        print(
            f"dx = {dx * 1e3:g} mm: {r['n_points']} points, {r['steps']} steps, "
            f"{r['wall_s']:.1f} s; initial angle upper {r['upper']['initial_angle_deg']:.1f}, "
            f"lower {r['lower']['initial_angle_deg']:.1f} deg; length "
            f"{r['upper']['length_m'] * 1e3:.1f} mm; branches {r['upper']['n_branches']}; "
            f"max tip speed {r['max_speed_m_per_s']:.0f} m/s "
            f"(c_R {r['rayleigh_speed_m_per_s']:.0f}); "
            f"old tip {r['old_tip_max_speed_m_per_s']:.0f} m/s",
            flush=True,
        )
    report = {
        "deck": str(DECK.relative_to(HERE.parents[1])),
        "machine": machine(),
        "experiment_angle_deg": EXPERIMENT_DEG,
        "initial_length_m": args.initial_length,
        "threshold": THRESHOLD,
        "runs": runs,
    }
    (args.out / "refinement.json").write_text(json.dumps(report, indent=1))
    plot(report, args.out / "refinement_paths.png", args.out)
    print(f"wrote {args.out / 'refinement.json'} and {args.out / 'refinement_paths.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
