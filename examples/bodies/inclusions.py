"""Two-material specimen with bonded interfaces: runs ``inclusions.yaml`` with its weak
interface and again with the interface at the mortar's critical stretch (or re-reads
finished runs), draws the damage fields with the aggregate outlines and the
load-displacement curves, and measures the numbers of the README.

Usage::

    python examples/bodies/inclusions.py                       # weak and strong
    python examples/bodies/inclusions.py --cases weak --out results/i
    python examples/bodies/inclusions.py --set discretisation.spacing=1.0e-3
    python examples/bodies/inclusions.py --no-run              # re-analyse

Every case runs into ``<out>/<case>/`` with a checkpoint of its final state (the State
field ``interface_intact``, the intact flags of the interface bonds, is not in
``final_state.npz``; the checkpoint holds every State field). The figure ``<name>.png``
and the numbers ``<name>.json`` go to ``--figures`` (default ``<out>``).

Measured per case:

* load = |reaction| of the fixed grip (probe ``reaction``), against the mean x
  displacement of the pulled grip (probe ``pull``); the peak load and the nominal peak
  stress (over the plate's section);
* the broken share of the mortar, aggregate and interface bonds (directed bonds, from
  the final checkpoint: ``state_intact`` for bonds within a body, in body order;
  ``state_interface_intact`` for the interface bonds), and the interface bonds' share
  among all broken bonds against their share among all bonds (above 1: the cracks
  prefer the interfaces);
* where the cracks run: of the mortar points with damage >= 0.35, the share within one
  horizon of an aggregate surface, against the share of all mortar points that lie
  there (a crack that ignores the aggregates gives about the same share; a crack along
  the interfaces, a larger one).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
DECK = HERE / "inclusions.yaml"
CASES = ("weak", "strong")
#: points with damage at least this are "cracked"
CRACKED = 0.35


def case_deck(case: str, sets: list[str]) -> dict[str, Any]:
    """The deck as a mapping with the overrides; ``strong``: the interface's critical
    stretch is the mortar's (after the overrides)."""
    from peridynamics.io.deck import apply_overrides

    data = apply_overrides(yaml.safe_load(DECK.read_text()), list(sets))
    if case == "strong":
        data["interfaces"][0]["critical_stretch"] = float(data["damage"]["critical_stretch"])
    data["name"] = f"{data['name']}_{case}"
    return data


def simulation(data: dict[str, Any]) -> Any:
    from peridynamics.io.deck import parse_deck
    from peridynamics.runner import Simulation

    return Simulation.from_deck(parse_deck(data, HERE))


def discs(data: dict[str, Any]) -> list[tuple[np.ndarray, float]]:
    """(centre, radius) of every aggregate disc of the deck."""
    body = next(b for b in data["bodies"] if b["name"] == "aggregates")
    region = body["region"]
    balls = region["any_of"] if "any_of" in region else [region]
    return [(np.asarray(b["ball"]["center"], float), float(b["ball"]["radius"])) for b in balls]


def analyse(case: str, folder: Path, sets: list[str]) -> dict[str, Any]:
    data = case_deck(case, sets)
    sim = simulation(data)
    fm = sim.model.force_model
    summ = json.loads((folder / "summary.json").read_text())
    res = summ["results"]
    if res["n_points"] != sim.cloud.n_points:
        raise ValueError(f"{folder}: the run does not match the deck (pass the same --set)")
    with np.load(folder / "checkpoint.npz") as ck:
        intact = ck["state_intact"]
        iface = ck["state_interface_intact"]
    st = np.load(folder / "final_state.npz")
    x, dmg = st["x"], st["damage"]
    b0 = fm.bonds.bond_intact
    out: dict[str, Any] = {}
    broken_total, bonds_total = 0, 0
    for part, bs in zip(fm.parts, fm.bond_slices, strict=True):
        n = int(np.count_nonzero(b0[bs]))
        nb = int(np.count_nonzero(b0[bs] & (intact[bs] == 0)))
        out[f"{part.name}_bonds"] = n
        out[f"{part.name}_broken_share"] = nb / n if n else 0.0
        broken_total += nb
        bonds_total += n
    i0 = np.concatenate([f.bonds.bond_intact for f in fm.interfaces])
    ni = int(np.count_nonzero(i0))
    nib = int(np.count_nonzero(i0 & (iface == 0)))
    out["interface_bonds"] = ni
    out["interface_broken_share"] = nib / ni if ni else 0.0
    broken_total += nib
    bonds_total += ni
    share_broken = nib / broken_total if broken_total else 0.0
    out["interface_share_of_broken_bonds"] = share_broken
    out["interface_share_of_all_bonds"] = ni / bonds_total
    out["interface_enrichment"] = share_broken / (ni / bonds_total)
    # where the cracks run: distance of mortar points to the nearest aggregate surface
    horizon = float(res["horizon_m"])
    main = fm.point_slices[0]
    xm = x[main]
    dist = np.full(len(xm), np.inf)
    for c, r in discs(data):
        dist = np.minimum(dist, np.linalg.norm(xm - c, axis=1) - r)
    near = dist <= horizon
    cracked = dmg[main] >= CRACKED
    out["cracked_mortar_points"] = int(cracked.sum())
    out["cracked_mortar_near_aggregate_share"] = (
        float(near[cracked].mean()) if cracked.any() else 0.0
    )
    out["mortar_near_aggregate_share"] = float(near.mean())
    out["cracked_aggregate_points"] = int(
        np.count_nonzero(dmg[fm.point_slices[1]] >= CRACKED)
    )
    pr = res["probes"]
    load = np.abs(np.asarray(pr["reaction"]["values"]))
    pull = np.asarray(pr["pull"]["values"])
    k = int(np.argmax(load))
    g = data["geometry"]
    section = float(g["size"][1]) * float(g.get("thickness", 1.0))
    out.update(
        {
            "n_points": res["n_points"],
            "spacing_m": res["spacing_m"],
            "horizon_m": horizon,
            "steps": res["steps"],
            "interface_critical_stretch": float(data["interfaces"][0]["critical_stretch"]),
            "mortar_critical_stretch": float(data["damage"]["critical_stretch"]),
            "peak_load_N": float(load[k]),
            "peak_nominal_stress_Pa": float(load[k] / section),
            "pull_at_peak_m": float(pull[k]),
            "final_load_over_peak": float(load[-1] / load[k]),
            "max_damage": res["max_damage"],
            "max_kinetic_to_strain_energy": res["max_kinetic_to_strain_energy"],
            "wall_s": summ["timing"]["wall_s"],
        }
    )
    return out


def plot(path: Path, folders: dict[str, Path], data: dict[str, Any]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle

    n = len(folders)
    fig = plt.figure(figsize=(4.2 * n + 4.8, 4.3), layout="constrained")
    axes = fig.subplots(1, n + 1, width_ratios=[1.0] * n + [1.15])
    sc = None
    for ax, (case, folder) in zip(axes[:n], folders.items(), strict=True):
        st = np.load(folder / "final_state.npz")
        x, dmg = st["x"] * 1e3, st["damage"]
        dx = float(json.loads((folder / "summary.json").read_text())["results"]["spacing_m"])
        size = 0.6 * (dx * 1e3 * 72 / 25.4 * 4.0 / 40.0) ** 2 * 40.0
        sc = ax.scatter(x[:, 0], x[:, 1], c=dmg, s=size, marker="s", cmap="inferno_r",
                        vmin=0.0, vmax=1.0, linewidths=0)  # fmt: skip
        for c, r in discs(data):
            ax.add_patch(Circle(tuple(c * 1e3), r * 1e3, fill=False, ec="tab:cyan", lw=0.9))
        ax.set_aspect("equal")
        ax.set_title(f"{case} interface: damage", fontsize=10)
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
    if sc is not None:
        fig.colorbar(sc, ax=list(axes[:n]), shrink=0.8, label="damage")
    ax = axes[n]
    for case, folder in folders.items():
        pr = json.loads((folder / "summary.json").read_text())["results"]["probes"]
        ax.plot(np.asarray(pr["pull"]["values"]) * 1e6,
                np.abs(np.asarray(pr["reaction"]["values"])) * 1e-3, label=case)  # fmt: skip
    ax.set_xlabel("pulled grip displacement (um)")
    ax.set_ylabel("load (kN)")
    ax.set_ylim(bottom=0.0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("load vs displacement", fontsize=10)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("cases", nargs="*", default=list(CASES), choices=list(CASES))
    p.add_argument("--out", type=Path, default=Path("results/bodies/inclusions"))
    p.add_argument("--figures", type=Path, default=None, help="default: --out")
    p.add_argument("--name", default="inclusions", help="figure and JSON file stem")
    p.add_argument("--set", action="append", default=[], dest="sets")
    p.add_argument("--no-run", action="store_true")
    args = p.parse_args(argv)
    cases = args.cases or list(CASES)
    figs = args.figures or args.out
    figs.mkdir(parents=True, exist_ok=True)
    folders: dict[str, Path] = {}
    for case in cases:
        folder = args.out / case
        if not args.no_run:
            sim = simulation(case_deck(case, args.sets))
            sim.run(folder, checkpoint_every=10**9)  # only the final state's checkpoint
        folders[case] = folder
    res = {
        "deck": DECK.name,
        "overrides": args.sets,
        "cases": {c: analyse(c, f, args.sets) for c, f in folders.items()},
    }
    plot(figs / f"{args.name}.png", folders, case_deck(cases[0], args.sets))
    (figs / f"{args.name}.json").write_text(json.dumps(res, indent=2) + "\n")
    print(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
