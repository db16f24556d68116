"""Figures and measured numbers of the research-outputs example (``notched_plate.yaml``).

Usage::

    python examples/research/make_figures.py                   # the deck as shipped
    python examples/research/make_figures.py --publish         # also copy into this folder
    python examples/research/make_figures.py --out results/np_coarse \
        --set discretisation.spacing=1e-3 --set discretisation.horizon_factor=3
    python examples/research/make_figures.py --no-run          # re-analyse a run

Runs the deck into ``<out>/`` (default ``results/notched_plate``); the deck itself writes
its figures there (``notched_plate_damage.png``, ``_deformed``, ``_probes``,
``_energies``), its frames and ``history.csv``. This script adds ``notched_plate.json``
(the measured numbers) and ``notched_plate.png`` (the load against the crack-mouth
opening, which the deck's own probe figure shows only against time, with the events
marked; the crack lengths against time). ``--publish`` copies ``notched_plate.png``,
``notched_plate.json`` and the deck's ``notched_plate_damage.png`` into this folder.

Measured (the plate is 1 mm thick; loads are for that thickness):

* the peak of the grip load (``load``: the reaction force on the top grip), its time and
  the crack-mouth opening (``cmod``) there; the load and CMOD at the first broken bond
  and at fracture (``results.events``);
* the crack: the polyline of ``output.crack_paths`` (length, tip, largest tip speed
  against the Rayleigh speed of the model as run, ``results.rayleigh_speed_m_per_s``),
  the crack length from the bonds broken in the run with and without the separating
  test (``crack_length_m``, ``crack_length_all_bonds_m``);
* the energy balance: the work of the two grips, 2 int F v dt (the trapezoid rule over
  the history records; v the deck's ramp to 0.5 m/s over 10 us; the bottom grip's work
  equals the top's by symmetry), less the final kinetic and strain energy, is the energy
  the broken bonds took; it is compared with G0 t times each crack length.
"""

from __future__ import annotations

import argparse
import csv
import json
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
CASE = "notched_plate"


def run(out: Path, sets: list[str], no_run: bool) -> tuple[Any, dict[str, Any]]:
    """Run the deck into ``out`` (unless ``no_run``); (deck, summary)."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    deck = load_deck(HERE / f"{CASE}.yaml", overrides=sets)
    if not no_run:
        Simulation.from_deck(deck).run(out, quiet=True, progress=False)
    return deck, json.loads((out / "summary.json").read_text())


def _history(out: Path) -> dict[str, Any]:
    with open(out / "history.csv") as fh:
        rows = list(csv.reader(fh))
    body = np.array(rows[1:], dtype=float)
    return {name.split(" [")[0]: body[:, k] for k, name in enumerate(rows[0])}


def _grip_velocity(deck: Any, t: Any) -> Any:
    """The top grip's y velocity at the times t (the deck's ramp, else constant)."""
    bc = next(b for b in deck.boundary_conditions if getattr(b, "set", None) == "top")
    v = float(bc.components["y"])
    tf = getattr(bc, "time_function", None)
    if tf is None:
        return np.full_like(t, v)
    if tf.type != "ramp":
        raise ValueError(f"only a ramp time function is integrated, not {tf.type!r}")
    start = float(tf.start)
    return v * np.clip((t - start) / (float(tf.end) - start), 0.0, 1.0)


def analyse(out: Path, deck: Any, summary: dict[str, Any]) -> dict[str, Any]:
    """The measured numbers (module docstring)."""
    r = summary["results"]
    h = _history(out)
    t, load, cmod = h["time"], h["load"], h["cmod"]
    k = int(np.argmax(load))
    ev = r["events"]

    def at(name: str) -> dict[str, float] | None:
        if name not in ev:
            return None
        te = ev[name]["time_s"]
        return {
            "time_s": te,
            "load_N": float(np.interp(te, t, load)),
            "cmod_m": float(np.interp(te, t, cmod)),
        }

    crack = r["crack_paths"]["crack"]
    c_r = r["rayleigh_speed_m_per_s"]
    thickness = deck.geometry.thickness
    g0 = deck.damage.fracture_energy
    work = 2.0 * float(np.trapezoid(load * _grip_velocity(deck, t), t))
    kinetic, strain = float(h["kinetic_energy"][-1]), float(h["strain_energy"][-1])
    dissipated = work - kinetic - strain
    lengths = {
        "crack_length_m": r["crack_length_m"],
        "crack_length_all_bonds_m": r["crack_length_all_bonds_m"],
        "crack_path_length_m": crack["length_m"],
    }
    return {
        "n_points": r["n_points"],
        "n_bonds": r["n_bonds"],
        "spacing_m": r["spacing_m"],
        "horizon_m": r["horizon_m"],
        "steps": r["steps"],
        "time_step_s": r["time_step_s"],
        "final_time_s": r["final_time_s"],
        "thickness_m": thickness,
        "peak_load_N": float(load[k]),
        "peak_load_time_s": float(t[k]),
        "cmod_at_peak_m": float(cmod[k]),
        "cmod_final_m": float(cmod[-1]),
        "load_final_N": float(load[-1]),
        "first_damage": at("first_damage"),
        "fracture": at("fracture"),
        **lengths,
        "crack_tip_m": crack["tip_m"],
        "crack_path_branches": crack["branches"],
        "max_tip_speed_m_per_s": crack["max_tip_speed_m_per_s"],
        "rayleigh_speed_m_per_s": c_r,
        "effective_modulus_ratio": r.get("effective_modulus_ratio"),
        "max_tip_speed_over_rayleigh": crack["max_tip_speed_m_per_s"] / c_r,
        "records_above_rayleigh": crack["above_rayleigh_speed"],
        "max_damage": r["max_damage"],
        "bonds_broken": r["bonds_broken"],
        "energy": {
            "grip_work_J": work,
            "kinetic_final_J": kinetic,
            "strain_final_J": strain,
            "dissipated_J": dissipated,
            "fracture_energy_J_per_m2": g0,
            **{f"g0_t_{name}_J": g0 * thickness * v for name, v in lengths.items()},
            **{
                f"dissipated_over_g0_t_{name}": dissipated / (g0 * thickness * v)
                for name, v in lengths.items()
            },
        },
        "_plot": (t, load, cmod, h.get("crack_length"), crack, ev),
    }


def plot(res: dict[str, Any], path: Path) -> None:
    """notched_plate.png: load against CMOD with the events; crack lengths over time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t, load, cmod, bond_length, crack, ev = res["_plot"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4.2))
    a1.plot(cmod * 1e6, load, "-", lw=1.2, color="C0", label="grip load")
    marks = {"first_damage": ("C2", "o"), "fracture": ("C1", "s"), "peak_load": ("C3", "^")}
    for name, (color, marker) in marks.items():
        if name in ev:
            te = ev[name]["time_s"]
            label = f"{name.replace('_', ' ')}, {te * 1e6:.1f} us"
            a1.plot(np.interp(te, t, cmod) * 1e6, np.interp(te, t, load), marker, color=color,
                    label=label)  # fmt: skip
    a1.set(xlabel="crack-mouth opening (um)", ylabel="load (N, 1 mm thick)", title="load-CMOD")
    a1.legend(fontsize=8)
    a2.plot(np.asarray(crack["time_s"]) * 1e6, np.asarray(crack["length_history_m"]) * 1e3,
            "-", label="crack path (damage >= 0.25, polyline)")  # fmt: skip
    if bond_length is not None:
        a2.plot(t * 1e6, bond_length * 1e3, "--", label="from broken bonds (crack_length)")
    if "peak_load" in ev:
        a2.axvline(ev["peak_load"]["time_s"] * 1e6, color="C3", lw=0.8, ls=":", label="peak load")
    a2.set(xlabel="t (us)", ylabel="crack length (mm)", title="crack growth from the notch")
    a2.legend(fontsize=8)
    fig.suptitle(
        f"notched glass plate, {res['n_points']} points, dx = {res['spacing_m'] * 1e3:g} mm, "
        f"delta = {res['horizon_m'] * 1e3:g} mm",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path(f"results/{CASE}"))
    ap.add_argument("--set", action="append", default=[], help="deck override key=value")
    ap.add_argument("--no-run", action="store_true", help="re-analyse an existing run")
    ap.add_argument("--publish", action="store_true", help="copy the figures into " + str(HERE))
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    deck, summary = run(args.out, list(args.set), args.no_run)
    res = analyse(args.out, deck, summary)
    plot(res, args.out / f"{CASE}.png")
    res.pop("_plot")
    res["overrides"] = list(args.set)
    res["timing"] = summary.get("timing", {})
    res["script_wall_s"] = time.perf_counter() - t0
    (args.out / f"{CASE}.json").write_text(json.dumps(res, indent=2) + "\n")
    if args.publish:
        for name in (f"{CASE}.png", f"{CASE}.json", f"{CASE}_damage.png"):
            shutil.copyfile(args.out / name, HERE / name)
    print(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
