"""Cost of one force evaluation per directed bond: correspondence (none, Silling 2017,
LBSCMM) against the PMB and LPS models on the same grid, side by side in one process.

Usage::

    python benchmarks/correspondence_step.py                 # 2-D 300 x 300, 3-D 40^3
    python benchmarks/correspondence_step.py --n2 200 --n3 30 --repeat 30 --json out.json

Each model's ``Evaluator.evaluate(state, commit=False)`` (pre-pass, force pass, and for PMB
the fused pure pass) is timed on a small random displacement, after a warm-up call;
the best of ``--repeat`` calls is kept. Prints seconds per evaluation, nanoseconds per
directed bond and the ratio to PMB, and the CPU model.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np


def _cpu() -> str:
    from _machine import cpu_model  # benchmarks/ is on sys.path when run as a script

    return cpu_model()


def _time(model: Any, repeat: int) -> float:
    s = model.new_state()
    s.u[...] = np.random.default_rng(0).normal(size=s.u.shape) * 1e-9
    model.evaluate(s, commit=False)
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        model.evaluate(s, commit=False)
        best = min(best, time.perf_counter() - t)
    return float(best)


def bench(dim: int, n: int, repeat: int) -> dict[str, Any]:
    from peridynamics.bonds.bonds import build_bonds
    from peridynamics.evaluation import Evaluator
    from peridynamics.families.correspondence.material import CorrespondenceMaterial
    from peridynamics.families.lps.material import LPSMaterial
    from peridynamics.families.pmb.material import BondBasedMaterial
    from peridynamics.geometry.generators import box, rectangle

    dx = 1e-3
    if dim == 2:
        cloud = rectangle((n * dx, n * dx), dx, thickness=dx)
    else:
        cloud = box((n * dx, n * dx, n * dx), dx)
    bonds = build_bonds(cloud, 3.015 * dx)
    E, rho = 70e9, 2700.0
    models = {
        "pmb": BondBasedMaterial(E, rho),
        "lps": LPSMaterial(E, 0.25, rho),
        "correspondence_none": CorrespondenceMaterial(E, 0.25, rho, "none"),
        "correspondence_silling2017": CorrespondenceMaterial(E, 0.25, rho, "silling2017"),
        "correspondence_lbscmm": CorrespondenceMaterial(E, 0.25, rho, "lbscmm"),
    }
    out: dict[str, Any] = {"dim": dim, "points": cloud.n_points, "bonds": bonds.n_bonds}
    for name, mat in models.items():
        sec = _time(Evaluator(cloud, bonds, mat), repeat)
        out[name] = {"s_per_eval": sec, "ns_per_bond": sec / bonds.n_bonds * 1e9}
    base = out["pmb"]["s_per_eval"]
    for name in models:
        out[name]["ratio_to_pmb"] = out[name]["s_per_eval"] / base
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--n2", type=int, default=300)
    p.add_argument("--n3", type=int, default=40)
    p.add_argument("--repeat", type=int, default=20)
    p.add_argument("--json", type=Path)
    args = p.parse_args(argv)
    import numba

    res = {
        "cpu": _cpu(),
        "threads": numba.get_num_threads(),
        "runs": [bench(2, args.n2, args.repeat), bench(3, args.n3, args.repeat)],
    }
    print(f"{res['cpu']}, {res['threads']} threads")
    for run in res["runs"]:
        print(f"{run['dim']}-D: {run['points']} points, {run['bonds']} directed bonds")
        for name, v in run.items():
            if isinstance(v, dict):
                print(
                    f"  {name:28s} {v['s_per_eval'] * 1e3:8.2f} ms  "
                    f"{v['ns_per_bond']:6.2f} ns/bond  {v['ratio_to_pmb']:5.2f} x PMB"
                )
    if args.json:
        args.json.write_text(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
