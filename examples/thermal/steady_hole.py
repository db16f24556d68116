"""Steady heat conduction through a plate with a hole: peridynamics against finite elements.

Runs ``steady_hole.yaml`` (bond-based heat conduction, ``solver.type: heat_steady``) and
solves the same plate, 0 <= x <= L, 0 <= y <= W with a hole of radius a at its centre,
by the classical heat equation div(k grad T) = 0 with scikit-fem: quadratic triangles
on the mesh of ``examples/correspondence/fem_reference.py`` (curved on the hole),
T = 300 K on x = 0 and 400 K on x = L, insulated elsewhere. The peridynamic
temperature of every point inside the plate is compared with the finite-element field
there; the difference is reported against the imposed rise T_hot - T_cold and against
the temperature itself.

Usage::

    python examples/thermal/steady_hole.py                     # dx = 1 mm (the deck)
    python examples/thermal/steady_hole.py --spacing 2e-3      # coarser
    python examples/thermal/steady_hole.py --correction none   # another micro-conductivity

Writes ``steady_hole.json`` and ``steady_hole.png`` into ``--out`` (default
``results/steady_hole``). Needs scikit-fem (``pip install ".[test]"``).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import time
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
DECK = HERE / "steady_hole.yaml"
FEM_MESH = HERE.parent / "correspondence" / "fem_reference.py"
T_COLD, T_HOT = 300.0, 400.0


def _fem_module() -> ModuleType:
    spec = importlib.util.spec_from_file_location("steady_hole_fem_mesh", FEM_MESH)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    try:
        spec.loader.exec_module(module)
    finally:
        sys.modules.pop(spec.name, None)
    return module


def fe_temperature(refine: int = 2) -> tuple[Any, np.ndarray, Any]:
    """(basis, nodal temperatures, mesh module) of the classical steady solution."""
    from skfem import Basis, BilinearForm, ElementTriP2, MeshTri1, asm, condense, solve
    from skfem.helpers import dot, grad

    fem = _fem_module()
    curved = fem._mesh(refine)  # its hole's chords are 2 pi a / (32 * 2**refine) long
    mesh = MeshTri1(curved.p, curved.t)  # straight sides: scikit-fem can locate points
    basis = Basis(mesh, ElementTriP2())

    @BilinearForm
    def laplace(u: Any, v: Any, _: Any) -> Any:
        return dot(grad(u), grad(v))

    a = asm(laplace, basis)
    cold = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    hot = basis.get_dofs(lambda x: np.isclose(x[0], fem.LENGTH)).all()
    t = np.zeros(basis.N)
    t[cold], t[hot] = T_COLD, T_HOT
    held = np.concatenate([cold, hot])
    t = solve(*condense(a, x=t, D=held))
    return basis, t, fem


def run_pd(out: Path, sets: list[str]) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """(positions, temperatures, summary) of the peridynamic run."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    sim = Simulation.from_deck(load_deck(DECK, overrides=sets))
    t0 = time.perf_counter()
    sim.run(out, quiet=True, progress=False)
    wall = time.perf_counter() - t0
    f = np.load(out / "final_state.npz")
    summary = json.loads((out / "summary.json").read_text())
    summary["wall_s_measured"] = wall
    return f["x"], f["temperature"], summary


def compare(out: Path, sets: list[str], refine: int = 2) -> dict[str, Any]:
    """Run both and measure the differences (written to ``steady_hole.json``)."""
    x, t_pd, summary = run_pd(out, sets)
    basis, t_fe_nodes, fem = fe_temperature(refine)
    inside = (x[:, 0] > 0.0) & (x[:, 0] < fem.LENGTH)
    pts = x[inside]
    # a point nearer the circle than the chords' sagitta (< 3 um) is moved onto the mesh
    c = np.asarray(fem.CENTRE)
    rad = np.hypot(*(pts - c).T)
    probe = c + (pts - c) * (np.maximum(rad, fem.RADIUS + 1e-5) / rad)[:, None]
    t_fe = basis.probes(probe.T) @ t_fe_nodes
    diff = t_pd[inside] - t_fe
    rise = T_HOT - T_COLD
    r = np.hypot(pts[:, 0] - fem.CENTRE[0], pts[:, 1] - fem.CENTRE[1])
    near_hole = r < fem.RADIUS + 3.015 * float(summary["inputs"]["discretisation"]["spacing"])
    result = {
        "spacing_m": float(summary["inputs"]["discretisation"]["spacing"]),
        "points_compared": int(inside.sum()),
        "fe_dofs": int(basis.N),
        "max_abs_difference_K": float(np.abs(diff).max()),
        "max_difference_over_rise": float(np.abs(diff).max() / rise),
        "rms_difference_over_rise": float(np.sqrt(np.mean(diff**2)) / rise),
        "max_relative_difference": float(np.abs(diff / t_fe).max()),
        "max_difference_over_rise_within_a_horizon_of_the_hole": float(
            np.abs(diff[near_hole]).max() / rise
        ),
        "max_difference_over_rise_elsewhere": float(np.abs(diff[~near_hole]).max() / rise),
        "pd_wall_s": float(summary["wall_s_measured"]),
    }
    (out / "steady_hole.json").write_text(json.dumps(result, indent=1))
    figure(out, pts, t_pd[inside], diff / rise)
    return result


def figure(out: Path, pts: np.ndarray, t_pd: np.ndarray, rel: np.ndarray) -> None:
    """The peridynamic temperature and its difference from the finite elements."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(7.5, 5.6), constrained_layout=True)
    for ax, val, label, cmap in (
        (axes[0], t_pd, "T, peridynamics (K)", "inferno"),
        (axes[1], 100.0 * rel, "(T_PD - T_FE) / (T_hot - T_cold) (%)", "coolwarm"),
    ):
        lim = float(np.abs(val).max()) if cmap == "coolwarm" else None
        sc = ax.scatter(pts[:, 0] * 1e3, pts[:, 1] * 1e3, c=val, s=4, cmap=cmap,
                        vmin=-lim if lim else None, vmax=lim)  # fmt: skip
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
        fig.colorbar(sc, ax=ax, label=label)
    fig.savefig(out / "steady_hole.png", dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", type=Path, default=Path("results/steady_hole"))
    p.add_argument("--spacing", type=float, default=None, help="grid spacing (m)")
    p.add_argument("--correction", default=None, help="thermal.correction")
    p.add_argument("--refine", type=int, default=2, help="finite-element mesh level")
    a = p.parse_args(argv)
    sets = []
    if a.spacing is not None:
        sets.append(f"discretisation.spacing={a.spacing}")
    if a.correction is not None:
        sets.append(f"thermal.correction={a.correction}")
    a.out.mkdir(parents=True, exist_ok=True)
    result = compare(a.out, sets, a.refine)
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
