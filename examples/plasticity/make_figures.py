"""Figures and measured numbers of the elastic-plastic examples: the cyclic J2
correspondence bar (``bar_cyclic.yaml``) against Prager's closed-form loop of linear
kinematic hardening, and (``--case lps``) the elastic-plastic LPS bar (``lps_bar.yaml``)
against the closed-form uniaxial J2 response with isotropic hardening
(docs/theory_plasticity.md).

Usage::

    python examples/plasticity/make_figures.py                     # bar_cyclic.png/.json here
    python examples/plasticity/make_figures.py --out /tmp/plastic --load-steps 8 \
        --length 0.012                                             # a quick, small run
    python examples/plasticity/make_figures.py --case lps          # lps_bar.png/.json here

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


def isotropic(strains: np.ndarray, e: float, sy: float, h: float) -> np.ndarray:
    """Uniaxial stress of J2 with linear isotropic hardening along a strain path (the
    1-D return map: yield radius sy + H alpha, hardening slope E H / (E + H))."""
    sig, prev, alpha, out = 0.0, 0.0, 0.0, []
    for ex in strains:
        trial = sig + e * (ex - prev)
        f = abs(trial) - (sy + h * alpha)
        if f > 0:
            d = f / (e + h)
            alpha += d
            trial -= np.sign(trial) * e * d
        sig, prev = trial, ex
        out.append(sig)
    return np.array(out)


def lps_bar(args: argparse.Namespace) -> dict:
    """The LPS bar (``lps_bar.yaml``): axial strain between two inner sections of points
    (a third of the layers in from either end: 6.5 and 13.5 mm) and the axial stress
    from the reaction of the pulled end layer, per ADR load step, against
    :func:`isotropic`."""
    deck = yaml.safe_load((HERE / "lps_bar.yaml").read_text())
    dx = deck["discretisation"]["spacing"]
    if args.load_steps is not None:
        deck["solver"]["load_steps"] = args.load_steps
    if args.length is not None:
        deck["geometry"]["size"][0] = args.length
        deck["node_sets"]["right"]["box"]["min"][0] = args.length - dx
        deck["boundary_conditions"][1]["components"]["x"] = 3e-3 * (args.length - dx)
    length, side = deck["geometry"]["size"][0], deck["geometry"]["size"][1]
    m, plast = deck["material"], deck["material"]["plasticity"]
    e, sy, h = (
        float(m["youngs_modulus"]),
        float(plast["yield_stress"]),
        float(plast["hardening_modulus"]),
    )
    sim = Simulation.from_deck(parse_deck(deck))
    x, vol = sim.model.cloud.x[:, 0], sim.model.cloud.volume
    layers = np.unique(np.round(x / (1e-3 * dx)) * (1e-3 * dx))
    xa, xb = layers[len(layers) // 3], layers[len(layers) - 1 - len(layers) // 3]
    a, b, right = np.abs(x - xa) < 1e-4 * dx, np.abs(x - xb) < 1e-4 * dx, x > length - dx
    s = sim.solver.init()
    eps, sig, t0 = [0.0], [0.0], time.perf_counter()
    while not sim.solver.done(s):
        if not sim.solver.step(s).converged:
            raise RuntimeError(f"load step {s.step} did not converge")
        eps.append(float((s.u[b, 0].mean() - s.u[a, 0].mean()) / (xb - xa)))
        sig.append(float(-(s.force[right, 0] * vol[right]).sum() / side**2))
    ep, sg = np.array(eps), np.array(sig)
    k = int(np.argmax(ep))
    et = e * h / (e + h)
    slope = np.diff(sg) / np.diff(ep)
    e_bar = slope[0]  # the first step is elastic
    hard = slope[k - 1]  # the last loading step is plastic
    # yield: where the elastic line meets the line through the last two plastic states
    eps_y = (sg[k] - hard * ep[k]) / (e_bar - hard)
    result = {
        "load_steps": len(ep) - 1,
        "elastic_slope_over_E": float(e_bar / e),
        "yield_stress_over_sigma_y": float(e_bar * eps_y / sy),
        "hardening_slope_over_closed_form": float(hard / et),
        "unloading_slope_over_E": float(slope[k] / e),
        "max_relative_error": float(np.max(np.abs(sg[1:] - isotropic(ep, e, sy, h)[1:]) / sy)),
        "seconds": time.perf_counter() - t0,
        "strain": eps,
        "stress_MPa": [v / 1e6 for v in sig],
    }
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "lps_bar.json").write_text(json.dumps(result, indent=1))
    fig, ax = _axes()
    dense = np.interp(np.linspace(0, len(ep) - 1, 20 * len(ep)), np.arange(len(ep)), ep)
    ax.plot(1e3 * dense, isotropic(dense, e, sy, h) / 1e6, "k-", lw=1, label="closed form (J2)")
    ax.plot(1e3 * ep, sg / 1e6, "o", ms=4, mfc="none", label="elastic-plastic LPS bar, ADR")
    _save(fig, ax, args.out / "lps_bar.png")
    return result


def _axes():  # noqa: ANN202
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt.subplots(figsize=(5.0, 3.8))


def _save(fig, ax, path: Path) -> None:  # noqa: ANN001
    import matplotlib.pyplot as plt

    ax.set_xlabel("axial strain (1e-3)")
    ax.set_ylabel("axial stress (MPa)")
    ax.legend(loc="lower center", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--case", choices=("cyclic", "lps"), default="cyclic")
    ap.add_argument("--load-steps", type=int, default=None)
    ap.add_argument("--length", type=float, default=None, help="bar length (m)")
    args = ap.parse_args(argv)
    if args.case == "lps":
        return lps_bar(args)
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
