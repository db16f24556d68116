"""Figures and measured numbers of the correspondence examples (PD zero-energy modes
(n.d.)): the plate with a central hole (elastic and with damage) and the three-point
bend, each with the linearised-bond stabilisation (LBSCMM), Silling (2017), no control
and the bond-based PMB model.

Usage::

    python examples/correspondence/make_figures.py                   # everything
    python examples/correspondence/make_figures.py plate             # a selection:
    python examples/correspondence/make_figures.py plate_damage bend # plate, plate_damage, bend
    python examples/correspondence/make_figures.py plate --out results/quick \
        --set discretisation.spacing=2.5e-3
    python examples/correspondence/make_figures.py bend --no-run     # re-analyse
    python examples/correspondence/make_figures.py plate_damage --variants none \
        --set none:solver.max_iterations=4000   # one variant, a key for it alone

Every variant runs its deck into ``<out>/<case>/<variant>/``; each case writes
``<case>.json`` (the measured numbers) and ``<case>.png`` into ``<out>``:

* plate: u_x along the row next to the axis (y = 24.5 mm) for every variant with the
  plane-stress FEM reference (``fem_reference.py``, scikit-fem), the grid-scale
  oscillation of that profile (``max |u_{k-1} - 2 u_k + u_{k+1}| / 4`` over runs of
  consecutive points, relative to max |u_x|), the displacement error against FEM over
  all points (u_y after removing the rigid shift of the pin), the reaction, and the
  gross stress concentration sigma_xx(hole) / (reaction / (W t)) at the particles next
  to the hole, against the FEM value at the same points and the handbook factor;
* plate_damage: damage maps, the damage factor against the pulled end's displacement,
  the load of the load step that first broke bonds (after the re-solve) and of the
  step before it (the onset lies between), the converged load steps, and where the
  damage lies (mean |x - 75 mm| of the damaged points and their x range: a crack
  perpendicular to the load at the minimum section has both small);
* bend: load against load-point deflection, the damage factor, damage maps, the load at
  first damage, and the crack path (the highest damaged point above the notch tip and
  its lateral offset from the notch plane). The bond-based variant uses the critical
  stretch s0 = f_t / E (the principal-stress criterion needs a stress tensor).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
from pathlib import Path
from typing import Any

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
VARIANTS = ("lbscmm", "silling2017", "none", "pmb")
CASES = {
    "plate": "plate_hole.yaml",
    "plate_damage": "plate_hole_damage.yaml",
    "bend": "three_point_bend.yaml",
}
#: the variants that are run (the others are re-read): ``--variants``
RUN: list[str] = list(VARIANTS)
#: points with damage above this are "damaged" in the crack measures
DAMAGED = 0.35


def variant_deck(case: str, variant: str) -> dict[str, Any]:
    """The deck of ``case`` as a mapping, with the material of ``variant``."""
    data = yaml.safe_load((HERE / CASES[case]).read_text())
    mat = data["material"]
    if variant == "pmb":
        for key in ("poisson_ratio", "stabilization", "stabilization_g", "law"):
            mat.pop(key, None)  # PMB fixes nu = 1/3 in plane stress
        mat["model"] = "pmb"
        dmg = data["damage"]
        if dmg.get("model") == "principal_stress":
            dmg["model"] = "critical_stretch"
            dmg["critical_stretch"] = float(dmg.pop("tensile_strength")) / float(
                mat["youngs_modulus"]
            )  # YAML 1.1 reads 0.8e6 as a string
    else:
        mat["stabilization"] = variant
    data["name"] = f"{data['name']}_{variant}"
    return data


def run_variant(case: str, variant: str, out: Path, sets: list[str], run: bool) -> dict[str, Any]:
    """Run (or re-read) one variant; returns summary.json's content. ``sets`` entries
    ``variant:key=value`` apply to that variant only."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import apply_overrides, parse_deck

    folder = out / case / variant
    if run:
        mine = [x.split(":", 1)[1] for x in sets if x.startswith(f"{variant}:")]
        common = [x for x in sets if ":" not in x.split("=", 1)[0]]
        data = apply_overrides(variant_deck(case, variant), common + mine)
        deck = parse_deck(data, HERE)
        Simulation.from_deck(deck).run(folder)
    return json.loads((folder / "summary.json").read_text())


def _final(out: Path, case: str, variant: str) -> Any:
    return np.load(out / case / variant / "final_state.npz")


def _fem_module() -> Any:
    spec = importlib.util.spec_from_file_location("fem_reference", HERE / "fem_reference.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def oscillation(x: np.ndarray, u: np.ndarray, dx: float) -> float:
    """Grid-scale oscillation of a profile u(x) sampled every dx (with gaps): max over
    runs of consecutive samples of |u_{k-1} - 2 u_k + u_{k+1}| / 4, divided by max |u|."""
    order = np.argsort(x)
    x, u = x[order], u[order]
    best = 0.0
    gap = np.flatnonzero(np.diff(x) > 1.5 * dx)
    for seg in np.split(np.arange(len(x)), gap + 1):
        if len(seg) >= 3:
            v = u[seg]
            best = max(best, float(np.abs(v[:-2] - 2 * v[1:-1] + v[2:]).max() / 4))
    scale = float(np.abs(u).max())
    return best / scale if scale > 0 else 0.0


def _cauchy(case_deck: dict[str, Any], variant: str, state: Any) -> np.ndarray:
    """sigma_xx of every point: the correspondence stress, or the PMB virial stress."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import parse_deck

    sim = Simulation.from_deck(parse_deck(case_deck, HERE))
    model = sim.model
    if model.n_points != len(state["u"]):
        raise ValueError("the deck does not match the run (pass the same --set overrides)")
    if variant == "pmb":
        return np.asarray(model.point_stress(state["u"], state["intact"])[:, 0, 0])
    return np.asarray(model.force_model.cauchy_stress(state["u"], state["intact"])[:, 0, 0])


def plate(out: Path, sets: list[str], run: bool) -> dict[str, Any]:
    fem_mod = _fem_module()
    fem = fem_mod.solve_plate()
    a, centre, width, t = 0.010, np.array([0.075, 0.025]), 0.050, 1.0e-3
    res: dict[str, Any] = {"fem_reaction_N": fem.reaction, "variants": {}}
    profiles = {}
    for var in VARIANTS:
        if not (run and var in RUN) and not (out / "plate" / var / "summary.json").exists():
            continue  # neither run now nor before
        summ = run_variant("plate", var, out, sets, run and var in RUN)
        st = _final(out, "plate", var)
        x, u = st["x"], st["u"]
        dx = float(summ["results"]["spacing_m"])
        row = np.abs(x[:, 1] - (centre[1] - dx / 2)) < 1e-9
        osc = oscillation(x[row, 0], u[row, 0], dx)
        uf = fem.displacement(x)
        pin = np.argmin(np.linalg.norm(x - [0.0005, 0.0245], axis=1))
        shift = uf[pin, 1] - u[pin, 1]
        err = np.abs(u - uf + [0.0, shift]).max() / np.abs(uf).max()
        reaction = float(summ["results"]["probes"]["reaction"]["values"][-1])
        from peridynamics.deck import apply_overrides

        deck = apply_overrides(
            variant_deck("plate", var), [x for x in sets if ":" not in x.split("=", 1)[0]]
        )
        sxx = _cauchy(deck, var, st)
        near = np.abs(np.linalg.norm(x - centre, axis=1) - a) < 0.75 * dx
        near &= np.abs(x[:, 0] - centre[0]) < 1.0 * dx
        nominal = reaction / (width * t)
        scf = float(sxx[near].max() / nominal)
        fem_scf = float(fem.stress(x[near])[:, 0].max() / (fem.reaction / (width * t)))
        res["variants"][var] = {
            "oscillation_rel": osc,
            "max_abs_ux_m": float(np.abs(u[:, 0]).max()),
            "max_error_vs_fem_rel": float(err),
            "reaction_N": reaction,
            "reaction_vs_fem": reaction / fem.reaction,
            "gross_scf_at_particles": scf,
            "fem_gross_scf_at_same_points": fem_scf,
            "adr_iterations": summ["results"].get("iterations"),
            "wall_s": summ["timing"]["wall_s"],
        }
        profiles[var] = (x[row, 0], u[row, 0])
    res["handbook_gross_scf_peterson"] = float(fem_mod.peterson_gross_factor(0.4))
    res["fem_gross_scf_at_hole_edge"] = float(fem.max_hole_stress() / (fem.reaction / (width * t)))
    _plot_plate(out, profiles, fem)
    return res


def _plot_plate(out: Path, profiles: dict[str, Any], fem: Any) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.5))
    xs = np.linspace(0.0005, 0.1495, 600)
    xy = np.column_stack([xs, np.full_like(xs, 0.0245)])
    keep = np.linalg.norm(xy - [0.075, 0.025], axis=1) > 0.010
    ux = np.full(len(xs), np.nan)  # a gap across the hole
    ux[keep] = fem.displacement(xy[keep])[:, 0]
    ax.plot(xs * 1e3, ux * 1e3, "k-", lw=1, label="FEM")
    for var, (x, u) in profiles.items():
        order = np.argsort(x)
        xo, uo = x[order], u[order].copy()
        gap = np.flatnonzero(np.diff(xo) > 1.5 * np.min(np.diff(xo)))
        xo, uo = np.insert(xo, gap + 1, np.nan), np.insert(uo, gap + 1, np.nan)
        ax.plot(xo * 1e3, uo * 1e3, ".-", ms=3, lw=0.6, label=var)
    ax.set_xlabel("x (mm), row y = 24.5 mm")
    ax.set_ylabel("u_x (mm)")
    ax.legend()
    ax.set_title("Plate with a hole: u_x along the axis")
    fig.tight_layout()
    fig.savefig(out / "plate.png", dpi=120)
    plt.close(fig)


def _damage_case(
    case: str, out: Path, sets: list[str], run: bool, load_probe: str
) -> dict[str, Any]:
    res: dict[str, Any] = {"variants": {}}
    curves = {}
    for var in VARIANTS:
        if not (run and var in RUN) and not (out / case / var / "summary.json").exists():
            continue  # neither run now nor before
        summ = run_variant(case, var, out, sets, run and var in RUN)
        r = summ["results"]
        st = _final(out, case, var)
        probes = r["probes"]
        disp = np.abs(np.asarray(probes["deflection" if case == "bend" else "pull"]["values"]))
        load = np.abs(np.asarray(probes[load_probe]["values"]))
        dfac = np.asarray(r["history"]["damage_factor"])
        first = np.flatnonzero(dfac > 0)
        x, dmg = st["x"], st["damage"]
        hit = dmg >= DAMAGED
        entry: dict[str, Any] = {
            "final_damage_factor": float(dfac[-1]),
            "peak_load_N": float(load.max()),
            "load_at_first_damage_N": float(load[first[0]]) if first.size else None,
            # the converged load of the last step without damage: the onset lies above
            "load_before_first_damage_N": float(load[first[0] - 1]) if first.size else None,
            "converged_steps": int(len(disp) - 1 - len(r.get("not_converged_load_steps", []))),
            "load_steps": int(len(disp) - 1),
            "displacement_at_first_damage_m": float(disp[first[0]]) if first.size else None,
            "damaged_points": int(hit.sum()),
            "wall_s": summ["timing"]["wall_s"],
        }
        if case == "plate_damage" and hit.any():
            entry["mean_abs_x_minus_75mm_m"] = float(np.abs(x[hit, 0] - 0.075).mean())
            entry["damaged_x_range_m"] = [float(x[hit, 0].min()), float(x[hit, 0].max())]
        if case == "bend" and hit.any():
            above = hit & (x[:, 1] > 0.017)
            if above.any():
                entry["crack_top_y_m"] = float(x[above, 1].max())
                entry["crack_max_abs_x_m"] = float(np.abs(x[above, 0]).max())
        res["variants"][var] = entry
        curves[var] = (disp, load, dfac, x, dmg)
    _plot_damage(out, case, curves)
    return res


def _plot_damage(out: Path, case: str, curves: dict[str, Any]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(curves)
    fig = plt.figure(figsize=(13, 1.0 + 2.0 * max(n, 2)), layout="constrained")
    left, right = fig.subfigures(1, 2, width_ratios=[1.25, 1])
    maps = left.subplots(n, 1, squeeze=False)[:, 0]
    ax_l, ax_d = right.subplots(2, 1, sharex=True)
    sc = None
    for ax, (var, (disp, load, dfac, x, dmg)) in zip(maps, curves.items(), strict=True):
        sc = ax.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, c=dmg, s=2, cmap="viridis", vmin=0, vmax=1)
        ax.set_aspect("equal")
        ax.set_title(f"{var}: damage", fontsize=9)
        ax.tick_params(labelsize=7)
        ax_l.plot(disp * 1e3, load, label=var)
        ax_d.plot(disp * 1e3, dfac, label=var)
    if sc is not None:
        left.colorbar(sc, ax=list(maps), shrink=0.6, label="damage")
    ax_l.set_ylabel("load (N)")
    ax_d.set_ylabel("damage factor")
    ax_d.set_xlabel("load-point displacement (mm)")
    ax_l.legend(fontsize=8)
    fig.savefig(out / f"{case}.png", dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("cases", nargs="*", default=list(CASES), choices=list(CASES))
    p.add_argument("--out", type=Path, default=Path("results/correspondence"))
    p.add_argument("--set", action="append", default=[], dest="sets")
    p.add_argument("--no-run", action="store_true")
    p.add_argument(
        "--variants", nargs="+", choices=VARIANTS, default=list(VARIANTS),
        help="run only these variants and re-read the others",
    )  # fmt: skip
    args = p.parse_args(argv)
    RUN[:] = args.variants
    args.out.mkdir(parents=True, exist_ok=True)
    for case in args.cases or list(CASES):
        if case == "plate":
            res = plate(args.out, args.sets, not args.no_run)
        else:
            probe = "load" if case == "bend" else "reaction"
            res = _damage_case(case, args.out, args.sets, not args.no_run, probe)
        (args.out / f"{case}.json").write_text(json.dumps(res, indent=2))
        print(case, json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
