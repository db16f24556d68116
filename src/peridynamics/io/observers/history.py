"""Histories of a run: time, energies, largest damage, the damage factor, probes, the
stress-strain pair and the crack tip, every ``output.history_every`` steps; at the end
their summary in ``results`` and ``history.csv``."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.analysis.crack import crack_tip
from peridynamics.io.observers.base import COMP, Observer, RunContext, RunOptions
from peridynamics.io.options import (
    STRESS_QUANTITIES,
    TENSOR_COMPONENTS,
    TENSOR_QUANTITIES,
    Probe,
)
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


def _reduce(vals: NDArray, how: str, comm: Any) -> float:
    """Reduce a probe's values over the node set on every rank (``comm``)."""
    if how == "mean":
        return comm.sum(float(np.sum(vals))) / comm.sum(float(len(vals)))
    if how == "sum":
        return comm.sum(float(np.sum(vals)))
    if how == "max":
        return comm.max(float(np.max(vals)) if len(vals) else -np.inf)
    return comm.min(float(np.min(vals)) if len(vals) else np.inf)


def tip_distance(
    ctx: RunContext, s: State, origin: NDArray, direction: NDArray | None, threshold: float
) -> float:
    """:func:`~peridynamics.analysis.crack.crack_tip` of the whole body (points a
    pre-crack damaged at t = 0 left out); under MPI every rank's farthest owned point,
    the largest over the ranks (the serial value: a maximum)."""
    if ctx.session is not None:
        return float(ctx.session.call("call", _tip_on_ranks, origin, direction, threshold))
    pre_damaged = ctx.initial_damage() >= threshold
    return crack_tip(ctx.model.cloud.x, ctx.damage(s), origin, direction, threshold, pre_damaged)


def _tip_on_ranks(
    session: Any, origin: NDArray, direction: NDArray | None, threshold: float
) -> float:
    """Every rank: :func:`tip_distance` of its owned points, the largest over the ranks."""
    m, n = session.model, session.comm.n_owned
    initial = session.cache.get("initial_damage")
    if initial is None:
        initial = session.cache["initial_damage"] = m.point_damage(m.bonds.bond_intact)[:n]
    damage = session.local_damage()[:n]
    mine = crack_tip(m.cloud.x[:n], damage, origin, direction, threshold, initial >= threshold)
    return session.comm.max(mine)


# ----------------------------------------------------------------------- histories
class History(Observer):
    """Time, energies, largest damage, probes, stress-strain and crack tip every
    ``output.history_every`` steps (and at the last step or a stop)."""

    def __init__(self, run: RunOptions, model: Evaluator) -> None:
        self.run, self.model = run, model
        ct = run.output.crack_tip
        self._tip = (
            None
            if ct is None
            else (
                np.asarray(ct.origin, dtype=float),
                None if ct.direction is None else np.asarray(ct.direction, dtype=float),
                ct.damage_threshold,
            )
        )

    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        if not resumed:
            self.record(ctx, s)

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if ctx.history_due(s):
            self.record(ctx, s)

    def _rigid_index(self, name: str) -> int:
        rigid = getattr(self.model, "rigid", None)
        names = [] if rigid is None else [b.name for b in rigid.bodies]
        return names.index(name)

    def probe_value(self, ctx: RunContext, probe: Probe, s: State) -> float:
        """One number for a probe at the current state (from the rows of its node set:
        under MPI only those reach rank 0)."""
        m = self.model
        q = probe.quantity
        if q in ("difference", "sum"):  # of probes recorded before this one, this record
            assert probe.of is not None
            got = [self._last[name] for name in probe.of]
            return got[0] - got[1] if q == "difference" else float(sum(got))
        if q == "section_stress":
            assert probe.position is not None
            return m.section_stress(s.u, s.intact, probe.position)
        nodes = m.cloud.node_set(probe.set)
        if q in ("damage", "max_stretch"):
            vals = ctx.rows(s, q, nodes)
            return _reduce(vals, probe.reduce or "max", m.comm)
        if q == "reaction_force":
            if probe.body is not None:  # the contact force on a rigid body (N)
                vec = s["rigid_force"][self._rigid_index(probe.body), : m.dim]
                return float(
                    np.linalg.norm(vec)
                    if probe.component == "magnitude"
                    else vec[COMP[probe.component]]
                )
            f = -ctx.rows(s, "force", nodes) * ctx.rows(s, "volume", nodes)[:, None]
            vec = m.comm.sum_array(f.sum(axis=0))
            return float(
                np.linalg.norm(vec)
                if probe.component == "magnitude"
                else vec[COMP[probe.component]]
            )
        if q in ("rotation", "moment"):
            if "theta" not in s:
                raise ValueError(f"probe {probe.name!r}: {q} needs material.model micropolar")
            field = ctx.rows(s, "theta" if q == "rotation" else "moment", nodes)
            return _reduce(field[:, 0], probe.reduce or "mean", m.comm)
        if q == "temperature":  # K, the heat solvers' State field T
            return _reduce(ctx.rows(s, "T", nodes), probe.reduce or "mean", m.comm)
        if q in STRESS_QUANTITIES:  # Pa (strain: 1), from the point stress
            rows = ctx.rows(s, q, nodes)
            if q in TENSOR_QUANTITIES:
                comp = {"x": "xx", "y": "yy", "z": "zz"}.get(probe.component, probe.component)
                rows = rows[:, TENSOR_COMPONENTS[comp]]
            elif q == "principal_stress":
                rows = rows[:, 0]  # the largest
            return _reduce(rows, probe.reduce or "mean", m.comm)
        arr = ctx.rows(
            s, {"displacement": "u", "velocity": "v", "force_density": "force"}[q], nodes
        )
        vals = (
            np.linalg.norm(arr, axis=1)
            if probe.component == "magnitude"
            else arr[:, COMP[probe.component]]
        )
        return _reduce(vals, probe.reduce or "mean", m.comm)

    def record(self, ctx: RunContext, s: State) -> None:
        """Append one record."""
        m, r = self.model, ctx.records
        r["time_s"].append(s.t)
        if "fatigue_cycles" in s:  # a fatigue run: the cycle count N of this record
            r.setdefault("cycles", []).append(float(s["fatigue_cycles"][0]))
        kinetic, strain = ctx.energies(s)
        r["kinetic_energy_J"].append(kinetic)
        r["strain_energy_J"].append(strain)
        r["max_damage"].append(m.comm.max(ctx.max_damage(s)))
        # specimen damage factor (PD zero-energy modes (n.d.), eq. 13): bonds broken in
        # the run / all bonds (pre-cracked bonds count as neither failed nor intact)
        failed, total = m.bond_counts(s)
        r.setdefault("damage_factor", []).append(failed / max(total, 1.0))
        self._last: dict[str, float] = {}
        for p in self.run.output.probes:
            value = self.probe_value(ctx, p, s)
            self._last[p.name] = value
            r["probes"][p.name].append(value)
        ss = self.run.output.stress_strain
        if ss is not None:
            d = np.asarray(ss.direction, dtype=float)
            d /= np.linalg.norm(d)
            if ss.body is not None:  # a rigid platen: its reaction and its displacement
                k = self._rigid_index(ss.body)
                push = s["rigid_force"][k, : m.dim]
                travel = s["rigid_position"][k, : m.dim]
            else:
                nodes = m.cloud.node_set(str(ss.set))
                volume = ctx.rows(s, "volume", nodes)[:, None]
                push = (ctx.rows(s, "force", nodes) * volume).sum(axis=0)
                travel = ctx.rows(s, "u", nodes).mean(axis=0)
            r.setdefault("stress_Pa", []).append(float(-np.sum(push * d) / ss.area))
            r.setdefault("strain", []).append(float(np.sum(travel * d) / ss.length))
        if self._tip is not None:
            origin, direction, thr = self._tip
            r["crack_tip_m"].append(tip_distance(ctx, s, origin, direction, thr))

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        r = ctx.records
        results["history"] = {
            k: r[k]
            for k in (
                "time_s",
                "kinetic_energy_J",
                "strain_energy_J",
                "max_damage",
                "damage_factor",
            )
            if k in r
        }
        results["probes"] = {}
        t = np.asarray(r["time_s"])
        for name, values in r["probes"].items():
            v = np.asarray(values)
            k = int(np.argmax(np.abs(v))) if len(v) else 0
            peak = float(v[k]) if len(v) else 0.0
            arrived = np.flatnonzero(np.abs(v) >= 0.1 * abs(peak)) if peak else np.array([])
            results["probes"][name] = {
                "time_s": r["time_s"],
                "values": values,
                "peak": peak,
                "peak_time_s": float(t[k]) if len(v) else None,
                "arrival_time_s": float(t[arrived[0]]) if arrived.size else None,
            }
        ke = np.asarray(r["kinetic_energy_J"])
        se = np.asarray(r["strain_energy_J"])
        # quasi-static check: KE / SE once the body is loaded (SE >= 10 % of its maximum)
        loaded = se >= 0.1 * se.max() if se.size and se.max() > 0 else np.zeros(0, bool)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = ke[loaded] / se[loaded]
        results["max_kinetic_to_strain_energy"] = float(ratio.max()) if ratio.size else 0.0
        ss = self.run.output.stress_strain
        if ss is not None and r.get("stress_Pa"):
            stress = np.asarray(r["stress_Pa"])
            strain = np.asarray(r["strain"])
            k = int(np.argmax(stress))
            offset = 0.0
            if ss.zero_at == "first_contact" and stress[k] > 0:
                # the last record before the stress first exceeds contact_fraction of
                # its peak: the strain there is the travel before contact
                first = int(np.flatnonzero(stress > ss.contact_fraction * stress[k])[0])
                offset = float(strain[max(first - 1, 0)])
            results["peak_stress_Pa"] = float(stress[k])
            results["strain_at_peak"] = float(strain[k] - offset)
            results["stress_strain"] = {
                "strain": (strain - offset).tolist(),
                "stress_Pa": r["stress_Pa"],
                "strain_offset": offset,
            }
        files = []
        if self.run.output.history_csv:
            from peridynamics.io.history_csv import write_history_csv

            files.append(write_history_csv(ctx.out / "history.csv", self.run.output, r))
        return files
