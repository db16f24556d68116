"""The PNG figures of a run (``output.plot``: one kind or a list) and the frames'
PNG series (``output.png_frames``).

Kinds: ``damage`` (the damage map over the reference configuration; 1-D: damage
against x; 3-D: slices through the model, ``output.slices``, by default the three
mid-planes, instead of a projection through the thickness), ``deformed`` (the damage
on the deformed shape, displacements magnified by ``output.deformation_scale``),
``probes`` (probe histories), ``energies`` (kinetic and strain energy) and
``stress_strain``.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.io import deck as dk
from peridynamics.io.deck_output import Slice
from peridynamics.io.observers import Observer, RunContext
from peridynamics.io.plots import plot_damage, plot_histories, plt
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Model

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
}


def probe_units(deck: dk.Deck) -> dict[str, str]:
    """The unit of every probe by name (derived probes take their first input's)."""
    units: dict[str, str] = {}
    for p in deck.output.probes:
        if p.of:
            units[p.name] = units.get(p.of[0], "-")
        else:
            units[p.name] = UNITS[p.quantity]
    return units


def deformation_scale(deck: dk.Deck, x: NDArray, u: NDArray) -> float:
    """``output.deformation_scale``, or the factor that draws the 99th percentile of
    the displacement magnitudes as 5 % of the model's largest extent (at least 1: the
    figure never shrinks displacements; 1 when nothing moved)."""
    if deck.output.deformation_scale is not None:
        return float(deck.output.deformation_scale)
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
    path: Path, deck: dk.Deck, model: Model, s: State, damage: NDArray, title: str
) -> None:
    """Damage on the deformed shape (2-D map; 3-D slices), displacements magnified."""
    cloud = model.cloud
    scale = deformation_scale(deck, cloud.x, s.u)
    title = f"{title}, u x {scale:.3g}"
    if cloud.dim == 3:
        slices_figure(path, cloud.x, damage, cloud.spacing, title, deck.output.slices,
                      s.u, scale, cloud.irregular)  # fmt: skip
        return
    rigid = getattr(model, "rigid", None)
    outlines = rigid.outlines(s, cloud.x) if rigid is not None else None
    plot_damage(path, cloud.x + scale * s.u, damage, cloud.spacing, title, outlines)


class Figure(Observer):
    """The PNGs of the run, ``{name}_{kind}.png``, one per kind in ``output.plot``."""

    def __init__(self, deck: dk.Deck, model: Model) -> None:
        self.deck, self.model = deck, model

    def kinds(self) -> list[str]:
        """The figure kinds asked for (``auto``: probes in 1-D, damage otherwise)."""
        plot = self.deck.output.plot
        if plot == "none":
            return []
        if plot == "auto":
            return ["probes" if self.model.dim == 1 else "damage"]
        return [plot] if isinstance(plot, str) else list(dict.fromkeys(plot))

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        files = []
        for kind in self.kinds():
            path = ctx.out / f"{self.deck.name}_{kind}.png"
            getattr(self, f"_{kind}")(path, ctx, s, results)
            files.append(path.name)
        return files

    def _title(self, s: State, what: str = "damage") -> str:
        name = self.deck.name
        if getattr(self.deck.solver, "type", "explicit") in ("adr", "static"):
            return f"{name}: {what} after load step {s.step}"  # pseudo-time is no time
        return f"{name}: {what} at t = {s.t * 1e6:.2f} us"

    def _damage(self, path: Path, ctx: RunContext, s: State, results: dict[str, Any]) -> None:
        cloud, damage = self.model.cloud, ctx.damage(s)
        title = self._title(s)
        if cloud.dim == 1:
            plot_histories(path, cloud.x[:, 0].tolist(), {"damage": damage.tolist()}, title,
                           xlabel="x (m)", xscale=1.0)  # fmt: skip
        elif cloud.dim == 3:
            slices_figure(path, cloud.x, damage, cloud.spacing, title, self.deck.output.slices,
                          irregular=cloud.irregular)  # fmt: skip
        else:
            rigid = getattr(self.model, "rigid", None)
            outlines = rigid.outlines(s, cloud.x) if rigid is not None else None
            plot_damage(path, cloud.x, damage, cloud.spacing, title, outlines)

    def _deformed(self, path: Path, ctx: RunContext, s: State, results: dict[str, Any]) -> None:
        deformed_figure(path, self.deck, self.model, s, ctx.damage(s),
                        self._title(s, "damage on the deformed shape"))  # fmt: skip

    def _probes(self, path: Path, ctx: RunContext, s: State, results: dict[str, Any]) -> None:
        r, units = ctx.records, probe_units(self.deck)
        series = {f"{n} ({units[n]})": v for n, v in r["probes"].items()}
        series = series or {"kinetic energy (J)": r["kinetic_energy_J"]}
        plot_histories(path, r["time_s"], series, f"{self.deck.name}: probes")

    def _energies(self, path: Path, ctx: RunContext, s: State, results: dict[str, Any]) -> None:
        r = ctx.records
        series = {
            "kinetic energy (J)": r["kinetic_energy_J"],
            "strain energy (J)": r["strain_energy_J"],
            "largest damage (-)": r["max_damage"],
        }
        plot_histories(path, r["time_s"], series, f"{self.deck.name}: energies")

    def _stress_strain(
        self, path: Path, ctx: RunContext, s: State, results: dict[str, Any]
    ) -> None:
        ss = results.get("stress_strain") or {"strain": [], "stress_Pa": []}
        fig, ax = plt.subplots(figsize=(6, 4.5))
        ax.plot(np.asarray(ss["strain"]) * 1e3, np.asarray(ss["stress_Pa"]) / 1e6, lw=1.4)
        if results.get("peak_stress_Pa") is not None:
            ax.plot(results["strain_at_peak"] * 1e3, results["peak_stress_Pa"] / 1e6, "o")
        ax.set_xlabel("strain (1e-3)")
        ax.set_ylabel("stress (MPa)")
        ax.grid(alpha=0.3)
        ax.set_title(f"{self.deck.name}: stress-strain")
        fig.tight_layout()
        fig.savefig(path, dpi=150)
        plt.close(fig)
