"""Figures (matplotlib): damage maps and probe histories.

Figures are made as :class:`matplotlib.figure.Figure` objects without pyplot, so that
writing them neither switches the user's backend (a notebook's inline figures) nor
keeps figures in pyplot's global list; ``savefig`` renders with Agg.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from numpy.typing import NDArray


class _Figures:
    """pyplot's ``subplots`` and ``close`` for figures that pyplot does not hold."""

    #: the keywords of ``Figure.subplots``; pyplot passes every other one to the Figure
    GRID = ("sharex", "sharey", "squeeze", "width_ratios", "height_ratios",
            "subplot_kw", "gridspec_kw")  # fmt: skip

    @staticmethod
    def subplots(nrows: int = 1, ncols: int = 1, **kw: Any) -> tuple[Figure, Any]:
        grid = {k: kw.pop(k) for k in _Figures.GRID if k in kw}
        fig = Figure(**kw)  # figsize, layout, dpi, ...
        return fig, fig.subplots(nrows, ncols, **grid)

    @staticmethod
    def close(fig: Figure) -> None:
        """Nothing to release: pyplot never held the figure."""


plt = _Figures()


def save(fig: Figure, path: Path, dpi: int = 150) -> None:
    """Write ``fig`` (PNG by the file's suffix)."""
    fig.savefig(path, dpi=dpi)


def plot_damage(
    path: Path,
    x: NDArray,
    damage: NDArray,
    spacing: float,
    title: str,
    outlines: list[NDArray] | None = None,
) -> None:
    """Write :func:`damage_figure` to ``path``."""
    save(damage_figure(x, damage, spacing, title, outlines), path)


def damage_figure(
    x: NDArray,
    damage: NDArray,
    spacing: float,
    title: str,
    outlines: list[NDArray] | None = None,
) -> Figure:
    """Scatter of local damage over the reference configuration (2-D; 3-D: max over z).

    Parameters
    ----------
    x : ndarray, shape (n, dim)
        Reference positions (m), dim 2 or 3.
    damage : ndarray, shape (n,)
        Point damage (0 to 1).
    spacing : float
        Grid spacing (m) (3-D: the columns whose largest damage is drawn).
    title : str
        Figure title.
    outlines : list of ndarray (k, 2), optional
        Closed polygons drawn on top (rigid bodies, in their final position).
    """
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
    return fig


def plot_histories(
    path: Path,
    time: list[float],
    series: dict[str, list[float]],
    title: str,
    xlabel: str = "time (us)",
    xscale: float = 1e6,
) -> None:
    """Write :func:`histories_figure` to ``path``."""
    save(histories_figure(time, series, title, xlabel, xscale), path)


def histories_figure(
    time: Any,
    series: dict[str, Any],
    title: str,
    xlabel: str = "time (us)",
    xscale: float = 1e6,
) -> Figure:
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
    return fig
