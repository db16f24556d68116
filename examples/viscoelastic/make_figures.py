"""Figure and measured numbers of the viscoelastic LPS example: the bar of
``bar_relaxation.yaml`` in stress relaxation and (the same bar under a held 1 MPa
traction) in creep, against the standard linear solid (docs/theory_viscoelasticity.md).

Usage::

    python examples/viscoelastic/make_figures.py                 # bar_sls.png/.json here
    python examples/viscoelastic/make_figures.py --out /tmp/ve --load-steps 4   # quick

Every run steps the deck's ADR solver load step by load step through the Python API.
The axial strain is the slope of the mean axial displacement between the grid layers
nearest 3 mm either side of the middle, the axial stress the reaction of the pulled end layer over
the cross-section. The analytic standard linear solid uses the bar's instantaneous and
relaxed Young's moduli E0, Einf, measured by two elastic runs of the same deck (fraction
0, shear modulus mu and (1 - fraction) mu at the same bulk modulus), so the comparison
tests the time integration and not the static accuracy of the discretisation:
E(t) = Einf + (E0 - Einf) exp(-c t), c = (1 - fraction) E0 / (Einf tau), and
J(t) = 1/Einf + (1/E0 - 1/Einf) exp(-a t), a = (1 - fraction) / tau, each convolved
with the load ramp of the first load step.
"""

from __future__ import annotations

import argparse
import copy
import json
import time
from pathlib import Path

import numpy as np
import yaml

from peridynamics.app.run import Simulation
from peridynamics.deck import parse_deck

HERE = Path(__file__).resolve().parent
TRACTION = 1.0e6  # Pa, the creep load


def run(deck: dict) -> np.ndarray:
    """(t, axial strain, axial stress) after every load step of ``deck``."""
    sim = Simulation.from_deck(parse_deck(deck))
    x, vol = sim.model.cloud.x, sim.model.cloud.volume
    lo, hi = x[:, 0].min(), x[:, 0].max()
    mid = 0.5 * (lo + hi)
    side = float(deck["geometry"]["size"][1])  # square cross-section
    layer_a = x[np.argmin(np.abs(x[:, 0] - (mid - 3e-3))), 0]  # the grid layers nearest
    layer_b = x[np.argmin(np.abs(x[:, 0] - (mid + 3e-3))), 0]  # mid -/+ 3 mm
    a = np.abs(x[:, 0] - layer_a) < 1e-6
    b = np.abs(x[:, 0] - layer_b) < 1e-6
    right = x[:, 0] > hi - 1e-4
    s = sim.solver.init()
    rows = []
    while not sim.solver.done(s):
        if not sim.solver.step(s).converged:
            raise RuntimeError(f"load step {s.step} did not converge")
        eps = (s.u[b, 0].mean() - s.u[a, 0].mean()) / (x[b, 0].mean() - x[a, 0].mean())
        rows.append((s.t, eps, -(s.force[right, 0] * vol[right]).sum() / side**2))
    return np.array(rows)


def variant(deck: dict, steps: int, fraction: float | None = None, shear_scale: float = 1.0,
            creep: bool = False) -> dict:  # fmt: skip
    """The deck with ``steps`` load steps (the ramp over the first), optionally another
    fraction, a scaled shear modulus at the same bulk modulus, or the creep load."""
    d = copy.deepcopy(deck)
    m = d["material"]
    e, nu = float(m["youngs_modulus"]), float(m["poisson_ratio"])
    k, g = e / (3 * (1 - 2 * nu)), shear_scale * e / (2 * (1 + nu))
    m["youngs_modulus"] = 9 * k * g / (3 * k + g)
    m["poisson_ratio"] = (3 * k - 2 * g) / (2 * (3 * k + g))
    if fraction is not None:
        m["viscoelastic"]["fraction"] = fraction
    d["solver"]["load_steps"] = steps
    tf = (
        {"type": "table", "times": [0.0, 1.0 / steps, 1.0], "values": [0.0, 1.0, 1.0]}
        if steps > 1
        else {"type": "table", "times": [0.0, 1.0], "values": [0.0, 1.0]}
    )
    bc = d["boundary_conditions"][1]
    bc["time_function"] = tf
    if creep:
        d["boundary_conditions"][1] = {
            "type": "traction",
            "set": bc["set"],
            "value": [TRACTION, 0.0, 0.0],
            "time_function": tf,
        }
    return d


def ramp(t: np.ndarray, t1: float, start: float, end: float, rate: float) -> np.ndarray:
    """Response to a unit input ramped over [0, t1] then held, of a standard linear solid
    whose step response is ``end + (start - end) exp(-rate t)``."""
    tm = np.minimum(t, t1)
    return (end * tm + (start - end) / rate * (np.exp(-rate * (t - tm)) - np.exp(-rate * t))) / t1


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=HERE)
    p.add_argument("--load-steps", type=int, default=None)
    args = p.parse_args(argv)
    deck = yaml.safe_load((HERE / "bar_relaxation.yaml").read_text())
    steps = args.load_steps or deck["solver"]["load_steps"]
    ve = deck["material"]["viscoelastic"]
    lam, tau = float(ve["fraction"]), float(ve["relaxation_time"])
    t0 = time.perf_counter()
    e0 = run(variant(deck, 1, 0.0))[-1]
    einf = run(variant(deck, 1, 0.0, 1.0 - lam))[-1]
    e0, einf = e0[2] / e0[1], einf[2] / einf[1]
    relax = run(variant(deck, steps))
    creep = run(variant(deck, steps, creep=True))
    wall = time.perf_counter() - t0
    t1 = 1.0 / steps
    c, a = (1 - lam) * e0 / (einf * tau), (1 - lam) / tau
    want_r = ramp(relax[:, 0], t1, e0, einf, c)
    want_c = TRACTION * ramp(creep[:, 0], t1, 1 / e0, 1 / einf, a)
    err_r = float(np.abs(relax[:, 2] / relax[:, 1] / want_r - 1).max())
    err_c = float(np.abs(creep[:, 1] / want_c - 1).max())
    res = {
        "load_steps": steps,
        "E0_over_E": e0 / float(deck["material"]["youngs_modulus"]),
        "Einf_over_E0": einf / e0,
        "relaxation_max_relative_error": err_r,
        "creep_max_relative_error": err_c,
        "max_relative_error": max(err_r, err_c),
        "wall_s": wall,
    }
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "bar_sls.json").write_text(json.dumps(res, indent=2) + "\n")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.6))
    tt = np.linspace(0.0, 1.0, 201)
    ax1.plot(tt, ramp(tt, t1, e0, einf, c) / 1e9, "k-", label="standard linear solid")
    ax1.plot(relax[:, 0], relax[:, 2] / relax[:, 1] / 1e9, "o", label="PD bar (ADR)")
    ax1.set(xlabel="t (s)", ylabel="stress / held strain (GPa)", title="relaxation")
    ax2.plot(tt, TRACTION * ramp(tt, t1, 1 / e0, 1 / einf, a) * 1e3, "k-", label="SLS")
    ax2.plot(creep[:, 0], creep[:, 1] * 1e3, "o", label="PD bar (ADR)")
    ax2.set(xlabel="t (s)", ylabel="strain (1e-3)", title="creep, 1 MPa")
    ax1.legend()
    fig.tight_layout()
    fig.savefig(args.out / "bar_sls.png", dpi=120)
    plt.close(fig)
    print(json.dumps(res, indent=2))
    return res


if __name__ == "__main__":
    main()
