"""Figures (matplotlib, Agg backend): damage maps and probe histories."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from numpy.typing import NDArray  # noqa: E402


def plot_damage(
    path: Path,
    x: NDArray,
    damage: NDArray,
    spacing: float,
    title: str,
    outlines: list[NDArray] | None = None,
) -> None:
    """Scatter of local damage over the reference configuration (2-D; 3-D: max over z).
    ``outlines``: closed polygons (k, 2) drawn on top (rigid bodies, in their final
    position)."""
    if x.shape[1] == 3:  # project: largest damage along z for each (x, y) column
        keys = np.floor((x[:, :2] - x[:, :2].min(axis=0)) / spacing + 0.5).astype(np.int64)
        _, inv = np.unique(keys, axis=0, return_inverse=True)
        dmax = np.zeros(inv.max() + 1)
        np.maximum.at(dmax, inv, damage)
        first = np.unique(inv, return_index=True)[1]
        x, damage = x[first, :2], dmax
    span = np.ptp(x, axis=0)
    aspect = float(span[1] / span[0]) if span[0] > 0 else 1.0
    fig, ax = plt.subplots(figsize=(8, max(2.5, min(8, 8 * aspect)) + 0.8))
    size = max(0.5, 6e4 / len(x)) if len(x) else 1
    sc = ax.scatter(
        x[:, 0], x[:, 1], c=damage, s=size, cmap="jet", vmin=0, vmax=1, marker="s", linewidths=0
    )
    for poly in outlines or ():
        closed = np.vstack([poly, poly[:1]])
        ax.fill(closed[:, 0], closed[:, 1], color="0.6", alpha=0.5, lw=0.8, ec="0.2")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title)
    fig.colorbar(sc, ax=ax, label="damage", shrink=0.8)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)


def plot_histories(
    path: Path,
    time: list[float],
    series: dict[str, list[float]],
    title: str,
    xlabel: str = "time (us)",
    xscale: float = 1e6,
) -> None:
    """One panel per series against time (plotted in us unless told otherwise)."""
    n = max(1, len(series))
    fig, axes = plt.subplots(n, 1, figsize=(8, 2.4 * n + 0.6), sharex=True, squeeze=False)
    t_us = np.asarray(time) * xscale
    for ax, (name, values) in zip(axes[:, 0], series.items(), strict=False):
        ax.plot(t_us, values, lw=1.2)
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel(xlabel)
    axes[0, 0].set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
