"""Figure and measured numbers of the elastic-plastic correspondence example: the cyclic
J2 bar (``bar_cyclic.yaml``) against Prager's closed-form loop of linear kinematic
hardening (docs/theory_plasticity.md).

Usage::

    python examples/plasticity/make_figures.py                     # bar_cyclic.png/.json here
    python examples/plasticity/make_figures.py --out /tmp/plastic --load-steps 8 \
        --length 0.012                                             # a quick, small run

The deck is run load step by load step through the Python API (ADR; the plastic history
committed on each accepted step); after each step the mean axial Cauchy stress and the
mean axial strain F_xx - 1 of the middle points (within 1.6 mm of the middle) are
recorded and compared with the closed form at that strain.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import yaml

from peridynamics.app.run import Simulation
from peridynamics.deck import parse_deck

HERE = Path(__file__).resolve().parent


def prager(strains: np.ndarray, e: float, sy: float, h_kin: float) -> np.ndarray:
    """Uniaxial stress of linear kinematic hardening along a strain path: slope E
    between the lines sigma = Et eps +- sy (1 - Et/E), Et = E H / (E + H)."""
    et = e * h_kin / (e + h_kin)
    band = sy * (1.0 - et / e)
    sig, prev, out = 0.0, 0.0, []
    for ex in strains:
        sig = min(max(sig + e * (ex - prev), et * ex - band), et * ex + band)
        prev = ex
        out.append(sig)
    return np.array(out)


def run(deck: dict, mid_half_width: float = 1.6e-3) -> dict[str, list[float]]:
    """Step the deck's solver; the mean axial strain and stress of the middle points."""
    sim = Simulation.from_deck(parse_deck(deck))
    fm = sim.model.force_model
    s = sim.solver.init()
    x = sim.model.cloud.x[:, 0]
    mid = np.abs(x - 0.5 * (x.min() + x.max())) < mid_half_width
    rec: dict[str, list[float]] = {"strain": [0.0], "stress": [0.0], "lateral": [0.0]}
    t0 = time.perf_counter()
    while not sim.solver.done(s):
        if not sim.solver.step(s).converged:
            raise RuntimeError(f"load step {s.step} did not converge")
        f = s["deformation_gradient"].reshape(-1, 3, 3)
        sig = fm.point_stress(s)
        rec["strain"].append(float(f[mid, 0, 0].mean() - 1.0))
        rec["stress"].append(float(sig[mid, 0, 0].mean()))
        rec["lateral"].append(float(np.abs(sig[mid, 1, 1]).max()))
    rec["seconds"] = [time.perf_counter() - t0]
    return rec


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--load-steps", type=int, default=None)
    ap.add_argument("--length", type=float, default=None, help="bar length (m)")
    args = ap.parse_args(argv)
    deck = yaml.safe_load((HERE / "bar_cyclic.yaml").read_text())
    if args.load_steps is not None:
        deck["solver"]["load_steps"] = args.load_steps
    if args.length is not None:
        dx = deck["discretisation"]["spacing"]
        length = args.length
        deck["geometry"]["size"][0] = length
        deck["node_sets"]["right"]["box"]["min"][0] = length - dx
        deck["boundary_conditions"][1]["components"]["x"] = 3e-3 * (length - dx)
    m = deck["material"]
    plast = m["plasticity"]
    e, sy = float(m["youngs_modulus"]), float(plast["yield_stress"])
    h = float(plast["kinematic_modulus"])
    rec = run(deck)
    eps = np.array(rec["strain"])
    sig = np.array(rec["stress"])
    want = prager(eps, e, sy, h)
    plastic = np.abs(want) > sy
    result = {
        "load_steps": len(eps) - 1,
        "max_relative_error": float(np.max(np.abs(sig[1:] - want[1:]) / np.abs(want[1:]).clip(sy))),
        "max_relative_error_plastic": float(
            np.max(np.abs(sig[plastic] - want[plastic]) / np.abs(want[plastic]))
        ) if plastic.any() else None,
        "max_lateral_over_yield": float(max(rec["lateral"]) / sy),
        "seconds": rec["seconds"][0],
        "strain": rec["strain"],
        "stress_MPa": [v / 1e6 for v in rec["stress"]],
    }  # fmt: skip
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "bar_cyclic.json").write_text(json.dumps(result, indent=1))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.0, 3.8))
    dense = np.interp(np.linspace(0, len(eps) - 1, 20 * len(eps)), np.arange(len(eps)), eps)
    ax.plot(1e3 * dense, prager(dense, e, sy, h) / 1e6, "k-", lw=1, label="closed form (Prager)")
    ax.plot(1e3 * eps, sig / 1e6, "o", ms=4, mfc="none", label="correspondence bar, ADR")
    ax.set_xlabel("axial strain (1e-3)")
    ax.set_ylabel("axial stress (MPa)")
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.out / "bar_cyclic.png", dpi=120)
    plt.close(fig)
    return result


if __name__ == "__main__":
    r = main()
    print({k: v for k, v in r.items() if k not in ("strain", "stress_MPa")})
