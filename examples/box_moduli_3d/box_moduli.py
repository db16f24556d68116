"""A 3-D box under uniaxial traction: runs ``deck.yaml`` (bond-based PMB) and ``lps.yaml``
(the linear peridynamic solid) to static equilibrium, fits the interior strains and draws
the interior displacements against the fits.

Usage::

    python examples/box_moduli_3d/box_moduli.py                      # both decks, their size
    python examples/box_moduli_3d/box_moduli.py --figures examples/box_moduli_3d
    python examples/box_moduli_3d/box_moduli.py --set 'geometry.size=[0.03, 0.012, 0.012]'

Each deck runs into ``<out>/<deck name>/``; the figure ``box_moduli.png`` and the numbers
``box_moduli.json`` go to ``--figures`` (default ``<out>``).

Measured per deck: the strains of a least-squares linear fit of the displacement over the
points farther than one horizon from every face (the measure of the verify cases
``pmb_box_moduli`` and ``lps_box_nu_*``, :mod:`peridynamics.app.verify_moduli`); from
them the interior modulus E = sigma / eps_xx (in units of the deck's E0) and the strain
ratio nu = -(eps_yy + eps_zz) / (2 eps_xx), against 1/4 for the isotropic bond-based
family (Silling (2000)) and the LPS deck's ``material.poisson_ratio``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
DECKS = {"pmb": HERE / "deck.yaml", "lps": HERE / "lps.yaml"}


def run(which: str, out: Path, sets: list[str]) -> Path:
    """Run deck ``which`` (``pmb`` or ``lps``) with the ``--set`` overrides into
    ``out/<deck name>``; returns the run folder."""
    import yaml

    import peridynamics as pd
    from peridynamics.deck import apply_overrides

    data = apply_overrides(yaml.safe_load(DECKS[which].read_text()), sets)
    folder = out / str(data["name"])
    pd.Simulation(pd.Deck.from_dict(data, base_dir=HERE), out=folder).run()
    return folder


def measure(folder: Path) -> dict[str, Any]:
    """The interior fit of one finished run: E/E0, nu and the reference nu."""
    from peridynamics.app.verify_moduli import interior_e_ratio, interior_nu

    summary = json.loads((folder / "summary.json").read_text())
    summary["folder"] = str(folder)
    material = summary["inputs"]["material"]
    nu_ref = float(material.get("poisson_ratio") or 0.25)
    nu = interior_nu(summary)
    return {
        "n_points": int(summary["results"]["n_points"]),
        "horizon_m": float(summary["results"]["horizon_m"]),
        "E_over_E0": interior_e_ratio(summary),
        "nu": nu,
        "nu_reference": nu_ref,
        "nu_relative_error": nu / nu_ref - 1.0,
    }


def figure(folders: dict[str, Path], numbers: dict[str, dict[str, Any]], path: Path) -> None:
    """Interior u_x against x and u_y, u_z against y, z, with the fitted lines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for which, folder in folders.items():
        state = np.load(folder / "final_state.npz")
        x, u = np.asarray(state["x"]), np.asarray(state["u"])
        margin = numbers[which]["horizon_m"]
        lo, hi = x.min(axis=0), x.max(axis=0)
        inner = np.all((x > lo + margin) & (x < hi - margin), axis=1)
        xc = x - x[inner].mean(axis=0)
        uc = u - u[inner].mean(axis=0)
        n = numbers[which]
        label = f"{which.upper()}: E = {n['E_over_E0']:.4f} E0"
        axes[0].plot(1e3 * xc[inner, 0], 1e6 * uc[inner, 0], ".", ms=2, label=label)
        for k, name in ((1, "y"), (2, "z")):
            axes[1].plot(
                1e3 * xc[inner, k], 1e6 * uc[inner, k], ".", ms=2,
                label=f"{which.upper()} u_{name}" + (f": nu = {n['nu']:.4f}" if k == 1 else ""),
            )  # fmt: skip
    axes[0].set(xlabel="x from the centre (mm)", ylabel="u_x (µm)", title="interior: axial")
    axes[1].set(xlabel="y or z from the centre (mm)", ylabel="u_y, u_z (µm)",
                title="interior: lateral")  # fmt: skip
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> dict[str, dict[str, Any]]:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", type=Path, default=Path("results/box_moduli_3d"))
    p.add_argument("--figures", type=Path, default=None, help="default: --out")
    p.add_argument("--decks", nargs="+", choices=sorted(DECKS), default=["pmb", "lps"])
    p.add_argument("--set", action="append", default=[], dest="sets")
    args = p.parse_args(argv)
    figures = args.figures or args.out
    figures.mkdir(parents=True, exist_ok=True)
    folders = {which: run(which, args.out, args.sets) for which in args.decks}
    numbers = {which: measure(folder) for which, folder in folders.items()}
    figure(folders, numbers, figures / "box_moduli.png")
    report = {"overrides": args.sets, "runs": numbers}
    (figures / "box_moduli.json").write_text(json.dumps(report, indent=2) + "\n")
    for which, n in numbers.items():
        print(f"{which}: E/E0 = {n['E_over_E0']:.4f}, nu = {n['nu']:.4f} "
              f"(reference {n['nu_reference']})")  # fmt: skip
    return numbers


if __name__ == "__main__":
    main()
