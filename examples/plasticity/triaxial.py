"""Confined (triaxial) compression of a Drucker-Prager rock specimen at several
confining pressures (``triaxial.yaml``): the plateau of the axial stress against the
closed-form triaxial strength of the cone the law uses (docs/theory_plasticity.md).

Usage::

    python examples/plasticity/triaxial.py                     # triaxial.png/.json here
    python examples/plasticity/triaxial.py --out /tmp/tx --pressures 0 10e6 \
        --load-steps 6 --section 5                             # a quick, small run

For each confining pressure P the deck's four pressures are set to P and the axial
displacement to twice the elastic axial strain at the closed-form strength; the deck
is stepped through the Python API (ADR, the plastic history committed on each accepted
load step). After each load step the mean axial and lateral Cauchy stresses of the
middle points (within 1.6 mm of the middle in x, whole cross-section) are recorded; the
strength is the largest axial compression.

Closed form (tension positive, p = tr(sigma)/3): on the cone sqrt(J2) + eta p = xi c
under sigma_2 = sigma_3 = -P, sigma_1 = -(P + q), sqrt(J2) = q/sqrt(3) and p = -P - q/3,
so q = (xi c + eta P)/(1/sqrt(3) - eta/3); for the cone through the Mohr-Coulomb
compressive meridian this is P + q = N P + 2 c sqrt(N), N = (1 + sin phi)/(1 - sin phi).
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import time
from pathlib import Path

import numpy as np
import yaml

from peridynamics.app.run import Simulation
from peridynamics.deck import parse_deck
from peridynamics.families.correspondence.plasticity import DruckerPrager

HERE = Path(__file__).resolve().parent
PRESSURES = (0.0, 5.0e6, 10.0e6, 20.0e6)


def strength(law: DruckerPrager, confining: float) -> float:
    """Axial compressive strength P + q (Pa, > 0) of the cone at confining pressure P."""
    eta, xi = _eta_xi(law.friction_angle)
    return confining + (xi * law.cohesion + eta * confining) / (1.0 / math.sqrt(3) - eta / 3.0)


def mohr_coulomb(law: DruckerPrager, confining: float) -> float:
    """The same strength from Mohr-Coulomb: N P + 2 c sqrt(N)."""
    s = math.sin(math.radians(law.friction_angle))
    n = (1.0 + s) / (1.0 - s)
    return n * confining + 2.0 * law.cohesion * math.sqrt(n)


def _eta_xi(phi_deg: float) -> tuple[float, float]:
    s, c = math.sin(math.radians(phi_deg)), math.cos(math.radians(phi_deg))
    d = math.sqrt(3.0) * (3.0 - s)
    return 6.0 * s / d, 6.0 * c / d


def _law(p: dict) -> DruckerPrager:
    """The deck's ``material.plasticity`` (YAML may read 1.0e6 as a string)."""
    return DruckerPrager(
        float(p["cohesion"]), float(p["friction_angle"]), float(p.get("dilation_angle", 0.0))
    )


def resize(deck: dict, points: int) -> dict:
    """A copy of the deck with a square cross-section of ``points`` (odd) points across;
    the face and mid-plane node sets follow."""
    if points < 3 or points % 2 == 0:
        raise ValueError(f"--section must be an odd number of points >= 3, got {points}")
    d = copy.deepcopy(deck)
    dx = float(d["discretisation"]["spacing"])
    d["geometry"]["size"][1:] = [points * dx, points * dx]
    sets = d["node_sets"]
    for k, name in ((1, "y"), (2, "z")):
        sets[f"{name}_high"]["box"]["min"][k] = (points - 1) * dx
        sets[f"{name}_mid"]["box"]["min"][k] = (points - 1) / 2 * dx
        sets[f"{name}_mid"]["box"]["max"][k] = (points + 1) / 2 * dx
    return d


def configure(deck: dict, confining: float, load_steps: int | None) -> dict:
    """A copy of the deck at confining pressure P, pushed to twice the elastic axial
    strain of the closed-form strength."""
    d = copy.deepcopy(deck)
    m = d["material"]
    e, nu = float(m["youngs_modulus"]), float(m["poisson_ratio"])
    p = m["plasticity"]
    law = _law(p)
    q = strength(law, confining) - confining
    eps = -(2.0 * q + (1.0 - 2.0 * nu) * confining) / e
    gap = d["geometry"]["size"][0] - d["discretisation"]["spacing"]
    for bc in d["boundary_conditions"]:
        if bc["type"] == "pressure":
            bc["value"] = confining
        elif bc["type"] == "displacement":
            bc["components"]["x"] = eps * gap
    if load_steps is not None:
        d["solver"]["load_steps"] = load_steps
    return d


def run(deck: dict, mid_half_width: float = 1.6e-3) -> dict[str, list[float]]:
    """Step the deck's solver; mean axial strain, axial and lateral stress of the middle."""
    sim = Simulation.from_deck(parse_deck(deck))
    fm = sim.model.force_model
    s = sim.solver.init()
    x = sim.model.cloud.x[:, 0]
    mid = np.abs(x - 0.5 * (x.min() + x.max())) < mid_half_width
    rec: dict[str, list[float]] = {"strain": [0.0], "axial": [0.0], "lateral": [0.0]}
    while not sim.solver.done(s):
        if not sim.solver.step(s).converged:
            raise RuntimeError(f"load step {s.step} did not converge")
        f = s["deformation_gradient"].reshape(-1, 3, 3)
        sig = fm.point_stress(s)
        rec["strain"].append(float(f[mid, 0, 0].mean() - 1.0))
        rec["axial"].append(float(sig[mid, 0, 0].mean()))
        rec["lateral"].append(float(0.5 * (sig[mid, 1, 1] + sig[mid, 2, 2]).mean()))
    return rec


def calibrate(deck: dict, confining: float) -> float:
    """The layer pressure that gives the middle points the mean lateral stress -P in the
    elastic confinement stage (two load steps of the deck with the axial displacement
    held at zero); 0 for P = 0."""
    if confining == 0.0:
        return 0.0
    d = configure(deck, confining, 2)
    for bc in d["boundary_conditions"]:
        if bc["type"] == "displacement":
            bc["components"]["x"] = 0.0
    lateral = -run(d)["lateral"][-1]
    return confining * confining / lateral


def series(
    deck: dict, pressures: list[float], load_steps: int | None = None, calibrated: bool = False
) -> list[dict]:
    """Run the deck at each confining pressure (``calibrated``: the layer pressure
    scaled by :func:`calibrate`); strength and its closed forms."""
    p = deck["material"]["plasticity"]
    law = _law(p)
    out = []
    for confining in pressures:
        t0 = time.perf_counter()
        applied = calibrate(deck, confining) if calibrated else confining
        d = configure(deck, confining, load_steps)
        for bc in d["boundary_conditions"]:
            if bc["type"] == "pressure":
                bc["value"] = applied
        rec = run(d)
        k = int(np.argmin(rec["axial"]))
        peak = -rec["axial"][k]
        lateral = -rec["lateral"][k]  # the confinement the middle sees at the peak
        want = strength(law, confining)
        out.append(
            {
                "confining_MPa": confining / 1e6,
                "applied_pressure_MPa": applied / 1e6,
                "peak_MPa": peak / 1e6,
                "closed_form_MPa": want / 1e6,
                "relative_error": peak / want - 1.0,
                "lateral_at_peak_MPa": lateral / 1e6,
                "closed_form_at_measured_lateral_MPa": strength(law, lateral) / 1e6,
                "relative_error_at_measured_lateral": peak / strength(law, lateral) - 1.0,
                "seconds": time.perf_counter() - t0,
                "strain": rec["strain"],
                "axial_MPa": [v / 1e6 for v in rec["axial"]],
            }
        )
    return out


def figure(res: list[dict], law: DruckerPrager, path: Path) -> None:
    """Peak strength against confining pressure: simulation points and the cone's line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9.0, 3.8))
    conf = np.array([r["confining_MPa"] for r in res])
    line = np.linspace(0.0, max(conf.max(), 1.0) * 1.1, 50)
    ax.plot(line, [strength(law, 1e6 * v) / 1e6 for v in line], "k-", lw=1,
            label="Drucker-Prager (MC compressive meridian)")  # fmt: skip
    peak = [r["peak_MPa"] for r in res]
    ax.plot(conf, peak, "o", mfc="none", label="correspondence, ADR: against P")
    ax.plot([r["lateral_at_peak_MPa"] for r in res], peak, "x",
            label="against the lateral stress of the middle")  # fmt: skip
    ax.set_xlabel("confining pressure / lateral stress (MPa)")
    ax.set_ylabel("axial strength (MPa)")
    ax.legend(loc="upper left", fontsize=8)
    for r in res:
        bx.plot(-1e3 * np.array(r["strain"]), -np.array(r["axial_MPa"]), "o-", ms=3,
                label=f"P = {r['confining_MPa']:g} MPa")  # fmt: skip
        bx.axhline(r["closed_form_MPa"], color="k", lw=0.6, ls=":")
    bx.set_xlabel("axial compressive strain (1e-3)")
    bx.set_ylabel("axial compressive stress (MPa)")
    bx.legend(loc="lower right", fontsize=8)
    for a in (ax, bx):
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--pressures", type=float, nargs="+", default=list(PRESSURES), help="Pa")
    ap.add_argument("--load-steps", type=int, default=None)
    ap.add_argument("--section", type=int, default=None, help="points across (odd)")
    ap.add_argument(
        "--calibrate", action="store_true",
        help="scale the layer pressure so the middle carries -P when the specimen is confined",
    )  # fmt: skip
    args = ap.parse_args(argv)
    deck = yaml.safe_load((HERE / "triaxial.yaml").read_text())
    if args.section is not None:
        deck = resize(deck, args.section)
    res = series(deck, args.pressures, args.load_steps, args.calibrate)
    p = deck["material"]["plasticity"]
    law = _law(p)
    args.out.mkdir(parents=True, exist_ok=True)
    name = "triaxial_calibrated" if args.calibrate else "triaxial"
    (args.out / f"{name}.json").write_text(json.dumps(res, indent=1))
    figure(res, law, args.out / f"{name}.png")
    return res


if __name__ == "__main__":
    for r in main():
        print({k: (round(v, 4) if isinstance(v, float) else v) for k, v in r.items()
               if k not in ("strain", "axial_MPa")})  # fmt: skip
