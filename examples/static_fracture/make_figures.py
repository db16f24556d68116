"""Figure and measured numbers of the edge-notched plate pulled to fracture by ADR.

Usage::

    python examples/static_fracture/make_figures.py             # deck as shipped
    python examples/static_fracture/make_figures.py --publish   # ... and copy PNG and JSON here
    python examples/static_fracture/make_figures.py --fem-h 1.25e-4   # a finer FEM reference
    python examples/static_fracture/make_figures.py --no-run    # re-analyse the last run

Runs ``notched_plate_adr.yaml`` into ``<out>/`` and writes
``<out>/notched_plate_adr.json`` (the measured numbers) and ``<out>/notched_plate_adr.png``.
The plate (30 x 15 mm, 1 mm thick, E = 70 GPa, PMB in plane stress, so nu = 1/3) has a
notch of a = 5 mm from the bottom edge at mid-length; its two left columns of points
are fixed and its two right columns pulled in x (free in y) in 20 load steps to 40 um.

From the run (``summary.json`` and the files beside it):

* the load-displacement curve: the reaction probe against the pull probe, one point per
  load step; the elastic stiffness (step 1) and how proportional the steps before the
  first broken bond are; the peak reaction, its step and its ratio to the elastic line;
  the reaction once the ligament is cut; broken bonds, crack length, ADR iterations;
* the PD crack-initiation load: in the last VTK frame before the first broken bond the
  largest ratio of a breakable bond's stretch to its critical stretch, r; the response
  is linear there, so the first bond breaks at reaction / r (needs that frame:
  ``output.vtk_every`` must hit a step before the first damage).

References, from a plane-stress finite-element model of the same plate (scikit-fem,
quadratic triangles of side ``--fem-h``, the notch a slit of zero width; skipped when
scikit-fem is not installed):

* the elastic stiffness with the clamp faces at x = 1.5 mm and 28.5 mm (the centres of
  the innermost fixed and pulled columns), and with them at 1.0 and 2.0 mm (the band
  that the choice spans);
* the LEFM load at which a crack of 5 mm grows, P_c = sqrt(2 t G0 / (dC/da)), with
  dC/da from the compliance at a -/+ h by central differences and G0 the fracture energy
  that the deck's critical stretch implies at this horizon, G0 = 9 E delta s0^2 / (4 pi)
  (plane stress, constant micromodulus: docs/deck.md, "Critical stretch from the
  fracture energy"; Ha & Bobaru 2010).

``--publish`` copies the PNG and the JSON into this folder (the committed files); it is
refused together with ``--set`` or ``--fem-h``, so the committed numbers are those of the
shipped deck and the default reference.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
CASE = "notched_plate_adr"
FEM_H = 5.0e-4  # FEM element side (m): stiffness and P_c within 0.5 % of h = 0.125 mm
CLAMPS = (1.0e-3, 1.5e-3, 2.0e-3)  # clamp faces (m) from each end; the middle is the reference


def run(out: Path, sets: list[str], do_run: bool) -> tuple[dict[str, Any], dict[str, Any]]:
    """Run (or re-read) the deck; returns summary.json's content and the deck data the
    references need (with the overrides applied)."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    deck = load_deck(HERE / f"{CASE}.yaml", overrides=sets)
    g = deck.geometry
    crack = np.asarray(deck.precracks[0].points, dtype=float)
    pull = next(bc for bc in deck.boundary_conditions if bc.type == "displacement")
    ref = {
        "E_Pa": float(deck.material.youngs_modulus),
        "constant_profile": deck.material.micromodulus_profile == "constant",
        "critical_stretch": float(deck.damage.critical_stretch),
        "length_m": float(g.size[0]),
        "width_m": float(g.size[1]),
        "thickness_m": float(g.thickness),
        "notch_x_m": float(crack[0, 0]),
        "notch_depth_m": float(crack[:, 1].max()),
        "pull_m": float(pull.components["x"]),
    }
    if do_run:
        Simulation.from_deck(deck).run(out, quiet=True, progress=False)
    return json.loads((out / "summary.json").read_text()), ref


def fem_stiffness(ref: dict[str, Any], a: float, clamp: float, h: float) -> float:
    """Elastic stiffness (N/m) of the plate with a slit of depth ``a`` (m) by plane-stress
    FEM (P2 triangles of side ``h``): all dofs fixed for x <= clamp, u_x prescribed and
    u_y free for x >= L - clamp."""
    from skfem import Basis, ElementTriP2, ElementVector, MeshTri, asm, condense, solve
    from skfem.models.elasticity import linear_elasticity, plane_stress

    length, width, xs = ref["length_m"], ref["width_m"], ref["notch_x_m"]
    nx, ny = round(length / h), round(width / h)
    mesh = MeshTri.init_tensor(np.linspace(0.0, length, nx + 1), np.linspace(0.0, width, ny + 1))
    p, tri = mesh.p.copy(), mesh.t.copy()
    tol = 1e-9 * length
    # the slit: the nodes on x = xs below the tip get a twin used by the right-hand cells
    slit = np.flatnonzero((np.abs(p[0] - xs) < tol) & (p[1] < a - tol))
    twin = np.arange(p.shape[1])
    twin[slit] = np.arange(p.shape[1], p.shape[1] + len(slit))
    p = np.hstack([p, p[:, slit]])
    right = p[0, tri].mean(axis=0) > xs
    tri[:, right] = twin[tri[:, right]]
    basis = Basis(MeshTri(p, tri), ElementVector(ElementTriP2()))
    lam, mu = plane_stress(ref["E_Pa"], 1.0 / 3.0)
    k = (ref["thickness_m"] * asm(linear_elasticity(lam, mu), basis)).tocsr()
    ix, iy = basis.split_indices()
    loc = basis.doflocs
    fixed = np.concatenate([ix[loc[0, ix] <= clamp + tol], iy[loc[0, iy] <= clamp + tol]])
    pulled = ix[loc[0, ix] >= length - clamp - tol]
    u = np.zeros(basis.N)
    u[pulled] = 1.0e-6
    u = solve(*condense(k, np.zeros(basis.N), x=u, D=np.concatenate([fixed, pulled])))
    return float((k @ u)[pulled].sum() / 1.0e-6)


def fem_reference(ref: dict[str, Any], horizon: float, h: float) -> dict[str, Any]:
    """FEM stiffness (band of clamp positions) and the LEFM growth load (module docstring)."""
    a = ref["notch_depth_m"]
    sizes = [ref[k] for k in ("length_m", "width_m", "notch_x_m", "notch_depth_m")]
    if any(abs(v / h - round(v / h)) > 1e-6 for v in sizes):
        raise ValueError(f"--fem-h {h:g} must divide the plate's size and the notch's position")
    t0 = time.perf_counter()
    band = {c: fem_stiffness(ref, a, c, h) for c in CLAMPS}
    clamp = CLAMPS[1]
    c_minus = 1.0 / fem_stiffness(ref, a - h, clamp, h)
    c_plus = 1.0 / fem_stiffness(ref, a + h, clamp, h)
    dcda = (c_plus - c_minus) / (2.0 * h)
    s0 = ref["critical_stretch"]
    g0 = 9.0 * ref["E_Pa"] * horizon * s0**2 / (4.0 * np.pi) if ref["constant_profile"] else None
    p_c = None if g0 is None else float(np.sqrt(2.0 * ref["thickness_m"] * g0 / dcda))
    return {
        "fem_element_side_m": h,
        "fem_clamp_faces_m": list(CLAMPS),
        "fem_stiffness_N_per_m": band[clamp],
        "fem_stiffness_band_N_per_m": [band[CLAMPS[0]], band[CLAMPS[2]]],
        "fem_dC_da_per_N": dcda,
        "G0_from_critical_stretch_J_per_m2": g0,
        "lefm_growth_load_N": p_c,
        "fem_wall_s": time.perf_counter() - t0,
    }


def initiation_load(out: Path, reaction: Any, first_damage_step: int) -> tuple[Any, Any]:
    """(load at which the first breakable bond reaches its critical stretch, the frame's
    step) from the last VTK frame before the first damage; (None, None) without one."""
    import meshio

    steps = sorted(
        int(m.group(1))
        for f in out.glob("frame_*.vtu")
        if (m := re.fullmatch(r"frame_(\d+)\.vtu", f.name))
    )
    elastic = [k for k in steps if 0 < k < first_damage_step]
    if not elastic:
        return None, None
    k = elastic[-1]
    u = meshio.read(out / f"frame_{k:07d}.vtu").point_data["displacement"][:, :2]
    bonds = np.load(out / "bonds.npz")
    s0 = np.load(out / "final_state.npz")["critical_stretch"]
    i, j, x = bonds["i"], bonds["j"], bonds["x_m"]
    limit = 0.5 * (s0[i] + s0[j])  # a bond breaks at the mean of its points' s0
    live = (bonds["initially_intact"] != 0) & np.isfinite(limit)  # no-fail points: s0 = inf
    stretched = np.linalg.norm(x[j] + u[j] - x[i] - u[i], axis=1)
    s = stretched / bonds["length_m"] - 1.0
    worst = float(np.max(s[live] / limit[live]))
    return float(reaction[k] / worst), k


def analyse(out: Path, summary: dict[str, Any], ref: dict[str, Any], fem_h: float) -> dict:
    """The measured numbers against the references (module docstring)."""
    r = summary["results"]
    reaction = np.asarray(r["probes"]["reaction"]["values"])
    pull = np.asarray(r["probes"]["pull"]["values"])
    first = r["events"].get("first_damage", {}).get("step")
    n_el = (first if first is not None else len(reaction)) - 1  # elastic steps 1..n_el
    stiff = reaction[1:] / pull[1:]
    k_pd = float(stiff[0])
    peak_k = int(np.argmax(reaction))
    p_init, frame = initiation_load(out, reaction, first if first is not None else len(reaction))
    cut = np.flatnonzero(reaction < 0.01 * reaction[peak_k])
    cut = cut[cut > peak_k]
    res: dict[str, Any] = {
        "n_points": r["n_points"],
        "spacing_m": r["spacing_m"],
        "horizon_m": r["horizon_m"],
        "load_steps": len(reaction) - 1,
        "pull_per_step_m": float(pull[1]),
        "pd_stiffness_N_per_m": k_pd,
        "elastic_steps": n_el,
        "elastic_steps_stiffness_spread_relative": float(np.ptp(stiff[:n_el]) / k_pd),
        "first_damage_step": first,
        "peak_reaction_N": float(reaction[peak_k]),
        "peak_step": peak_k,
        "elastic_line_at_peak_step_N": float(k_pd * pull[peak_k]),
        "peak_over_elastic_line": float(reaction[peak_k] / (k_pd * pull[peak_k])),
        "last_elastic_reaction_N": float(reaction[n_el]) if n_el > 0 else None,
        "pd_initiation_load_N": p_init,
        "pd_initiation_from_frame_step": frame,
        "first_step_below_1pct_of_peak": int(cut[0]) if len(cut) else None,
        "final_reaction_N": float(reaction[-1]),
        "bonds_broken": r["bonds_broken"],
        "crack_length_m": r.get("crack_length_m"),
        "max_damage": r["max_damage"],
        "adr_converged": r["converged"],
        "adr_iterations": r["iterations"],
        "adr_iterations_per_load_step": r["iterations_per_load_step"],
        "run_wall_s": summary["timing"]["wall_s"],
    }
    try:
        import skfem  # noqa: F401
    except ImportError:
        fem = None
    else:
        fem = fem_reference(ref, r["horizon_m"], fem_h)
        res.update(fem)
        res["pd_over_fem_stiffness"] = k_pd / fem["fem_stiffness_N_per_m"]
        p_c = fem["lefm_growth_load_N"]
        if p_c is not None:
            res["peak_reaction_over_lefm"] = float(reaction[peak_k] / p_c)
            res["pd_initiation_over_lefm"] = None if p_init is None else p_init / p_c
    state = np.load(out / "final_state.npz")
    res["_curves"] = (pull, reaction, state["x"], state["damage"], ref, fem)
    return res


def figure(res: dict[str, Any], path: Path) -> None:
    """Load-displacement curve with the references, and the final damage field."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pull, reaction, x, damage, ref, fem = res["_curves"]
    um = pull * 1e6
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [1.1, 1]})
    a = ax[0]
    line = np.array([0.0, pull[-1]])
    upto = min(1.0, 1.6 * reaction.max() / (res["pd_stiffness_N_per_m"] * pull[-1]))
    a.plot(
        line * upto * 1e6,
        res["pd_stiffness_N_per_m"] * line * upto,
        "-",
        color="0.6",
        lw=1,
        label=f"PD elastic line, step 1: {res['pd_stiffness_N_per_m'] / 1e6:.2f} N/µm",
    )
    if fem is not None:
        k_lo, k_hi = fem["fem_stiffness_band_N_per_m"]
        xs = line * upto
        a.fill_between(
            xs * 1e6,
            k_lo * xs,
            k_hi * xs,
            color="C2",
            alpha=0.15,
            lw=0,
            label="FEM, clamp faces 1.0-2.0 mm",
        )
        a.plot(
            xs * 1e6,
            fem["fem_stiffness_N_per_m"] * xs,
            "--",
            color="C2",
            lw=1,
            label=f"FEM, clamp faces 1.5 mm: {fem['fem_stiffness_N_per_m'] / 1e6:.2f} N/µm",
        )
        if fem["lefm_growth_load_N"] is not None:
            a.axhline(
                fem["lefm_growth_load_N"],
                color="C3",
                ls="--",
                lw=1,
                label=f"LEFM growth load {fem['lefm_growth_load_N']:.0f} N",
            )
    a.plot(um, reaction, "o-", color="C0", ms=4, lw=1.3, label="PD, ADR (one point per load step)")
    if res["pd_initiation_load_N"] is not None:
        p = res["pd_initiation_load_N"]
        a.plot(
            p / res["pd_stiffness_N_per_m"] * 1e6,
            p,
            "*",
            color="C3",
            ms=11,
            label=f"PD first bond breaks: {p:.0f} N",
        )
    a.set(
        xlabel="pulled displacement (µm)",
        ylabel="reaction on the pulled columns (N)",
        title="load-displacement curve",
    )
    a.grid(alpha=0.3)
    a.legend(fontsize=7.5, loc="center right")
    top = a.secondary_xaxis(
        "top",
        functions=(
            lambda v: v / (res["pull_per_step_m"] * 1e6),
            lambda s: s * res["pull_per_step_m"] * 1e6,
        ),
    )
    top.set_xlabel("load step", fontsize=8)
    top.set_xticks(np.arange(0, res["load_steps"] + 1, max(1, res["load_steps"] // 10)))
    b = ax[1]
    sc = b.scatter(
        x[:, 0] * 1e3,
        x[:, 1] * 1e3,
        c=damage,
        s=28,
        cmap="inferno_r",
        vmin=0,
        vmax=1,
        marker="s",
        edgecolors="none",
    )
    b.plot(
        [ref["notch_x_m"] * 1e3] * 2,
        [0.0, ref["notch_depth_m"] * 1e3],
        "c-",
        lw=2,
        label="notch (pre-crack)",
    )
    b.set(
        aspect="equal",
        xlabel="x (mm)",
        ylabel="y (mm)",
        title=f"damage after step {res['load_steps']} ({res['bonds_broken']} bonds broken)",
    )
    b.legend(fontsize=7.5, loc="upper right")
    fig.colorbar(sc, ax=b, shrink=0.7, label="damage φ")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("results") / "static_fracture")
    ap.add_argument("--set", action="append", default=[], help="deck override key=value")
    ap.add_argument("--fem-h", type=float, default=FEM_H, help="FEM element side (m)")
    ap.add_argument("--no-run", action="store_true", help="re-analyse the run in --out")
    ap.add_argument("--publish", action="store_true", help=f"copy {CASE}.png/.json into {HERE}")
    args = ap.parse_args(argv)
    if args.publish and (args.set or args.fem_h != FEM_H):
        ap.error("--publish copies the numbers of the shipped deck: not with --set or --fem-h")
    t0 = time.perf_counter()
    summary, ref = run(args.out, list(args.set), not args.no_run)
    res = analyse(args.out, summary, ref, args.fem_h)
    figure(res, args.out / f"{CASE}.png")
    del res["_curves"]
    res["script_wall_s"] = time.perf_counter() - t0
    (args.out / f"{CASE}.json").write_text(json.dumps(res, indent=2) + "\n")
    print(json.dumps(res, indent=2))
    if args.publish:
        for ext in ("png", "json"):
            shutil.copy2(args.out / f"{CASE}.{ext}", HERE / f"{CASE}.{ext}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
