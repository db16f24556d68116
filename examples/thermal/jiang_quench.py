"""Thermal-shock benchmark: the quenched alumina plates of Jiang et al. (2012).

Usage: ``python jiang_quench.py [OUT] [--set KEY=VALUE ...]``: runs
``jiang_quench.yaml`` at T0 = 300 C and 600 C (one run after the other; set
``NUMBA_NUM_THREADS=1`` on a shared machine), counts the edge cracks of the final
damage field and writes ``OUT/jiang_quench.json`` and ``OUT/jiang_quench.png`` (the
damage maps at both T0 and the histogram of the crack lengths). ``--set`` values change
both runs (``--set solver.end_time=0.05``).

Post-processing (a regular grid of points, spacing ``dx``, is assumed):

* **crack starts**: along each long edge (top, bottom) the damage of the row of points
  ``probe_rows`` spacings inside the edge; every run of consecutive points whose damage
  is at least ``threshold`` is one crack, placed at its damage maximum. The ``margin``
  at both ends (the corners, cooled from two sides) is left out.
* **crack length**: from a start, the crack is followed row by row into the plate (the
  damage maximum within ``window`` spacings of the previous row's position) while that
  maximum is at least ``threshold``; the length is the distance from the edge surface
  to the far side of the last such point's cell.
* **length classes**: the sorted lengths split wherever one is more than ``gap_ratio``
  times the next shorter one and longer by more than two spacings (a gap in the
  hierarchy the grid can resolve).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

DECK = Path(__file__).with_name("jiang_quench.yaml")
T0_C = (300.0, 600.0)  # the two quench temperatures (C)
THRESHOLD = 0.3  # the damage a point of a crack has at least (-)
PROBE_ROWS = 2  # the row of the crack starts, in spacings inside the edge
WINDOW = 2  # the lateral search of the crack following, in spacings
GAP_RATIO = 1.4  # the ratio of consecutive sorted lengths that starts a new class
MARGIN = 1.0e-3  # left out at both ends of a long edge (m)


def grid(x: NDArray[np.float64], dx: float) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Column and row indices (n,) of points ``x`` (n, 2) in m on a regular grid of
    spacing ``dx`` (m), counted from the smallest coordinates."""
    ij = np.rint((x - x.min(axis=0)) / dx).astype(np.intp)
    return ij[:, 0], ij[:, 1]


def damage_image(x: NDArray[np.float64], damage: NDArray[np.float64], dx: float) -> NDArray:
    """The damage (n,) of points ``x`` (n, 2) as an image (n_rows, n_columns); cells
    without a point hold 0."""
    col, row = grid(x, dx)
    img = np.zeros((row.max() + 1, col.max() + 1))
    img[row, col] = damage
    return img


def crack_starts(profile: NDArray[np.float64], threshold: float) -> list[int]:
    """Indices of the damage maximum of every run of consecutive entries of ``profile``
    (n,) that are at least ``threshold``."""
    above = np.concatenate(([False], profile >= threshold, [False]))
    edges = np.flatnonzero(np.diff(above.astype(np.int8)))
    return [int(a + np.argmax(profile[a:b])) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def follow(img: NDArray[np.float64], col: int, threshold: float, window: int) -> int:
    """Rows (from row 0, the edge row, inward) a crack starting at column ``col``
    crosses: the count of consecutive rows whose damage maximum within ``window``
    columns of the previous row's maximum is at least ``threshold``."""
    n = 0
    for row in img:
        lo, hi = max(col - window, 0), min(col + window + 1, row.size)
        j = lo + int(np.argmax(row[lo:hi]))
        if row[j] < threshold:
            break
        col, n = j, n + 1
    return n


def edge_cracks(
    x: NDArray[np.float64],
    damage: NDArray[np.float64],
    dx: float,
    *,
    threshold: float = THRESHOLD,
    probe_rows: int = PROBE_ROWS,
    window: int = WINDOW,
    margin: float = MARGIN,
) -> dict[str, list[dict[str, float]]]:
    """The cracks from the two long edges (the y extremes) of a plate.

    Parameters
    ----------
    x : ndarray (n, 2)
        Point positions (m), a regular grid of spacing ``dx``.
    damage : ndarray (n,)
        Point damage (-).
    dx : float
        The grid spacing (m).
    threshold, probe_rows, window, margin
        As in the module's description (damage; spacings; spacings; m).

    Returns
    -------
    dict
        ``{"top": [...], "bottom": [...]}``, each crack ``{"x_m": position along the
        edge, "length_m": depth from the edge surface}``, ordered by position.
    """
    img = damage_image(x, damage, dx)
    x0 = float(x[:, 0].min())
    out: dict[str, list[dict[str, float]]] = {}
    for name, rows in (("bottom", img), ("top", img[::-1])):
        found = []
        for j in crack_starts(rows[probe_rows], threshold):
            pos = x0 + j * dx
            if pos < x0 + margin or pos > float(x[:, 0].max()) - margin:
                continue
            n = follow(rows, j, threshold, window)
            found.append({"x_m": pos, "length_m": n * dx})
        out[name] = found
    return out


def length_classes(lengths: Sequence[float], dx: float, gap_ratio: float = GAP_RATIO) -> list:
    """The sorted ``lengths`` (m) split into classes at the gaps (module description);
    returns the classes, longest first, each a list of lengths (m)."""
    ordered = sorted(lengths, reverse=True)
    classes: list[list[float]] = []
    for length in ordered:
        prev = classes[-1][-1] if classes else None
        if prev is None or (prev > gap_ratio * length and prev - length > 2.0 * dx):
            classes.append([length])
        else:
            classes[-1].append(length)
    return classes


def summarise(cracks: dict[str, list[dict[str, float]]], span: float, dx: float) -> dict:
    """Counts, densities, spacings and length classes of ``edge_cracks``' result; ``span``
    (m) is the length of edge searched on each long edge."""
    lengths = [c["length_m"] for side in cracks.values() for c in side]
    gaps = [
        b["x_m"] - a["x_m"]
        for side in cracks.values()
        for a, b in zip(side[:-1], side[1:], strict=True)
    ]
    classes = length_classes(lengths, dx)
    return {
        "cracks_top": len(cracks["top"]),
        "cracks_bottom": len(cracks["bottom"]),
        "cracks_per_mm": len(lengths) / (2.0 * span * 1e3),
        "mean_spacing_mm": float(np.mean(gaps) * 1e3) if gaps else None,
        "longest_mm": max(lengths) * 1e3 if lengths else 0.0,
        "mean_length_mm": float(np.mean(lengths) * 1e3) if lengths else 0.0,
        "n_classes": len(classes),
        "classes_mm": [[round(v * 1e3, 4) for v in c] for c in classes],
        "cracks": cracks,
    }


def run(t0_c: float, out: Path, overrides: Sequence[str] = ()) -> dict[str, Any]:
    """Run the deck quenched from ``t0_c`` (C) into ``out``; return its final ``x``,
    ``damage``, the spacing and the summary's results."""
    import peridynamics as pd

    over = [f"thermal.initial_temperature={t0_c + 273.15}", "output.plot=none", *overrides]
    result = pd.Simulation(DECK, over, out=out).run()
    final = result.final
    res = result.summary["results"]
    return {"x": final["x"], "damage": final["damage"], "dx": res["spacing_m"], "results": res}


def analyse(x: NDArray[np.float64], damage: NDArray[np.float64], dx: float) -> dict:
    """``summarise`` of the edge cracks of one run."""
    span = float(np.ptp(x[:, 0])) + dx - 2.0 * MARGIN
    return summarise(edge_cracks(x, damage, dx), span, dx)


def figure(runs: dict[float, dict[str, Any]], stats: dict[float, dict], path: Path) -> None:
    """Damage maps (one per T0) and the histogram of the crack lengths, to ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(runs) + 1, 1, figsize=(9, 2.4 * len(runs) + 2.6))
    for ax, (t0, r) in zip(axes[:-1], runs.items(), strict=True):
        x = r["x"] * 1e3
        sc = ax.scatter(x[:, 0], x[:, 1], c=r["damage"], s=2, cmap="magma_r", vmin=0, vmax=1)
        ax.set(aspect="equal", ylabel="y (mm)", title=f"T0 = {t0:.0f} C: damage")
        fig.colorbar(sc, ax=ax, fraction=0.02)
    axes[-2].set_xlabel("x (mm)")
    hi = max((s["longest_mm"] for s in stats.values()), default=1.0)
    bins = np.arange(0.0, hi + 0.5, 0.25)
    for t0, s in stats.items():
        lengths = [c["length_m"] * 1e3 for side in s["cracks"].values() for c in side]
        axes[-1].hist(lengths, bins=bins, alpha=0.6, label=f"T0 = {t0:.0f} C")
    axes[-1].set(xlabel="crack length (mm)", ylabel="cracks", title="edge-crack lengths")
    axes[-1].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(out: Path, overrides: Sequence[str] = ()) -> dict[float, dict]:
    """Run both quench temperatures into ``out/T0_<C>``, write the JSON and figure."""
    runs, stats = {}, {}
    for t0 in T0_C:
        runs[t0] = run(t0, out / f"T0_{t0:.0f}", overrides)
        stats[t0] = analyse(runs[t0]["x"], runs[t0]["damage"], runs[t0]["dx"])
        res = runs[t0]["results"]
        stats[t0]["bonds_broken"] = res["bonds_broken"]
        stats[t0]["max_kinetic_to_strain_energy"] = res.get("max_kinetic_to_strain_energy")
        brief = {k: v for k, v in stats[t0].items() if k not in ("cracks", "classes_mm")}
        print(f"T0 = {t0:.0f} C: {brief}")
    settings = {
        "threshold": THRESHOLD,
        "probe_rows": PROBE_ROWS,
        "window": WINDOW,
        "gap_ratio": GAP_RATIO,
        "margin_m": MARGIN,
        "overrides": list(overrides),
    }
    doc = {"settings": settings, "runs": {f"{t:.0f}": s for t, s in stats.items()}}
    (out / "jiang_quench.json").write_text(json.dumps(doc, indent=1))
    figure(runs, stats, out / "jiang_quench.png")
    return stats


if __name__ == "__main__":
    args = sys.argv[1:]
    sets = [args[i + 1] for i, a in enumerate(args[:-1]) if a == "--set"]
    rest = [a for i, a in enumerate(args) if a != "--set" and (i == 0 or args[i - 1] != "--set")]
    main(Path(rest[0] if rest else "out_jiang"), sets)
