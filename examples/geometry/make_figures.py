"""Figure and measured numbers of the geometry examples: the STL tube, the Gmsh plate
with a hole and the image-based concrete mesostructure.

Usage::

    python examples/geometry/make_figures.py                  # decks as shipped (3 min)
    python examples/geometry/make_figures.py --out /tmp/geo --spacing-factor 2.5
                                                              # every deck coarser

For each deck: the cloud's volume against the solid it describes (the tube: pi (R^2 -
r^2) h and the 48-facet tube of the STL; the plate: its CAD volume 7214.60 mm^3; the
concrete: the image less its pores), then the run (``peridynamics run``) into
``<out>/<deck>/``: the peak reaction of each. Writes ``<out>/geometry.json`` (the
numbers) and ``<out>/geometry.png``: the tube's points, the plate's points coloured by
physical group, the concrete's phases and its damage at the end of the run.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
DECKS = ("tube", "part", "concrete")
#: the solids the decks describe (m^3): the round tube, the 48-facet tube of the STL
#: (polygon area n/2 sin(2 pi / n) R^2), the plate's CAD volume
R_OUT, R_IN, HEIGHT, FACETS = 0.010, 0.005, 0.030, 48
TUBE_ROUND = math.pi * (R_OUT**2 - R_IN**2) * HEIGHT
TUBE_STL = 0.5 * FACETS * math.sin(2 * math.pi / FACETS) * (R_OUT**2 - R_IN**2) * HEIGHT
PART_CAD = (40 * 20 * 10 - math.pi * 5**2 * 10) * 1e-9


def measure(name: str, sets: list[str], out: Path) -> dict[str, Any]:
    """Build the deck's cloud, run it, and return its numbers."""
    from peridynamics.build.cloud import build_cloud
    from peridynamics.cli import main as cli
    from peridynamics.deck import load_deck

    deck = load_deck(HERE / f"{name}.yaml", overrides=sets)
    t0 = time.perf_counter()
    cloud = build_cloud(deck)
    rec: dict[str, Any] = {
        "spacing_m": deck.discretisation.spacing,
        "points": cloud.n_points,
        "volume_m3": float(cloud.volume.sum()),
        "build_s": round(time.perf_counter() - t0, 3),
    }
    if name == "tube":
        rec["volume_over_stl_tube"] = rec["volume_m3"] / TUBE_STL
        rec["volume_over_round_tube"] = rec["volume_m3"] / TUBE_ROUND
    elif name == "part":
        rec["volume_over_cad"] = rec["volume_m3"] / PART_CAD
        rec["set_sizes"] = {k: int(len(v)) for k, v in cloud.node_sets.items()}
    else:
        rec["set_sizes"] = {k: int(len(v)) for k, v in cloud.node_sets.items()}
    args = ["run", str(HERE / f"{name}.yaml"), "--out", str(out / name), "--quiet"]
    assert cli(args + [a for s in sets for a in ("--set", s)]) == 0
    summary = json.loads((out / name / "summary.json").read_text())
    probe = summary["results"]["probes"]["reaction"]
    rec["peak_reaction_N"] = float(probe["peak"])
    rec["max_damage"] = float(summary["results"]["max_damage"])
    rec["run_s"] = float(summary["timing"]["wall_s"])
    return rec


def figure(out: Path, numbers: dict[str, Any]) -> Path:
    """Four panels: the tube, the plate by group, the concrete's phases and damage."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(13, 7.5))
    tube = np.load(out / "tube" / "final_state.npz")["x"]
    ax = fig.add_subplot(2, 2, 1, projection="3d")
    ax.scatter(*(1e3 * tube.T), s=2, c=tube[:, 2], cmap="viridis")
    ax.set_title(f"tube.stl filled: {numbers['tube']['points']} points")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    part = np.load(out / "part" / "final_state.npz")["x"]
    ax = fig.add_subplot(2, 2, 2, projection="3d")
    ax.scatter(*(1e3 * part.T), s=1, c="0.75")
    ax.scatter(*(1e3 * part[part[:, 0] < 2e-3].T), s=4, c="tab:blue", label="near x = 0")
    ax.scatter(*(1e3 * part[part[:, 0] > 38e-3].T), s=4, c="tab:red", label="near x = 40")
    ax.set_title(f"part.geo meshed: {numbers['part']['points']} cell centroids")
    ax.legend(loc="upper left", fontsize=8)
    conc = np.load(out / "concrete" / "final_state.npz")
    x, dmg = 1e3 * conc["x"], conc["damage"]
    ax = fig.add_subplot(2, 2, 3)
    from PIL import Image

    with Image.open(HERE / "concrete.png") as img:
        grey = np.asarray(img.convert("L"))
    ax.imshow(grey, cmap="gray", extent=(0, 40, 0, 20), vmin=0, vmax=255)
    ax.set_title("concrete.png: aggregate, mortar, pores (0.2 mm pixels)")
    ax.set_xlabel("x (mm)")
    ax = fig.add_subplot(2, 2, 4)
    sc = ax.scatter(x[:, 0], x[:, 1], c=dmg, s=4, cmap="inferno", vmin=0, vmax=1)
    fig.colorbar(sc, ax=ax, label="damage")
    ax.set_aspect("equal")
    ax.set_title(f"damage at the end, peak {abs(numbers['concrete']['peak_reaction_N']):.0f} N")
    ax.set_xlabel("x (mm)")
    fig.tight_layout()
    path = out / "geometry.png"
    fig.savefig(path, dpi=70)
    plt.close(fig)
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=Path("results") / "geometry")
    ap.add_argument("--spacing-factor", type=float, default=1.0,
                    help="multiply every deck's spacing (2.5: a quick check)")  # fmt: skip
    ap.add_argument("--decks", nargs="+", default=list(DECKS), choices=DECKS)
    args = ap.parse_args(argv)
    from peridynamics.deck import load_deck

    numbers = {}
    for name in args.decks:
        dx = load_deck(HERE / f"{name}.yaml").discretisation.spacing * args.spacing_factor
        numbers[name] = measure(name, [f"discretisation.spacing={dx}"], args.out)
        print(name, json.dumps(numbers[name]))
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "geometry.json").write_text(json.dumps(numbers, indent=2) + "\n")
    if set(args.decks) == set(DECKS):
        print(figure(args.out, numbers))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
