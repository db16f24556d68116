"""Two-material specimen with bonded interfaces: runs ``inclusions.yaml`` with its weak
interface (``weak``), again with the interface at the mortar's critical stretch
(``strong``) and without the aggregates (``plain``: mortar everywhere, the control of
where cracks run), or re-reads finished runs; draws the damage fields with the
aggregate outlines and the load-displacement curves, and measures the numbers of the
README.

Usage::

    python examples/bodies/inclusions.py                       # weak, strong, plain
    python examples/bodies/inclusions.py weak --out results/i  # one case
    python examples/bodies/inclusions.py --set discretisation.spacing=1.0e-3
    python examples/bodies/inclusions.py --no-run              # re-analyse

Every case runs into ``<out>/<case>/`` with a checkpoint of its final state (the State
field ``interface_intact``, the intact flags of the interface bonds, is not in
``final_state.npz``; the checkpoint holds every State field). The figure ``<name>.png``
and the numbers ``<name>.json`` go to ``--figures`` (default ``<out>``).

Measured per case:

* load = the reaction of the fixed grip (probe ``reaction``, positive in tension)
  against the mean x displacement of the pulled grip (probe ``pull``); the peak load,
  the nominal peak stress (over the plate's section), the mean load over the last tenth
  of the run over the peak;
* the broken share of the mortar, aggregate and interface bonds (directed bonds, from
  the final checkpoint: ``state_intact`` for bonds within a body, in body order;
  ``state_interface_intact`` for the interface bonds), and the interface bonds' share
  among all broken bonds against their share among all bonds (above 1: the cracks
  prefer the interfaces);
* quasi-statics: the largest kinetic / strain energy over the second half of the
  loading before the peak (the first records hold the wave that the grip starts, where
  the two are about equal);
* where the cracks run: of the mortar points (outside every disc) with damage >= 0.35,
  the share within one horizon of an aggregate surface, against the share of all
  mortar points that lie there (a crack that ignores the aggregates, as in ``plain``,
  gives about the same share; a crack along the interfaces, a larger one).
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
CASES = ("weak", "strong", "plain")
#: points with damage at least this are "cracked"
CRACKED = 0.35


def case_deck(case: str, sets: list[str]) -> dict[str, Any]:
    """The deck as a mapping with the overrides; ``strong``: the interface's critical
    stretch is the mortar's (after the overrides); ``plain``: no aggregates (the
    mortar everywhere)."""
    from peridynamics.deck import apply_overrides

    data = apply_overrides(yaml.safe_load(DECK.read_text()), list(sets))
    if case == "strong":
        data["interfaces"][0]["critical_stretch"] = float(data["damage"]["critical_stretch"])
    data["name"] = f"{data['name']}_{case}"
    return data


def run_deck(case: str, sets: list[str]) -> dict[str, Any]:
    """What is run: the case's deck, for ``plain`` without ``bodies`` and ``interfaces``
    (the outlines of the figure and the distances still come from ``case_deck``)."""
    data = case_deck(case, sets)
    if case == "plain":
        data.pop("bodies")
        data.pop("interfaces")
    return data


def simulation(data: dict[str, Any]) -> Any:
    from peridynamics.app.run import Simulation
    from peridynamics.deck import parse_deck

    return Simulation.from_deck(parse_deck(data, HERE))


def discs(data: dict[str, Any]) -> list[tuple[np.ndarray, float]]:
    """(centre, radius) of every aggregate disc of the deck."""
    body = next(b for b in data["bodies"] if b["name"] == "aggregates")
    region = body["region"]
    balls = region["any_of"] if "any_of" in region else [region]
    return [(np.asarray(b["ball"]["center"], float), float(b["ball"]["radius"])) for b in balls]


def signed_load(probes: dict[str, Any]) -> np.ndarray:
    """The reaction of the fixed grip, positive in tension (the sign of its largest
    magnitude); a broken plate rings about zero."""
    r = np.asarray(probes["reaction"]["values"])
    return r * np.sign(r[np.argmax(np.abs(r))])


def bond_shares(fm: Any, intact: np.ndarray, iface: np.ndarray | None) -> dict[str, Any]:
    """Bonds and broken shares per body and of the interfaces (directed bonds)."""
    b0 = fm.bonds.bond_intact
    parts = getattr(fm, "parts", None)
    slices = fm.bond_slices if parts else [slice(0, len(b0))]
    names = [p.name for p in parts] if parts else ["main"]
    out: dict[str, Any] = {}
    broken_total, bonds_total = 0, 0
    for name, bs in zip(names, slices, strict=True):
        n = int(np.count_nonzero(b0[bs]))
        nb = int(np.count_nonzero(b0[bs] & (intact[bs] == 0)))
        out[f"{name}_bonds"] = n
        out[f"{name}_broken_share"] = nb / n if n else 0.0
        broken_total += nb
        bonds_total += n
    if iface is None:
        return out
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
    return out


def analyse(case: str, folder: Path, sets: list[str]) -> dict[str, Any]:
    data = case_deck(case, sets)
    sim = simulation(run_deck(case, sets))
    summ = json.loads((folder / "summary.json").read_text())
    res = summ["results"]
    if res["n_points"] != sim.cloud.n_points:
        raise ValueError(f"{folder}: the run does not match the deck (pass the same --set)")
    with np.load(folder / "checkpoint.npz") as ck:
        intact = ck["state_intact"]
        iface = ck["state_interface_intact"] if case != "plain" else None
    out = bond_shares(sim.model.force_model, intact, iface)
    st = np.load(folder / "final_state.npz")
    x, dmg = st["x"], st["damage"]
    # where the cracks run: distance of mortar points (outside every disc) to the
    # nearest aggregate surface
    horizon = float(res["horizon_m"])
    dist = np.full(len(x), np.inf)
    for c, r in discs(data):
        dist = np.minimum(dist, np.linalg.norm(x - c, axis=1) - r)
    mortar = dist > 0.0
    near = dist[mortar] <= horizon
    cracked = dmg[mortar] >= CRACKED
    out["cracked_mortar_points"] = int(cracked.sum())
    out["cracked_mortar_near_aggregate_share"] = (
        float(near[cracked].mean()) if cracked.any() else 0.0
    )
    out["mortar_near_aggregate_share"] = float(near.mean())
    out["cracked_points_inside_discs"] = int(np.count_nonzero(dmg[~mortar] >= CRACKED))
    pr = res["probes"]
    load = signed_load(pr)
    pull = np.asarray(pr["pull"]["values"])
    k = int(np.argmax(load))
    h = res["history"]
    th, tk = np.asarray(h["time_s"]), float(np.asarray(pr["reaction"]["time_s"])[k])
    late = (th >= 0.5 * tk) & (th <= tk)  # the second half of the loading before the peak
    ratio = np.asarray(h["kinetic_energy_J"]) / np.maximum(np.asarray(h["strain_energy_J"]), 1e-300)
    g = data["geometry"]
    section = float(g["size"][1]) * float(g.get("thickness", 1.0))
    out.update(
        {
            "n_points": res["n_points"],
            "spacing_m": res["spacing_m"],
            "horizon_m": horizon,
            "steps": res["steps"],
            "interface_critical_stretch": (
                None if case == "plain" else float(data["interfaces"][0]["critical_stretch"])
            ),
            "mortar_critical_stretch": float(data["damage"]["critical_stretch"]),
            "peak_load_N": float(load[k]),
            "peak_nominal_stress_Pa": float(load[k] / section),
            "pull_at_peak_m": float(pull[k]),
            # the mean over the last tenth of the records (the broken plate rings)
            "final_load_over_peak": float(load[-max(1, len(load) // 10) :].mean() / load[k]),
            "max_damage": res["max_damage"],
            "max_kinetic_to_strain_late_before_peak": float(ratio[late].max()),
            "wall_s": summ["timing"]["wall_s"],
        }
    )
    return out


def damage_image(folder: Path) -> tuple[np.ndarray, dict[str, Any]]:
    """The final damage of a run on its grid as an image (NaN where there is no point)
    and the ``extent`` (mm) for ``imshow``."""
    st = np.load(folder / "final_state.npz")
    x, dmg = st["x"], st["damage"]
    dx = float(json.loads((folder / "summary.json").read_text())["results"]["spacing_m"])
    lo = x.min(axis=0)
    ij = np.rint((x - lo) / dx).astype(int)
    img = np.full((ij[:, 1].max() + 1, ij[:, 0].max() + 1), np.nan)
    img[ij[:, 1], ij[:, 0]] = dmg
    hi = lo + dx * np.array(img.shape[::-1])
    ext = [(lo[0] - dx / 2) * 1e3, (hi[0] - dx / 2) * 1e3, (lo[1] - dx / 2) * 1e3,
           (hi[1] - dx / 2) * 1e3]  # fmt: skip
    return img, {"extent": ext}


def plot(path: Path, folders: dict[str, Path], data: dict[str, Any]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle

    n = len(folders)
    fig = plt.figure(figsize=(4.2 * n + 4.8, 4.3), layout="constrained")
    axes = fig.subplots(1, n + 1, width_ratios=[1.0] * n + [1.15])
    im = None
    for ax, (case, folder) in zip(axes[:n], folders.items(), strict=True):
        img, kw = damage_image(folder)
        im = ax.imshow(img, origin="lower", cmap="inferno_r", vmin=0.0, vmax=1.0,
                       interpolation="nearest", **kw)  # fmt: skip
        for c, r in discs(data):
            ax.add_patch(Circle(tuple(c * 1e3), r * 1e3, fill=False, ec="tab:cyan", lw=0.9))
        title = "no aggregates" if case == "plain" else f"{case} interface"
        ax.set_title(f"{title}: damage", fontsize=10)
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
    if im is not None:
        fig.colorbar(im, ax=list(axes[:n]), shrink=0.8, label="damage")
    ax = axes[n]
    for case, folder in folders.items():
        pr = json.loads((folder / "summary.json").read_text())["results"]["probes"]
        ax.plot(np.asarray(pr["pull"]["values"]) * 1e6, signed_load(pr) * 1e-3, lw=0.8,
                label=case)  # fmt: skip
    ax.set_xlabel("pulled grip displacement (um)")
    ax.set_ylabel("load (kN)")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("load vs displacement", fontsize=10)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("cases", nargs="*", help=f"of {', '.join(CASES)} (default: all)")
    p.add_argument("--out", type=Path, default=Path("results/bodies/inclusions"))
    p.add_argument("--figures", type=Path, default=None, help="default: --out")
    p.add_argument("--name", default="inclusions", help="figure and JSON file stem")
    p.add_argument("--set", action="append", default=[], dest="sets")
    p.add_argument("--no-run", action="store_true")
    args = p.parse_args(argv)
    cases = args.cases or list(CASES)
    for c in cases:
        if c not in CASES:
            p.error(f"unknown case {c!r}; choose from {', '.join(CASES)}")
    figs = args.figures or args.out
    figs.mkdir(parents=True, exist_ok=True)
    folders: dict[str, Path] = {}
    for case in cases:
        folder = args.out / case
        if not args.no_run:
            sim = simulation(run_deck(case, args.sets))
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
