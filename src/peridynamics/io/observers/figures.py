"""The PNG figures of a run (``output.plot``: one kind or a list), drawn at its end by
the :class:`Figure` observer with :mod:`peridynamics.io.figures`."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from peridynamics.io.figures import deformed_figure, probe_units, slices_figure
from peridynamics.io.observers.base import Observer, RunContext, RunOptions
from peridynamics.io.plots import plot_damage, plot_histories, plt
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


class Figure(Observer):
    """The PNGs of the run, ``{name}_{kind}.png``, one per kind in ``output.plot``."""

    def __init__(self, run: RunOptions, model: Evaluator) -> None:
        self.run, self.model = run, model

    def kinds(self) -> list[str]:
        """The figure kinds asked for (``auto``: probes in 1-D, damage otherwise)."""
        plot = self.run.output.plot
        if plot == "none":
            return []
        if plot == "auto":
            return ["probes" if self.model.dim == 1 else "damage"]
        return [plot] if isinstance(plot, str) else list(dict.fromkeys(plot))

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        files = []
        for kind in self.kinds():
            path = ctx.out / f"{self.run.name}_{kind}.png"
            getattr(self, f"_{kind}")(path, ctx, s, results)
            files.append(path.name)
        return files

    def _title(self, s: State, what: str = "damage") -> str:
        name = self.run.name
        if self.run.static:
            return f"{name}: {what} after load step {s.step}"  # pseudo-time is no time
        return f"{name}: {what} at t = {s.t * 1e6:.2f} us"

    def _damage(self, path: Path, ctx: RunContext, s: State, results: dict[str, Any]) -> None:
        cloud, damage = self.model.cloud, ctx.damage(s)
        title = self._title(s)
        if cloud.dim == 1:
            plot_histories(path, cloud.x[:, 0].tolist(), {"damage": damage.tolist()}, title,
                           xlabel="x (m)", xscale=1.0)  # fmt: skip
        elif cloud.dim == 3:
            slices_figure(path, cloud.x, damage, cloud.spacing, title, self.run.output.slices,
                          irregular=cloud.irregular)  # fmt: skip
        else:
            rigid = getattr(self.model, "rigid", None)
            outlines = rigid.outlines(s, cloud.x) if rigid is not None else None
            plot_damage(path, cloud.x, damage, cloud.spacing, title, outlines)

    def _deformed(self, path: Path, ctx: RunContext, s: State, results: dict[str, Any]) -> None:
        deformed_figure(path, self.run.output, self.model, s, ctx.damage(s),
                        self._title(s, "damage on the deformed shape"))  # fmt: skip

    def _probes(self, path: Path, ctx: RunContext, s: State, results: dict[str, Any]) -> None:
        r, units = ctx.records, probe_units(self.run.output)
        series = {f"{n} ({units[n]})": v for n, v in r["probes"].items()}
        series = series or {"kinetic energy (J)": r["kinetic_energy_J"]}
        plot_histories(path, r["time_s"], series, f"{self.run.name}: probes")

    def _energies(self, path: Path, ctx: RunContext, s: State, results: dict[str, Any]) -> None:
        r = ctx.records
        series = {
            "kinetic energy (J)": r["kinetic_energy_J"],
            "strain energy (J)": r["strain_energy_J"],
            "largest damage (-)": r["max_damage"],
        }
        plot_histories(path, r["time_s"], series, f"{self.run.name}: energies")

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
        ax.set_title(f"{self.run.name}: stress-strain")
        fig.tight_layout()
        fig.savefig(path, dpi=150)
        plt.close(fig)
