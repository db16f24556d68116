"""Crack outputs that need no damage threshold: the crack length (2-D) or area (3-D) of
the bonds broken during the run (:mod:`peridynamics.analysis.crack_length`), as a
history, in total and per tracked crack."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from peridynamics.analysis.crack_attribution import attribute_to_polylines
from peridynamics.analysis.crack_length import CrackMeter
from peridynamics.analysis.energy_release import (
    broken_bond_energy,
    energy_release_rate,
    supports_broken_bond_energy,
)
from peridynamics.io.observers.base import Observer, RunContext, RunOptions
from peridynamics.io.observers.crack_bonds import (
    all_intact,
    build_meter,
    crack_measure,
    crack_weights,
)
from peridynamics.io.observers.crack_paths import CrackPaths
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


class CrackLength(Observer):
    """Crack length (2-D, m) or area (3-D, m^2) from the bonds broken during the run, at
    every history record and at the end; per tracked crack (``output.crack_paths``,
    ``output.crack_tip``) at the end. Keys: docs/output.md."""

    def __init__(self, run: RunOptions, model: Evaluator) -> None:
        self.run, self.model = run, model
        self.dim = model.dim
        # result keys: crack_length_m ... in 2-D, crack_area_m2 ... in 3-D
        what, unit = ("length", "m") if self.dim == 2 else ("area", "m2")
        self.keys = {
            "total": f"crack_{what}_{unit}",
            "history": f"crack_{what}_history_{unit}",
            "all": f"crack_{what}_all_bonds_{unit}",
            "rest": f"crack_{what}_unattributed_{unit}",
            "per_crack": f"broken_bond_{what}_{unit}",
        }
        # the energy of the broken bonds (J) and G (J/m^2): bond-based PMB, brittle
        self.energy = supports_broken_bond_energy(model)
        self._energy_last: tuple[int, float] | None = None  # (bonds_broken, energy)
        self.meter: CrackMeter | None = None
        self._last: tuple[int, float] | None = None  # (bonds_broken, value) of the last record

    def _meter(self) -> CrackMeter:
        if self.meter is None:
            self.meter = build_meter(self.model)
        return self.meter

    def value(self, s: State, session: Any = None) -> float:
        """Crack length (area) of ``s``: reused while no further bond broke (``session``:
        of a decomposed run, whose ranks measure their own bonds)."""
        if self._last is not None and self._last[0] == s.bonds_broken:
            return self._last[1]
        if session is not None:  # every rank its bonds
            v = crack_measure(session)
        else:
            v = self._meter().measure(all_intact(self.model, s))
        self._last = (s.bonds_broken, v)
        return v

    def broken_energy(self, s: State, session: Any = None) -> float:
        """Energy (J) the bonds broken during the run stored at their threshold
        (:func:`~peridynamics.analysis.energy_release.broken_bond_energy`), reused while
        no further bond broke."""
        if self._energy_last is not None and self._energy_last[0] == s.bonds_broken:
            return self._energy_last[1]  # no further bond broke since the last record
        if session is not None:  # every rank its owned bonds
            e = float(session.call("call", _energy_on_ranks))
        else:
            e = broken_bond_energy(self.model, s.intact)
        self._energy_last = (s.bonds_broken, e)
        return e

    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        ctx.records.setdefault(self.keys["history"], [])
        if self.energy:
            ctx.records.setdefault("broken_bond_energy_J", [])
        if not resumed:
            self.record(ctx, s)

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if ctx.history_due(s):
            self.record(ctx, s)

    def record(self, ctx: RunContext, s: State) -> None:
        """Append the crack length (area) at this state."""
        ctx.records[self.keys["history"]].append(self.value(s, ctx.session))
        if self.energy:
            ctx.records["broken_bond_energy_J"].append(self.broken_energy(s, ctx.session))

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        m, keys = self.model, self.keys
        if ctx.session is not None:  # a decomposed run
            mid, w = crack_weights(ctx.session)
            results[keys["all"]] = crack_measure(ctx.session, separating=False)
        else:
            meter = self._meter()
            intact = all_intact(m, s)
            idx, w = meter.weights(intact)
            results[keys["all"]] = meter.measure(intact, separating=False)
            mid = meter.midpoints(idx)
        results[keys["total"]] = float(w.sum())
        results[keys["history"]] = list(ctx.records.get(keys["history"], []))
        if self.energy:
            energy = list(ctx.records.get("broken_bond_energy_J", []))
            results["broken_bond_energy_J"] = self.broken_energy(s, ctx.session)
            results["broken_bond_energy_history_J"] = energy
            thickness = m.cloud.cross_section if self.dim == 2 else 1.0
            g = energy_release_rate(
                np.asarray(energy), np.asarray(results[keys["history"]]), thickness
            )
            results["energy_release_rate_J_m2"] = None if np.isnan(g) else g
        horizon = m.bonds.horizon
        o = self.run.output
        if o.crack_paths and isinstance(results.get("crack_paths"), dict):
            paths = CrackPaths(self.run, m).paths(ctx, s)
            lines = {n: list(p.branches) or [p.vertices] for n, p in paths.items()}
            share, rest = attribute_to_polylines(mid, w, lines, 2.0 * horizon)
            for name, v in share.items():
                if name in results["crack_paths"]:
                    results["crack_paths"][name][keys["per_crack"]] = v
            results[keys["rest"]] = rest
        ct = o.crack_tip
        if ct is not None and self.dim == 2:
            if ct.direction is None:
                ahead = np.ones(w.size, dtype=bool)
            else:
                d = np.asarray(ct.direction, dtype=float)
                d = d / np.linalg.norm(d)
                ahead = (mid - np.asarray(ct.origin, dtype=float)) @ d >= -horizon
            results["crack_tip_broken_bond_length_m"] = float(w[ahead].sum())
        return []


def _energy_on_ranks(session: Any) -> float:
    """Every rank: the broken-bond energy of its owned bonds, summed over the ranks."""
    m = session.model
    return float(session.comm.sum(broken_bond_energy(m, session.state.intact, m.owned_bonds)))


def crack_length_observers(run: RunOptions, model: Evaluator) -> list[Observer]:
    """The observers of this module a run gets: :class:`CrackLength` in 2-D and 3-D when
    bonds can break and ``output.crack_length`` is on."""
    if model.dim < 2 or not getattr(run.output, "crack_length", True):
        return []
    if not run.can_break:
        return []
    return [CrackLength(run, model)]
