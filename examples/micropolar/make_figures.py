"""Figures and measured numbers of the micropolar examples (Zhou, Zhu & Li (n.d.)).

Usage::

    python examples/micropolar/make_figures.py                 # all three, as shipped
    python examples/micropolar/make_figures.py cantilever dcb  # a selection
    python examples/micropolar/make_figures.py dcb --out results/quick \
        --set discretisation.spacing=1.0e-3 --set geometry.size=[0.203,0.04]
    python examples/micropolar/make_figures.py l_panel --no-run  # re-analyse a run

Each case runs its deck (``cantilever.yaml``, ``dcb.yaml``, ``l_panel.yaml``) into
``<out>/<case>/`` and writes ``<case>.json`` (the measured numbers) and
``<case>.png`` there:

* cantilever: max |u_x| and max |u_y| of the body against the plane-stress FEM
  reference of ``fem_reference.py`` (scikit-fem, evaluated at the particle positions)
  and the tip deflection against Timoshenko & Goodier (1970), section 21;
* dcb: the elastic compliance (the first solve) against corrected beam theory, the
  P-Delta saw-tooth against the LEFM propagation curve: P / P_LEFM(Delta) at the peak of
  every breaking event on the straight part of the path (ligament > 3 arm heights), the
  largest distance of the crack path from the mid-line;
* l_panel: the crack start (the mean midpoint of the first broken pairs against the
  re-entrant corner), the angle of the crack path over its first 25 and 50 mm (upward
  from the horizontal, heading left), where it ends, and the P-Delta curve against
  Winkler's experiment (thesis Fig. 7.12, series A) with the peak loads of both.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent

#: Winkler (2001), thesis Fig. 7.12, series A: (load-point displacement mm, load kN)
WINKLER_A = np.array(
    [
        (0.0498, 2.015), (0.0956, 4.016), (0.1207, 5.001), (0.1483, 5.999), (0.1713, 6.708),
        (0.1925, 7.133), (0.2078, 7.219), (0.2161, 7.124), (0.2383, 6.714), (0.2693, 5.996),
        (0.3002, 5.265), (0.3996, 3.529), (0.4992, 2.477), (0.5986, 1.911), (0.6982, 1.545),
        (0.7988, 1.283), (1.0003, 1.041),
    ]
)  # fmt: skip


def run_case(case: str, out: Path, sets: list[str], run: bool) -> dict[str, Any]:
    """Run (or re-read) one deck; returns summary.json's content."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    folder = out / case
    if run:
        deck = load_deck(HERE / f"{case}.yaml", overrides=sets)
        Simulation.from_deck(deck).run(folder)
    return json.loads((folder / "summary.json").read_text())


def _final(out: Path, case: str) -> Any:
    return np.load(out / case / "final_state.npz")


def cantilever(out: Path, summary: dict[str, Any]) -> dict[str, Any]:
    """PD against the FEM reference and Timoshenko-Goodier (module docstring)."""
    from peridynamics.analysis.beams import timoshenko_goodier_tip_deflection

    spec = importlib.util.spec_from_file_location("fem_reference", HERE / "fem_reference.py")
    assert spec is not None and spec.loader is not None
    fem_mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(fem_mod)
    state = _final(out, "cantilever")
    x, u = state["x"], state["u"]
    length, height = 1.0, 0.3
    body = x[:, 0] > 0.0
    fem = fem_mod.solve_cantilever()
    u_fem = fem.displacement(x[body])
    pd_ux, pd_uy = np.abs(u[body, 0]).max(), np.abs(u[body, 1]).max()
    fe_ux, fe_uy = np.abs(u_fem[:, 0]).max(), np.abs(u_fem[:, 1]).max()
    tg_tip = timoshenko_goodier_tip_deflection(-1000.0, length, height, 1.0, 200e9, 0.2)
    dx = summary["results"]["spacing_m"]
    near_axis = body & (np.abs(x[:, 1] - height / 2) <= 0.5 * dx + 1e-12)
    tip_pd = float(u[near_axis][np.argmax(x[near_axis, 0]), 1])
    res = {
        "pd_max_abs_ux_m": float(pd_ux),
        "pd_max_abs_uy_m": float(pd_uy),
        "fem_max_abs_ux_at_particles_m": float(fe_ux),
        "fem_max_abs_uy_at_particles_m": float(fe_uy),
        "fem_max_abs_ux_m": float(fem.max_abs_ux),
        "fem_max_abs_uy_m": float(fem.max_abs_uy),
        "ux_ratio_pd_to_fem": float(pd_ux / fe_ux),
        "uy_ratio_pd_to_fem": float(pd_uy / fe_uy),
        "pd_tip_uy_near_axis_m": tip_pd,
        "timoshenko_goodier_tip_m": float(tg_tip),
        "tip_ratio_pd_to_tg": float(abs(tip_pd) / abs(tg_tip)),
    }
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
    order = np.argsort(x[near_axis, 0])
    xa = x[near_axis][order]
    ax[0].plot(xa[:, 0], -u[near_axis][order, 1] * 1e6, "o", ms=3, label="micropolar PD")
    ax[0].plot(xa[:, 0], -fem.displacement(xa)[:, 1] * 1e6, "-", label="FEM (scikit-fem, P2)")
    ax[0].set(xlabel="x (m)", ylabel="-u_y on the axis (um)", title="deflection")
    top = body & (x[:, 1] >= height - 0.5 * dx - 1e-12)
    ot = np.argsort(x[top, 0])
    xt = x[top][ot]
    ax[1].plot(xt[:, 0], u[top][ot, 0] * 1e6, "o", ms=3, label="micropolar PD")
    ax[1].plot(xt[:, 0], fem.displacement(xt)[:, 0] * 1e6, "-", label="FEM")
    ax[1].set(xlabel="x (m)", ylabel="u_x on the top row (um)", title="axial displacement")
    for a in ax:
        a.legend()
    fig.tight_layout()
    fig.savefig(out / "cantilever" / "cantilever.png", dpi=120)
    plt.close(fig)
    return res


def _pd_curve(summary: dict[str, Any], load: str, disp: list[str]) -> tuple[Any, Any, Any]:
    r = summary["results"]
    p = np.asarray(r["probes"][load]["values"])
    d = np.asarray(r["probes"][disp[0]]["values"])
    if len(disp) > 1:
        d = d - np.asarray(r["probes"][disp[1]]["values"])
    t = np.asarray(r["probes"][load]["time_s"])
    return p, d, t


def dcb(out: Path, summary: dict[str, Any]) -> dict[str, Any]:
    """Compliance against corrected beam theory, events against LEFM."""
    from peridynamics.analysis.dcb import dcb_compliance, dcb_lefm_curve
    from peridynamics.analysis.dcb_events import dcb_event_ratios

    r = summary["results"]
    dx = r["spacing_m"]
    E, nu, gc, b, h = 200e9, 0.2, 962.8, 0.01, 0.02
    a0 = 0.1 - 0.5 * dx  # from the load line (first column) to the pre-crack tip
    p, d, t = _pd_curve(summary, "load_N", ["top_uy", "bottom_uy"])
    stiff = p[1] / d[1]
    cbt = 1.0 / dcb_compliance(a0, h, b, E, nu)
    crack = r["crack_paths"]["crack"]
    events = dcb_event_ratios(
        p, d, t, crack["length_history_m"], a0, 0.2, h, b, E, nu, gc, dx
    )  # the peaks of the saw-tooth against LEFM (also the verify case micropolar_dcb)
    peaks, ratio, straight = events.index, events.ratio, events.straight
    verts = np.asarray(crack["vertices_m"])
    res = {
        "stiffness_pd_N_per_m": float(stiff),
        "stiffness_cbt_N_per_m": float(cbt),
        "compliance_ratio_pd_to_cbt": float(cbt / stiff),
        "events": int(len(peaks)),
        "events_on_straight_part": int(straight.sum()),
        "p_over_p_lefm_mean": float(ratio[straight].mean()) if straight.any() else None,
        "p_over_p_lefm_std": float(ratio[straight].std()) if straight.any() else None,
        "p_over_p_lefm_min": float(ratio[straight].min()) if straight.any() else None,
        "p_over_p_lefm_max": float(ratio[straight].max()) if straight.any() else None,
        "first_event_p_over_p_lefm": float(ratio[0]) if len(ratio) else None,
        "crack_growth_m": float(crack["length_m"]),
        "max_path_offset_from_midline_m": float(np.abs(verts[:, 1]).max()) if len(verts) else 0,
    }
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.plot(d * 1e3, p, "-", lw=0.8, label="micropolar PD (every solve)")
    ax.plot(d[peaks] * 1e3, p[peaks], ".", ms=3, label="breaking events")
    dd = np.linspace(max(d[peaks].min(), 1e-5) if len(peaks) else 1e-4, d.max(), 200)
    ax.plot(dd * 1e3, dcb_lefm_curve(dd, h, b, E, nu, gc), "k--", label="LEFM, beam theory")
    ax.set(xlabel="opening Delta (mm)", ylabel="load P (N)", title="DCB, mode I")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "dcb" / "dcb.png", dpi=120)
    plt.close(fig)
    return res


def l_panel(out: Path, summary: dict[str, Any]) -> dict[str, Any]:
    """Crack start, angle and end; P-Delta against the experiment."""
    r = summary["results"]
    p, d, _ = _pd_curve(summary, "load_N", ["load_uy"])
    crack = r["crack_paths"]["crack"]
    verts = np.asarray(crack["vertices_m"])
    bonds = np.load(out / "l_panel" / "bonds.npz")
    broken = np.flatnonzero((bonds["intact"] == 0) & (bonds["initially_intact"] != 0))
    corner = np.array([0.25, 0.25])

    def chord_angle(reach: float) -> float | None:
        """Angle (deg, upward from the horizontal, the crack heading left) of the chord
        from the corner to the first path vertex at least ``reach`` from it (also the
        verify case micropolar_l_panel)."""
        from peridynamics.analysis.crack_chord import chord_angle_from

        angle = chord_angle_from(verts, corner, reach, heading=(-1.0, 0.0))
        return None if np.isnan(angle) else angle

    first = r.get("first_break_m")
    res = {
        "first_break_m": first,
        "first_break_distance_from_corner_m": (
            None if first is None else float(np.linalg.norm(np.asarray(first) - corner))
        ),
        "crack_angle_first_25mm_deg": chord_angle(0.025),
        "crack_angle_first_50mm_deg": chord_angle(0.05),
        "crack_length_m": float(crack["length_m"]),
        "crack_tip_m": list(map(float, crack["tip_m"])),
        "crack_end_m": verts[np.argmin(verts[:, 0])].tolist() if len(verts) else None,
        "crack_reaches_left_edge": bool(len(verts) and verts[:, 0].min() <= 0.01),
        "peak_load_kN": float(p.max() / 1e3),
        "displacement_at_peak_mm": float(d[int(np.argmax(p))] * 1e3),
        "experiment_peak_kN": 7.219,
        "peak_ratio_pd_to_experiment": float(p.max() / 1e3 / 7.219),
        "initial_stiffness_kN_per_mm": float(p[1] / d[1] / 1e6) if len(p) > 1 else None,
        "broken_pairs": int(len(broken)),
    }
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 4.2))
    ax[0].plot(d * 1e3, p / 1e3, "-", lw=0.8, label="micropolar PD")
    ax[0].plot(WINKLER_A[:, 0], WINKLER_A[:, 1], "ks", ms=4, label="experiment (Winkler, A)")
    ax[0].set(xlabel="load-point displacement (mm)", ylabel="load (kN)", title="P-Delta")
    ax[0].legend()
    outline = np.array([[0, 0], [0.25, 0], [0.25, 0.25], [0.5, 0.25], [0.5, 0.5], [0, 0.5], [0, 0]])
    ax[1].plot(outline[:, 0], outline[:, 1], "k-", lw=1)
    if len(verts):
        ax[1].plot(verts[:, 0], verts[:, 1], "r-", lw=2, label="PD crack path")
    ax[1].set(aspect="equal", xlabel="x (m)", ylabel="y (m)", title="crack path")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig(out / "l_panel" / "l_panel.png", dpi=120)
    plt.close(fig)
    return res


CASES = {"cantilever": cantilever, "dcb": dcb, "l_panel": l_panel}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("cases", nargs="*", default=list(CASES), choices=list(CASES))
    ap.add_argument("--out", type=Path, default=Path("results/micropolar"))
    ap.add_argument("--set", action="append", default=[], help="deck override key=value")
    ap.add_argument("--no-run", action="store_true", help="re-analyse existing runs")
    args = ap.parse_args(argv)
    for case in args.cases or list(CASES):
        summary = run_case(case, args.out, list(args.set), not args.no_run)
        res = CASES[case](args.out, summary)
        res["timing"] = summary.get("timing", {})
        res["solver"] = {
            k: summary["results"].get(k)
            for k in ("solves", "breaking_events", "factorizations", "time_per_event_s")
        }
        (args.out / case / f"{case}.json").write_text(json.dumps(res, indent=2))
        print(case, json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
