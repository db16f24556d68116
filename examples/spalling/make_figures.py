"""Lu & Wang (2016), Figs 7 and 8 (rock-bar waves and spalling) with one command.

    python examples/spalling/make_figures.py [--out DIR]

* ``seed000_fig7a.png``: stress history at x = 0.5 m for FDM and PD with delta = 1, 2, 4, 8 dx
  (the ``wave_*.yaml`` decks).
* ``seed000_fig7b.png``: PD with delta = 3 dx, dx = 5 mm vs 10 mm and t0 = 0.12 vs 0.24 ms.
* ``seed000_fig8a.png``: damage along the bar at the fracture time of Table 1 case 1.
* ``seed000_fig8b.png``: tensile stress profiles near the free end at several times before
  fracture (case 1), from the bond-force flux across every section.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
try:
    import peridynamics  # noqa: F401
except ImportError:  # running from a checkout without installing
    sys.path.insert(0, str(HERE.parents[1] / "src"))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from peridynamics.app.run import Simulation  # noqa: E402
from peridynamics.deck import load_deck  # noqa: E402


def _finish(fig: plt.Figure, ax: plt.Axes, path: Path) -> Path:
    """Grid, legend, tight layout, save and close."""
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def _stress_history(
    deck: Path, overrides: list[str] | None = None, position: float = 0.5025
) -> tuple[np.ndarray, np.ndarray]:
    sim = Simulation.from_deck(load_deck(deck, overrides or []))
    s = sim.solver.init()
    t, sig = [0.0], [sim.model.section_stress(s.u, s.intact, position)]
    for st in sim.solver.irun(s, sim.n_steps):
        t.append(st.t)
        sig.append(sim.model.section_stress(st.u, st.intact, position))
    return np.array(t), np.array(sig)


def fig7a(out: Path) -> Path:
    """FDM and PD (delta = 1, 2, 4, 8 dx) stress at x = 0.5 m."""
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for kind, label in [
        ("fdm", "FDM"),
        ("pd_m1", "PD, δ = Δx"),
        ("pd_m2", "PD, δ = 2Δx"),
        ("pd_m4", "PD, δ = 4Δx"),
        ("pd_m8", "PD, δ = 8Δx"),
    ]:
        t, sig = _stress_history(HERE / f"wave_{kind}.yaml")
        ax.plot(
            t * 1e3,
            sig / 1e6,
            lw=1.8 if kind == "fdm" else 1.2,
            ls="--" if kind == "pd_m1" else "-",
            label=label,
        )
    ax.set(
        xlabel="time (ms)",
        ylabel="stress at x = 0.5 m (MPa, tension +)",
        title="Seed 000 Fig. 7(a): Δx = 5 mm, Δt = 1 µs, p_m = 8.9 MPa, t0 = 0.12 ms",
    )
    return _finish(fig, ax, out / "seed000_fig7a.png")


def fig7b(out: Path) -> Path:
    """delta = 3 dx: dx 5 vs 10 mm, t0 0.12 vs 0.24 ms (rise t0/3)."""
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    deck = HERE / "wave_pd_m1.yaml"
    for dx, t0 in [(0.005, 1.2e-4), (0.01, 1.2e-4), (0.005, 2.4e-4), (0.01, 2.4e-4)]:
        sets = [
            f"discretisation.spacing={dx}",
            "discretisation.horizon_factor=3.0",
            f"boundary_conditions.0.time_function.duration={t0}",
            f"boundary_conditions.0.time_function.rise_time={t0 / 3}",
            "solver.end_time=5.0e-4",
        ]
        pos = 0.5 + dx / 2
        t, sig = _stress_history(deck, sets, position=pos)
        ax.plot(t * 1e3, sig / 1e6, label=f"Δx = {dx * 1e3:g} mm, t0 = {t0 * 1e3:g} ms")
    ax.set(
        xlabel="time (ms)",
        ylabel="stress at x = 0.5 m (MPa, tension +)",
        title="Seed 000 Fig. 7(b): PD with δ = 3Δx",
    )
    return _finish(fig, ax, out / "seed000_fig7b.png")


def fig8(out: Path) -> list[Path]:
    """Case 1: damage at fracture (a) and tensile stress near the free end over time (b)."""
    sim = Simulation.from_deck(load_deck(HERE / "table1_case1.yaml"))
    model, solver = sim.model, sim.solver
    s = solver.init()
    x = model.cloud.x[:, 0]
    sections = np.arange(0.80, 0.995, 0.002) + 0.0005
    times = [3.9e-4, 4.1e-4, 4.2e-4, 4.3e-4, 4.39e-4]
    profiles: dict[float, np.ndarray] = {}
    dt = solver.dt
    fracture_t, damage = None, None
    while s.step < sim.n_steps:
        solver.step(s)
        for tt in times:
            if tt not in profiles and s.t >= tt - 0.5 * dt:
                profiles[tt] = np.array([model.section_stress(s.u, s.intact, p) for p in sections])
        phi = model.point_damage(s.intact)
        if phi.max() >= 0.3:
            fracture_t, damage = s.t, phi
            break
    paths = []
    fig, ax = plt.subplots(figsize=(7.5, 4))
    ax.plot(x, damage, lw=1.2)
    ax.axhline(0.3, color="k", ls=":", lw=1, label="φ0 = 0.3")
    ax.set(
        xlim=(0.85, 0.95),
        xlabel="x (m)",
        ylabel="damage",
        title=f"Seed 000 Fig. 8(a): damage at fracture, case 1, t_F = {fracture_t * 1e3:.4f} ms",
    )
    paths.append(_finish(fig, ax, out / "seed000_fig8a.png"))
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for tt, prof in profiles.items():
        ax.plot(sections, prof / 1e6, label=f"t = {tt * 1e3:.3f} ms")
    ax.axhline(10.0, color="k", ls=":", lw=1, label="σ_t = 10 MPa")
    ax.set(
        xlabel="x (m)",
        ylabel="stress (MPa, tension +)",
        title="Seed 000 Fig. 8(b): tensile stress near the free end, case 1",
    )
    paths.append(_finish(fig, ax, out / "seed000_fig8b.png"))
    return paths


def make_figures(out: Path) -> list[Path]:
    """All figures into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    return [fig7a(out), fig7b(out), *fig8(out)]


def main(argv: list[str] | None = None) -> int:
    """Command line."""
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", type=Path, default=HERE)
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    for path in make_figures(args.out):
        print(f"wrote {path}")
    print(f"{time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
