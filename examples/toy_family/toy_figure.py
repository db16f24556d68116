"""The toy family's figure: its strain-energy density on a plate stretched by 0.1 %, and
its force against the finite-difference gradient of its energy (the contract's oracle,
force = -grad(energy), Silling et al. (2007), eq. 5 for bond-based forces).

Usage::

    python examples/toy_family/toy_figure.py --out examples/toy_family

Writes ``toy_family.png`` and ``toy_family.json`` (the largest relative gap between
the force and the central-difference gradient over the checked degrees of freedom).
"""

from __future__ import annotations

import argparse
import json
import runpy
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent


def _toy_spring_model() -> Any:
    """``ToySpringModel`` of ``toy_family.py`` (beside this script, not a package)."""
    return runpy.run_path(str(HERE / "toy_family.py"), run_name="toy_family")["ToySpringModel"]


def measure(n_checked: int = 40, seed: int = 0) -> dict[str, Any]:
    """The plate (10 x 10 mm, dx = 0.5 mm, delta = 3.015 dx, c = 1e20 N/m^6) stretched by
    0.1 %: energy density (J/m^3) per point; then a random displacement of 1e-6 m
    amplitude and, at ``n_checked`` random degrees of freedom, the force times the
    point's volume (N) against -dW/du by central differences (step 1e-9 m: the gap is
    the differences' O(h^2) truncation and round-off, 4e-10 of the largest force)."""
    from peridynamics.bonds.bonds import build_bonds
    from peridynamics.geometry.generators import rectangle
    from peridynamics.state import State

    plate = rectangle((0.01, 0.01), 5e-4, thickness=1e-3, plane="stress")
    model = _toy_spring_model()(plate, build_bonds(plate, 3.015 * 5e-4), c=1e20)
    n = plate.n_points

    def state(u: np.ndarray) -> Any:
        return State(u=u, force=np.zeros((n, 2)), max_stretch=np.zeros(n),
                     intact=np.ones(model.bonds.n_bonds, dtype=np.uint8))  # fmt: skip

    def energy(u: np.ndarray) -> float:
        return float(np.sum(model.energy_density(state(u)) * plate.volume))

    stretched = state(1e-3 * plate.x)
    density = model.energy_density(stretched)
    rng = np.random.default_rng(seed)
    u = 1e-6 * rng.standard_normal((n, 2))
    st = state(u.copy())
    model.force(st)
    analytic, numeric = [], []
    h = 1e-9
    for flat in rng.choice(2 * n, size=n_checked, replace=False):
        i, k = divmod(int(flat), 2)
        up, down = u.copy(), u.copy()
        up[i, k] += h
        down[i, k] -= h
        numeric.append(-(energy(up) - energy(down)) / (2 * h))
        analytic.append(float(st.force[i, k] * plate.volume[i]))
    a, g = np.array(analytic), np.array(numeric)
    return {
        "x": plate.x, "density": density, "analytic": a, "numeric": g,
        "max_relative_gap": float(np.max(np.abs(a - g)) / np.max(np.abs(g))),
        "n_points": n, "n_checked": n_checked,
    }  # fmt: skip


def figure(m: dict[str, Any], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    sc = axes[0].scatter(1e3 * m["x"][:, 0], 1e3 * m["x"][:, 1], c=m["density"], s=14,
                         cmap="viridis")  # fmt: skip
    fig.colorbar(sc, ax=axes[0], label="energy density (J/m³)")
    axes[0].set(xlabel="x (mm)", ylabel="y (mm)", aspect="equal",
                title="toy springs: plate stretched by 0.1 %")  # fmt: skip
    lim = 1.1 * float(np.max(np.abs(m["numeric"])))
    axes[1].plot([-lim, lim], [-lim, lim], "k-", lw=0.8, label="force = −∂W/∂u")
    axes[1].plot(m["numeric"], m["analytic"], "o", ms=4,
                 label=f"{m['n_checked']} dofs, max gap {m['max_relative_gap']:.1e}")  # fmt: skip
    axes[1].set(xlabel="−∂W/∂u by central differences (N)", ylabel="force × volume (N)",
                title="the contract's oracle")  # fmt: skip
    axes[1].legend(fontsize=8)
    axes[1].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", type=Path, default=Path("results/toy_family"))
    args = p.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    m = measure()
    figure(m, args.out / "toy_family.png")
    rec = {k: m[k] for k in ("n_points", "n_checked", "max_relative_gap")}
    (args.out / "toy_family.json").write_text(json.dumps(rec, indent=2) + "\n")
    print(f"force against -grad(energy): largest relative gap {rec['max_relative_gap']:.2e}")
    return rec


if __name__ == "__main__":
    main()
