"""Notched three-point bend with a tension-softening bond law: runs
``three_point_bend_softening.yaml`` (or re-reads finished runs), draws load against the
load-point displacement and against the CMOD, and measures the numbers of the README.

Usage::

    python examples/bodies/bend_softening.py                        # bilinear + brittle
    python examples/bodies/bend_softening.py --spacings 2.5e-3 1.25e-3   # two resolutions
    python examples/bodies/bend_softening.py --laws bilinear trilinear --out results/b
    python examples/bodies/bend_softening.py --no-run               # re-analyse
    python examples/bodies/bend_softening.py --reuse --spacings 2.5e-3 1.25e-3  # add runs
    python examples/bodies/bend_softening.py --set solver.end_time=0.02

Every (law, spacing) runs the deck into ``<out>/<law>_dx<spacing in um>um/``; the
figure ``<name>.png`` and the numbers ``<name>.json`` go to ``--figures`` (default
``<out>``). The laws: ``bilinear`` (the deck), ``trilinear`` (Petersson's knee) and
``brittle`` (the brittle PMB bond with the same fracture energy: the deck's
``tensile_strength`` and ``bond_law`` are dropped).

Measured per run:

* load P = the y reaction of the loading roller (``results.rigid_bodies.pin``), the
  load-point displacement its downward displacement, CMOD = u_x(mouth_right) -
  u_x(mouth_left) (probes of the bottom points either side of the notch);
* the peak load, the displacement and CMOD at the peak, the last load / peak; and the
  largest load before the load first falls below 80 % of its running maximum past half
  the peak (for a brittle beam the impacts of the broken halves on the roller come
  later and can be higher: this one is compared with LEFM), and the displacement over
  which the load then falls to 40 % of it (how abrupt the drop is);
* the work of fracture W_F = the area under P(load-point displacement) over the whole run
  (trapezoids, nothing extrapolated) against G_F t (D - a0) (RILEM 50-FMC);
* LEFM: P = K_IC t D^(3/2) / (S f(a0/D)), K_IC = sqrt(E G_F) (plane stress), f of
  ASTM E399 for S/D = 4 (Tada, Paris & Irwin 2000); and two strength bounds of a
  material whose tensile stress cannot exceed f_t: the elastic net-section load
  P_e = f_t t (D - a0)^2 / (1.5 S) (first cracking at the notch tip if there were no
  stress concentration) and the rigid-plastic limit P_p = 2 f_t t (D - a0)^2 / S (the
  whole ligament at f_t, the compression resultant at the top);
* the kinetic and strain energy left at the end (a brittle beam's broken halves rattle
  between the rollers: that energy and the impacts are not a softening tail);
* the equilibrium of the rollers: max |P + R_left + R_right| after the ramp-in, over
  the peak load (the dynamic wobble), and results.max_kinetic_to_strain_energy.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
DECK = HERE / "three_point_bend_softening.yaml"
LAWS = ("bilinear", "trilinear", "brittle")


def law_deck(law: str) -> dict[str, Any]:
    """The deck as a mapping, with the damage law ``law``."""
    data = yaml.safe_load(DECK.read_text())
    dmg = data["damage"]
    if law == "brittle":
        dmg.pop("tensile_strength", None)
        dmg.pop("bond_law", None)
        dmg.pop("trilinear_knee", None)
    else:
        dmg["bond_law"] = law
    data["name"] = f"{data['name']}_{law}"
    return data


def run_dir(out: Path, law: str, spacing: float) -> Path:
    return out / f"{law}_dx{round(spacing * 1e6)}um"


def deck_for(law: str, spacing: float | None, sets: list[str]) -> dict[str, Any]:
    from peridynamics.deck import apply_overrides

    extra = [] if spacing is None else [f"discretisation.spacing={spacing!r}"]
    return apply_overrides(law_deck(law), list(sets) + extra)


def run(law: str, spacing: float | None, out: Path, sets: list[str]) -> Path:
    """Run one law at one spacing (``None``: the deck's); returns its folder."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import parse_deck

    data = deck_for(law, spacing, sets)
    folder = run_dir(out, law, float(data["discretisation"]["spacing"]))
    Simulation.from_deck(parse_deck(data, HERE)).run(folder)
    return folder


def geometry(data: dict[str, Any]) -> dict[str, float]:
    """S, D, a0, t, E, G_F, f_t of a deck mapping (SI)."""
    g = data["geometry"]
    rig = {r["name"]: r for r in data["rigid_bodies"]}
    xl = float(rig["support_left"]["shape"]["cylinder"]["center"][0])
    xr = float(rig["support_right"]["shape"]["cylinder"]["center"][0])
    (p0, p1) = data["precracks"][0]["points"]
    y0 = float(g.get("origin", [0.0, 0.0])[1])
    return {
        "span_m": xr - xl,
        "depth_m": float(g["size"][1]),
        "notch_m": max(float(p0[1]), float(p1[1])) - y0,
        "thickness_m": float(g["thickness"]),
        "youngs_modulus_Pa": float(data["material"]["youngs_modulus"]),
        "fracture_energy_J_m2": float(data["damage"]["fracture_energy"]),
        "tensile_strength_Pa": float(law_deck("bilinear")["damage"]["tensile_strength"]),
    }


def f_astm(x: float) -> float:
    """ASTM E399 / Tada, Paris & Irwin (2000) geometry factor of the single-edge-notched
    bend specimen with S/W = 4: K = P S / (B W^(3/2)) f(a/W)."""
    return (
        3.0
        * math.sqrt(x)
        * (1.99 - x * (1.0 - x) * (2.15 - 3.93 * x + 2.7 * x * x))
        / (2.0 * (1.0 + 2.0 * x) * (1.0 - x) ** 1.5)
    )


def estimates(geo: dict[str, float]) -> dict[str, float]:
    s, d, a0, t = geo["span_m"], geo["depth_m"], geo["notch_m"], geo["thickness_m"]
    e, gf, ft = geo["youngs_modulus_Pa"], geo["fracture_energy_J_m2"], geo["tensile_strength_Pa"]
    k_ic = math.sqrt(e * gf)
    lig = d - a0
    return {
        "a0_over_D": a0 / d,
        "S_over_D": s / d,
        "f_astm_e399": f_astm(a0 / d),
        "K_IC_Pa_sqrt_m": k_ic,
        "P_lefm_N": k_ic * t * d**1.5 / (s * f_astm(a0 / d)),
        "P_net_section_elastic_N": ft * t * lig**2 / (1.5 * s),
        "P_rigid_plastic_N": 2.0 * ft * t * lig**2 / s,
        "characteristic_length_m": e * gf / ft**2,
        "ligament_fracture_energy_J": gf * t * lig,
    }


def curves(folder: Path) -> dict[str, np.ndarray]:
    """Time, load, load-point displacement, CMOD, support reactions of a finished run."""
    r = json.loads((folder / "summary.json").read_text())["results"]
    rb = r["rigid_bodies"]
    h = r["probes"]
    return {
        "t": np.asarray(rb["time_s"]),
        "load": np.asarray(rb["pin"]["force_N"])[:, 1],
        "disp": -np.asarray(rb["pin"]["displacement_m"])[:, 1],
        "supports": np.asarray(rb["support_left"]["force_N"])[:, 1]
        + np.asarray(rb["support_right"]["force_N"])[:, 1],
        "cmod": np.asarray(h["mouth_right_ux"]["values"])
        - np.asarray(h["mouth_left_ux"]["values"]),
        "top_uy": np.asarray(h["top_uy"]["values"]),
        "kinetic": np.interp(
            rb["time_s"], r["history"]["time_s"], r["history"]["kinetic_energy_J"]
        ),
        "strain": np.interp(rb["time_s"], r["history"]["time_s"], r["history"]["strain_energy_J"]),
    }


def analyse(folder: Path, est: dict[str, float], ramp_end: float) -> dict[str, Any]:
    summ = json.loads((folder / "summary.json").read_text())
    res = summ["results"]
    c = curves(folder)
    load, disp, cmod = c["load"], c["disp"], c["cmod"]
    k = int(np.argmax(load))
    peak = float(load[k])
    work = float(np.sum(0.5 * (load[1:] + load[:-1]) * np.diff(disp)))
    after = c["t"] >= ramp_end
    wobble = np.abs(load + c["supports"])[after]
    drops = np.diff(cmod[k:])
    # the load before the beam breaks: the largest load before it first falls below 80 %
    # of the running maximum, once that maximum is past half the peak (a brittle beam's
    # broken halves later hit the roller: those impacts can exceed it)
    running = np.maximum.accumulate(load)
    fell = np.flatnonzero((load < 0.8 * running) & (running > 0.5 * peak))
    k_on = int(np.argmax(load[: fell[0]])) if fell.size else k
    onset = float(load[k_on])
    # how abruptly the load falls: the displacement from there to 40 % of that load
    below = np.flatnonzero(load[k_on:] < 0.4 * onset)
    width = float(disp[k_on + below[0]] - disp[k_on]) if below.size else None
    return {
        "n_points": res["n_points"],
        "spacing_m": res["spacing_m"],
        "horizon_m": res["horizon_m"],
        "time_step_s": res["time_step_s"],
        "steps": res["steps"],
        "peak_load_N": peak,
        "peak_before_first_drop_N": onset,
        "displacement_at_that_peak_m": float(disp[k_on]),
        "drop_to_40pct_displacement_m": width,
        "displacement_at_peak_m": float(disp[k]),
        "cmod_at_peak_m": float(cmod[k]),
        "final_displacement_m": float(disp[-1]),
        "final_cmod_m": float(cmod[-1]),
        "final_load_N": float(load[-1]),
        "final_over_peak": float(load[-1] / peak),
        "peak_over_lefm": onset / est["P_lefm_N"],
        "work_of_fracture_J": work,
        "work_over_GF_ligament": work / est["ligament_fracture_energy_J"],
        "largest_cmod_decrease_after_peak_m": max(0.0, float(-drops.min())) if drops.size else 0.0,
        "max_reaction_imbalance_over_peak": float(wobble.max() / peak) if wobble.size else 0.0,
        "max_kinetic_to_strain_energy": res["max_kinetic_to_strain_energy"],
        "final_kinetic_energy_J": float(c["kinetic"][-1]),
        "final_strain_energy_J": float(c["strain"][-1]),
        "bonds_broken": res["bonds_broken"],
        "wall_s": summ["timing"]["wall_s"],
    }


def plot(path: Path, runs: dict[str, Path], est: dict[str, float]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2, a3) = plt.subplots(
        1, 3, figsize=(15, 4.2), layout="constrained", width_ratios=[1.0, 1.0, 0.8]
    )
    for label, folder in runs.items():
        c = curves(folder)
        kw = {"lw": 0.7, "alpha": 0.7} if label.startswith("brittle") else {"lw": 1.4}
        a1.plot(c["disp"] * 1e3, c["load"], label=label, **kw)
        a2.plot(c["cmod"] * 1e3, c["load"], label=label, **kw)
        a3.semilogy(c["disp"][1:] * 1e3, c["kinetic"][1:], label=label, **kw)
    a3.set_xlabel("load-point displacement (mm)")
    a3.set_ylabel("kinetic energy (J)")
    a3.set_ylim(bottom=1e-6)
    a3.grid(alpha=0.3)
    a3.set_title("kinetic energy of the beam", fontsize=10)
    for ax in (a1, a2):
        ax.axhline(est["P_lefm_N"], color="k", lw=0.8, ls=":")
        ax.axhline(est["P_rigid_plastic_N"], color="0.5", lw=0.8, ls="-.")
        ax.set_ylabel("load P (N)")
        ax.set_ylim(bottom=0.0)
        ax.grid(alpha=0.3)
    a1.text(0.0, est["P_lefm_N"], " LEFM", va="bottom", fontsize=8)
    a1.text(0.0, est["P_rigid_plastic_N"], " rigid-plastic limit", va="bottom", fontsize=8)
    a1.set_xlabel("load-point displacement (mm)")
    a2.set_xlabel("CMOD (mm)")
    a1.legend(fontsize=8)
    a1.set_title("load vs load-point displacement", fontsize=10)
    a2.set_title("load vs crack-mouth opening", fontsize=10)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", type=Path, default=Path("results/bodies/bend"))
    p.add_argument("--figures", type=Path, default=None, help="default: --out")
    p.add_argument("--name", default="bend_softening", help="figure and JSON file stem")
    p.add_argument("--laws", nargs="+", choices=LAWS, default=["bilinear", "brittle"])
    p.add_argument("--spacings", nargs="+", type=float, default=[None])
    p.add_argument("--set", action="append", default=[], dest="sets")
    p.add_argument("--no-run", action="store_true")
    p.add_argument("--reuse", action="store_true", help="do not rerun finished runs")
    args = p.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    figs = args.figures or args.out
    figs.mkdir(parents=True, exist_ok=True)
    base = deck_for("bilinear", args.spacings[0], args.sets)
    est = estimates(geometry(base))
    ramp = float(base["rigid_bodies"][0].get("time_function", {}).get("end", 0.0))
    runs: dict[str, Path] = {}
    for spacing in args.spacings:
        for law in args.laws:
            dx = float(deck_for(law, spacing, args.sets)["discretisation"]["spacing"])
            folder = run_dir(args.out, law, dx)
            done = (folder / "summary.json").exists()
            if not (args.no_run or (args.reuse and done)):
                run(law, spacing, args.out, args.sets)
            elif not done:
                print(f"{folder}: not run (skipped)")
                continue
            runs[f"{law} dx={dx * 1e3:g} mm"] = folder
    res = {
        "deck": DECK.name,
        "overrides": args.sets,
        "geometry": geometry(base),
        "estimates": est,
        "runs": {k: analyse(v, est, ramp) for k, v in runs.items()},
    }
    plot(figs / f"{args.name}.png", runs, est)
    (figs / f"{args.name}.json").write_text(json.dumps(res, indent=2) + "\n")
    print(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
