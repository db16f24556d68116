"""One command that measures the Warp backend against the Numba backend in one run.

    python benchmarks/gpu_measure.py                 # on a GPU machine: the issue's cases
    python benchmarks/gpu_measure.py --device cpu --sizes 2d:100,3d:16 --main-spacing 1e-3

For each case (a square / cube of points on a grid, dx = 1 mm, delta = 3.015 dx, PMB
with critical-stretch damage, the explicit step with velocity Verlet) it times the
whole step (the solver's ``step``: integrator, force-and-break pass, bond count read
back) and the force pass alone, on the Warp device and with the Numba kernels on all
cores of this machine, and reports directed bond updates per second (bonds of the full
list per step / seconds per step). Then it runs the main job (the README's deck,
``examples/crack_branching_2d/deck.yaml``) on both backends and compares the damage.
Writes ``gpu_measure.json`` (and prints a Markdown table) with the machine: CPU model,
cores, GPU name, Warp and Numba versions.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import cpu_model  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def _model(dim: int, n_side: int) -> Any:
    """The package benchmark's body (:func:`peridynamics.app.bench._model`) with
    critical-stretch damage (nothing breaks in the few steps timed: the kernels still
    test every bond)."""
    from peridynamics.app.bench import _model as bench_model
    from peridynamics.damage.critical_stretch import CriticalStretch

    return bench_model(dim, n_side, CriticalStretch(critical_stretch=0.01))


def _time_steps(solver: Any, state: Any, steps: int, sync: Any) -> float:
    """Seconds per step over ``steps`` steps after two warm-up steps."""
    for _ in range(2):
        solver.step(state)
    sync()
    t0 = time.perf_counter()
    for _ in range(steps):
        solver.step(state)
    sync()
    return (time.perf_counter() - t0) / steps


def measure_case(dim: int, n_side: int, steps: int, cpu_steps: int, device: str) -> dict:
    """Warp and Numba figures of one case (one model, built once)."""
    import warp as wp

    from peridynamics.backends.warp_solver import WarpExplicitSolver
    from peridynamics.solvers import ExplicitSolver

    t0 = time.perf_counter()
    model = _model(dim, n_side)
    setup = time.perf_counter() - t0
    n_bonds = int(model.bonds.n_bonds)
    rng = np.random.default_rng(0)
    out: dict[str, Any] = {"dim": dim, "points": model.n_points, "bonds": n_bonds,
                           "setup_s": setup}  # fmt: skip
    # Warp: the whole step, then the force pass alone
    ws = WarpExplicitSolver(model, device=device, check_every=10**9)
    state = ws.init()
    ds = ws.ds
    wp.copy(ds.v, wp.array(rng.normal(scale=1e-3, size=(model.n_points, dim)),
                           dtype=wp.float64, device=ws.device_name))  # fmt: skip

    name = ws.device_name

    def sync() -> None:
        wp.synchronize_device(name)

    step_s = _time_steps(ws, state, steps, sync)
    fam = ws.family
    fam.evaluate(ds, True)
    sync()
    t0 = time.perf_counter()
    for _ in range(steps):
        fam.evaluate(ds, True)
    sync()
    force_s = (time.perf_counter() - t0) / steps
    out.update(
        warp_device=ws.device_name,
        warp_seconds_per_step=step_s,
        warp_bond_updates_per_s=n_bonds / step_s,
        warp_force_pass_s=force_s,
        warp_force_pass_bond_updates_per_s=n_bonds / force_s,
    )
    del ws, state, ds
    # Numba on this machine's cores, same model
    cs = ExplicitSolver(model, check_every=10**9)
    cstate = cs.init()
    cstate.v[:] = rng.normal(scale=1e-3, size=cstate.v.shape)
    cpu_s = _time_steps(cs, cstate, cpu_steps, lambda: None)
    out.update(
        numba_seconds_per_step=cpu_s,
        numba_bond_updates_per_s=n_bonds / cpu_s,
        speedup=cpu_s / step_s,
    )
    return out


def main_job(spacing: float | None, device: str) -> dict:
    """The README's main job on both backends: wall times and the damage compared."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    deck_path = ROOT / "examples" / "crack_branching_2d" / "deck.yaml"
    over = ["output.plot=none"]
    if spacing is not None:
        over.append(f"discretisation.spacing={spacing}")
    out: dict[str, Any] = {"deck": str(deck_path.relative_to(ROOT)), "overrides": over}
    runs = {}
    with tempfile.TemporaryDirectory() as tmp:
        for backend, extra in (("numba", []), ("warp", ["solver.backend=warp",
                                                       f"solver.device={device}"])):  # fmt: skip
            deck = load_deck(deck_path, overrides=over + extra)
            t0 = time.perf_counter()
            summary = Simulation.from_deck(deck).run(Path(tmp) / backend, quiet=True)
            total = time.perf_counter() - t0
            data = np.load(Path(tmp) / backend / "final_state.npz")
            runs[backend] = (summary, data["damage"], data["intact"], total)
    (sn, dn, inn, tn), (sw, dw, inw, tw) = runs["numba"], runs["warp"]
    out.update(
        points=int(len(dn)),
        steps=int(sn["timing"]["steps"]),
        numba_loop_s=sn["timing"]["wall_s"],
        warp_loop_s=sw["timing"]["wall_s"],
        numba_total_s=tn,
        warp_total_s=tw,
        loop_speedup=sn["timing"]["wall_s"] / sw["timing"]["wall_s"],
        bonds_broken_numba=sn["results"]["bonds_broken"],
        bonds_broken_warp=sw["results"]["bonds_broken"],
        bond_flags_differing=int(np.count_nonzero(inn != inw)),
        max_damage_difference=float(np.abs(dn - dw).max()),
        crack_length_numba_m=sn["results"].get("crack_length_m"),
        crack_length_warp_m=sw["results"].get("crack_length_m"),
        device_to_host_bytes=sw["results"].get("device_to_host_bytes"),
    )
    return out


def machine(device: str) -> dict:
    """What this ran on."""
    import numba
    import warp as wp

    from peridynamics.backends.warp_device import pick_device

    name = pick_device(device)
    dev = wp.get_device(name)
    return {
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "numba_threads": numba.get_num_threads(),
        "device": name,
        "device_name": getattr(dev, "name", name),
        "warp": wp.config.version,
        "numba": numba.__version__,
        "python": platform.python_version(),
        "date": time.strftime("%Y-%m-%d %H:%M:%S"),
    }


def _table(res: dict) -> str:
    lines = [
        "| case | points | directed bonds | Warp step (s) | Warp bond upd/s | Warp force pass "
        "upd/s | Numba step (s) | Numba bond upd/s | Warp / Numba |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for c in res["cases"]:
        lines.append(
            f"| {c['dim']}-D | {c['points']:,} | {c['bonds']:,} | "
            f"{c['warp_seconds_per_step']:.4g} | {c['warp_bond_updates_per_s']:.3g} | "
            f"{c['warp_force_pass_bond_updates_per_s']:.3g} | "
            f"{c['numba_seconds_per_step']:.4g} | {c['numba_bond_updates_per_s']:.3g} | "
            f"{c['speedup']:.1f}x |"
        )
    mj = res.get("main_job")
    if mj:
        lines.append("")
        lines.append(
            f"main job ({mj['points']:,} points, {mj['steps']} steps): time loop Numba "
            f"{mj['numba_loop_s']:.2f} s, Warp {mj['warp_loop_s']:.2f} s "
            f"({mj['loop_speedup']:.2f}x); bond flags differing: "
            f"{mj['bond_flags_differing']}, max damage difference "
            f"{mj['max_damage_difference']:.3g}"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--device", default="auto", choices=["auto", "cuda", "cpu"])
    p.add_argument("--sizes", default="2d:2000,3d:100",
                   help="cases as DIMd:POINTS_PER_SIDE, comma-separated")  # fmt: skip
    p.add_argument("--steps", type=int, default=50, help="timed Warp steps per case")
    p.add_argument("--cpu-steps", type=int, default=5, help="timed Numba steps per case")
    p.add_argument("--main-spacing", type=float, default=None,
                   help="main job spacing (m); default the deck's (2.5e-4)")  # fmt: skip
    p.add_argument("--no-main-job", action="store_true")
    p.add_argument("--out", default="gpu_measure.json")
    a = p.parse_args(argv)
    res: dict[str, Any] = {"machine": machine(a.device), "cases": []}
    print(json.dumps(res["machine"], indent=1), flush=True)
    for item in a.sizes.split(","):
        dim_s, n_s = item.split(":")
        case = measure_case(int(dim_s.rstrip("dD")), int(n_s), a.steps, a.cpu_steps, a.device)
        res["cases"].append(case)
        print(json.dumps(case), flush=True)
    if not a.no_main_job:
        res["main_job"] = main_job(a.main_spacing, a.device)
        print(json.dumps(res["main_job"]), flush=True)
    Path(a.out).write_text(json.dumps(res, indent=1))
    print(_table(res))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
