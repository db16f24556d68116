"""Drawing the PNG figures of a run (the :class:`~peridynamics.io.observers.figures.Figure`
observer, ``output.plot``: one kind or a list) and the frames' PNG series
(``output.png_frames``).

Kinds: ``damage`` (the damage map over the reference configuration; 1-D: damage
against x; 3-D: slices through the model, ``output.slices``, by default the three
mid-planes, instead of a projection through the thickness), ``deformed`` (the damage
on the deformed shape, displacements magnified by ``output.deformation_scale``),
``probes`` (probe histories), ``energies`` (kinetic and strain energy) and
``stress_strain``.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from peridynamics.io.options import Output, Slice
from peridynamics.io.plots import plot_damage, plt
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator

AXES = "xyz"
UNITS = {
    "displacement": "m",
    "velocity": "m/s",
    "force_density": "N/m^3",
    "rotation": "rad",
    "moment": "N m/m^3",
    "reaction_force": "N",
    "section_stress": "Pa",
    "max_stretch": "-",
    "damage": "-",
    "stress": "Pa",
    "strain": "-",
    "von_mises": "Pa",
    "pressure": "Pa",
    "principal_stress": "Pa",
    "temperature": "K",
}


def probe_units(output: Output) -> dict[str, str]:
    """The unit of every probe by name (derived probes take their first input's)."""
    units: dict[str, str] = {}
    for p in output.probes:
        if p.of:
            units[p.name] = units.get(p.of[0], "-")
        else:
            units[p.name] = UNITS[p.quantity]
    return units


def deformation_scale(output: Output, x: NDArray, u: NDArray) -> float:
    """``output.deformation_scale``, or the factor that draws the 99th percentile of
    the displacement magnitudes as 5 % of the model's largest extent (at least 1: the
    figure never shrinks displacements; 1 when nothing moved)."""
    if output.deformation_scale is not None:
        return float(output.deformation_scale)
    # the 99th percentile, so a few flying fragments do not set the scale; never < 1
    umax = float(np.percentile(np.linalg.norm(u, axis=1), 99)) if u.size else 0.0
    size = float(np.ptp(x, axis=0).max()) if len(x) else 0.0
    return max(1.0, 0.05 * size / umax) if umax > 0 and size > 0 else 1.0


def slice_masks(
    x: NDArray, spacing: float, slices: list[Slice] | None, irregular: bool = False
) -> list[tuple[str, float, NDArray]]:
    """(axis, position, mask) of each slice of a 3-D cloud ``x`` (n, 3): the layer of
    grid points nearest the plane, or (``irregular`` clouds) the points within half a
    spacing of it."""
    if not slices:
        centre = 0.5 * (x.min(axis=0) + x.max(axis=0))
        chosen = [(a, float(centre[k])) for k, a in enumerate(AXES)]
    else:
        lo = x.min(axis=0)
        chosen = [
            (sl.axis, sl.position if sl.position is not None else float(
                lo[AXES.index(sl.axis)] + 0.5 * np.ptp(x[:, AXES.index(sl.axis)])))
            for sl in slices
        ]  # fmt: skip
    out = []
    for axis, pos in chosen:
        c = x[:, AXES.index(axis)]
        if irregular:  # a slab one spacing thick
            mask = np.abs(c - pos) <= 0.5 * spacing
        else:  # the layer of grid points nearest the plane (the lower one on a tie)
            d = np.abs(c - pos)
            layer = c[d <= d.min() + 1e-9 * spacing].min()
            mask = np.abs(c - layer) <= 1e-6 * spacing
        out.append((axis, pos, mask))
    return out


def slices_figure(
    path: Path,
    x: NDArray,
    damage: NDArray,
    spacing: float,
    title: str,
    slices: list[Slice] | None,
    u: NDArray | None = None,
    scale: float = 0.0,
    irregular: bool = False,
) -> None:
    """One panel per slice of a 3-D model: the damage of the points of the slice, in
    the reference configuration or (``u``, ``scale``) on the deformed shape."""
    masks = slice_masks(x, spacing, slices, irregular)
    fig, axes = plt.subplots(
        1, len(masks), figsize=(4.6 * len(masks) + 1.2, 4.4), squeeze=False, layout="constrained"
    )
    pos = x if u is None else x + scale * u
    sc = None
    for ax, (axis, p, mask) in zip(axes[0], masks, strict=True):
        a, b = [k for k in range(3) if AXES[k] != axis]
        n = int(mask.sum())
        # squares one spacing wide: a panel is about 4.4 in (317 pt) across its extent
        extent = max(float(np.ptp(pos[mask, a])), float(np.ptp(pos[mask, b])), spacing) if n else 1
        size = max(0.25, (0.9 * 317.0 * spacing / extent) ** 2)
        sc = ax.scatter(pos[mask, a], pos[mask, b], c=damage[mask], s=size, cmap="jet",
                        vmin=0, vmax=1, marker="s", linewidths=0)  # fmt: skip
        ax.set_aspect("equal")
        ax.set_xlabel(f"{AXES[a]} (m)")
        ax.set_ylabel(f"{AXES[b]} (m)")
        ax.set_title(f"{axis} = {p:.4g} m ({n} points)", fontsize=9)
    fig.suptitle(title)
    if sc is not None:
        fig.colorbar(sc, ax=axes[0].tolist(), label="damage", shrink=0.8)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def deformed_figure(
    path: Path, output: Output, model: Evaluator, s: State, damage: NDArray, title: str
) -> None:
    """Damage on the deformed shape (2-D map; 3-D slices), displacements magnified."""
    cloud = model.cloud
    scale = deformation_scale(output, cloud.x, s.u)
    title = f"{title}, u x {scale:.3g}"
    if cloud.dim == 3:
        slices_figure(path, cloud.x, damage, cloud.spacing, title, output.slices,
                      s.u, scale, cloud.irregular)  # fmt: skip
        return
    rigid = getattr(model, "rigid", None)
    outlines = rigid.outlines(s, cloud.x) if rigid is not None else None
    plot_damage(path, cloud.x + scale * s.u, damage, cloud.spacing, title, outlines)
