"""Observers: every output of a run is a small class with ``on_step`` and ``finalize``.

The runner builds the list from the deck (:func:`observers_for`) and calls, in list
order, ``on_start`` once, ``on_step`` after every solver step and ``finalize`` when the
run ends (completed, stopped or unstable). Histories live in one ``records`` mapping
shared by the observers, so a checkpoint saves and restores all of them at once.
Adding an output adds a class here, not a branch in the runner.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.analysis.crack import branching, crack_tip, tip_speed
from peridynamics.analysis.waves import dominant_period, pulse_comparison
from peridynamics.io import deck as dk
from peridynamics.io.checkpoint import write_checkpoint
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.model import Model

COMP = {"x": 0, "y": 1, "z": 2}


@dataclass
class RunContext:
    """What observers share: the deck, the model, the solver, the output folder, the
    records (histories, checkpointed) and the stop flag an observer may raise."""

    deck: dk.Deck
    model: Model
    solver: Any
    out: Path
    records: dict[str, Any]
    fingerprint: str = ""
    stop: bool = False
    status: str = "completed"
    damage_cache: dict[int, NDArray] = field(default_factory=dict)
    initial_damage_cache: NDArray | None = None
    #: a decomposed run's :class:`~peridynamics.parallel.session.Session` (else None)
    session: Any = None

    def write_checkpoint(self, s: State, meta: dict[str, Any] | None = None) -> Path:
        """A checkpoint of ``s`` with the records (under MPI every rank writes its own
        part, :mod:`peridynamics.parallel.checkpoints`); its path."""
        if self.session is None:
            return write_checkpoint(self.out, s, self.records, self.fingerprint, meta)
        from peridynamics.parallel.checkpoints import write_rank_checkpoints

        return self.session.call(
            "call", write_rank_checkpoints, str(self.out), self.records, self.fingerprint, meta
        )

    def history_due(self, s: State) -> bool:
        """True when histories are recorded after this step: every
        ``output.history_every`` steps, at the last step and when the run stops."""
        every = self.deck.output.history_every
        if every is None:  # static solvers: every load step / solve; dynamics: every 10
            every = 1 if self.deck.solver.type in ("adr", "static") else 10
        return self.stop or s.step % every == 0 or self.solver.done(s)

    def initial_damage(self) -> NDArray:
        """Point damage of the bonds as built (pre-cracks), computed once."""
        if self.initial_damage_cache is None:
            self.initial_damage_cache = self.model.point_damage(self.model.bonds.bond_intact)
        return self.initial_damage_cache

    def energies(self, s: State) -> tuple[float, float]:
        """(kinetic, strain) energy (J) of ``s``: the solver's own (the Warp backend
        reduces the strain energy density on the device) or the model's."""
        on_device = getattr(self.solver, "state_energies", None)
        got = on_device(s) if on_device is not None else None
        return got if got is not None else self.model.state_energies(s)

    def damage(self, s: State) -> NDArray:
        """Point damage of ``s`` (computed once per step for all observers)."""
        got = self.damage_cache.get(s.step)
        if got is None:
            self.damage_cache.clear()
            on_device = getattr(self.solver, "point_damage", None)  # the Warp backend's
            got = on_device(s) if on_device is not None else None
            if got is None:
                got = self.model.point_damage(s.intact, s.fields.get("interface_intact"))
            self.damage_cache[s.step] = got
        return got


class Observer:
    """Base class: every hook is optional."""

    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        """Once before the first step (``resumed``: continuing from a checkpoint)."""

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        """After every solver step."""

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        """At the end: add entries to ``results``; return the files written."""
        return []


def new_records(deck: dk.Deck) -> dict[str, Any]:
    """Empty histories of a run."""
    return {
        "time_s": [],
        "kinetic_energy_J": [],
        "strain_energy_J": [],
        "max_damage": [],
        "probes": {p.name: [] for p in deck.output.probes},
        "crack_tip_m": [],
        "vtk_frames": [],
        "stress_Pa": [],
        "strain": [],
    }


def _reduce(vals: NDArray, how: str, comm: Any) -> float:
    """Reduce a probe's values over the node set on every rank (``comm``)."""
    if how == "mean":
        return comm.sum(float(np.sum(vals))) / comm.sum(float(len(vals)))
    if how == "sum":
        return comm.sum(float(np.sum(vals)))
    if how == "max":
        return comm.max(float(np.max(vals)) if len(vals) else -np.inf)
    return comm.min(float(np.min(vals)) if len(vals) else np.inf)


# ----------------------------------------------------------------------- histories
class History(Observer):
    """Time, energies, largest damage, probes, stress-strain and crack tip every
    ``output.history_every`` steps (and at the last step or a stop)."""

    def __init__(self, deck: dk.Deck, model: Model) -> None:
        self.deck, self.model = deck, model
        ct = deck.output.crack_tip
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

    def probe_value(self, probe: dk.Probe, s: State, damage: NDArray) -> float:
        """One number for a probe at the current state."""
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
            vals = damage[nodes] if q == "damage" else m.largest_stretch(s)[nodes]
            return _reduce(vals, probe.reduce or "max", m.comm)
        if q == "reaction_force":
            if probe.body is not None:  # the contact force on a rigid body (N)
                vec = s["rigid_force"][self._rigid_index(probe.body), : m.dim]
                return float(
                    np.linalg.norm(vec)
                    if probe.component == "magnitude"
                    else vec[COMP[probe.component]]
                )
            f = -s.force[nodes] * m.cloud.volume[nodes, None]
            vec = m.comm.sum_array(f.sum(axis=0))
            return float(
                np.linalg.norm(vec)
                if probe.component == "magnitude"
                else vec[COMP[probe.component]]
            )
        if q in ("rotation", "moment"):
            if "theta" not in s:
                raise ValueError(f"probe {probe.name!r}: {q} needs material.model micropolar")
            field = s["theta"] if q == "rotation" else s["moment"]
            return _reduce(field[nodes, 0], probe.reduce or "mean", m.comm)
        arr = {"displacement": s.u, "velocity": s.v, "force_density": s.force}[q][nodes]
        vals = (
            np.linalg.norm(arr, axis=1)
            if probe.component == "magnitude"
            else arr[:, COMP[probe.component]]
        )
        return _reduce(vals, probe.reduce or "mean", m.comm)

    def record(self, ctx: RunContext, s: State) -> None:
        """Append one record."""
        m, r = self.model, ctx.records
        damage = ctx.damage(s)
        r["time_s"].append(s.t)
        kinetic, strain = ctx.energies(s)
        r["kinetic_energy_J"].append(kinetic)
        r["strain_energy_J"].append(strain)
        r["max_damage"].append(m.comm.max(float(damage.max())))
        # specimen damage factor (PD zero-energy modes (n.d.), eq. 13): bonds broken in
        # the run / all bonds (pre-cracked bonds count as neither failed nor intact)
        failed, total = m.bond_counts(s)
        r.setdefault("damage_factor", []).append(failed / max(total, 1.0))
        self._last: dict[str, float] = {}
        for p in self.deck.output.probes:
            value = self.probe_value(p, s, damage)
            self._last[p.name] = value
            r["probes"][p.name].append(value)
        ss = self.deck.output.stress_strain
        if ss is not None:
            d = np.asarray(ss.direction, dtype=float)
            d /= np.linalg.norm(d)
            if ss.body is not None:  # a rigid platen: its reaction and its displacement
                k = self._rigid_index(ss.body)
                push = s["rigid_force"][k, : m.dim]
                travel = s["rigid_position"][k, : m.dim]
            else:
                nodes = m.cloud.node_set(str(ss.set))
                push = (s.force[nodes] * m.cloud.volume[nodes, None]).sum(axis=0)
                travel = s.u[nodes].mean(axis=0)
            r.setdefault("stress_Pa", []).append(float(-np.sum(push * d) / ss.area))
            r.setdefault("strain", []).append(float(np.sum(travel * d) / ss.length))
        if self._tip is not None:
            origin, direction, thr = self._tip
            pre_damaged = ctx.initial_damage() >= thr  # points a pre-crack damages at t = 0
            r["crack_tip_m"].append(
                crack_tip(m.cloud.x, damage, origin, direction, thr, pre_damaged)
            )

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
        ss = self.deck.output.stress_strain
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
        if self.deck.output.history_csv:
            from peridynamics.io.history_csv import write_history_csv

            files.append(write_history_csv(ctx.out / "history.csv", self.deck, r))
        return files


# ------------------------------------------------------------------------ fracture
class Fracture(Observer):
    """Records when the largest damage first reaches ``output.fracture.damage_threshold``
    (and where); asks the run to stop there when ``stop`` is set."""

    def __init__(self, spec: dk.Fracture, model: Model) -> None:
        self.spec, self.model = spec, model

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        r = ctx.records
        if "fracture_time_s" in r or result.broken == 0:
            return
        damage = ctx.damage(s)
        hit = damage >= self.spec.damage_threshold
        if not np.any(hit):
            return
        x = self.model.cloud.x[hit]
        r["fracture_time_s"] = s.t
        r["fracture_step"] = s.step
        if self.model.dim == 1:
            r["fracture_position_m"] = [float(x[:, 0].min()), float(x[:, 0].max())]
        else:
            r["fracture_position_m"] = [x.min(axis=0).tolist(), x.max(axis=0).tolist()]
        r["fracture_damage"] = damage.tolist() if self.model.dim == 1 else None
        if self.spec.stop:
            ctx.stop = True

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        r = ctx.records
        results["fracture_time_s"] = r.get("fracture_time_s")
        results["fracture_position_m"] = r.get("fracture_position_m")
        results["fracture_step"] = r.get("fracture_step")
        if r.get("fracture_damage") is not None:
            results["damage_at_fracture"] = r["fracture_damage"]
        return []


class CrackBranching(Observer):
    """Crack-tip position and speed histories; in 2-D the branching analysis of the
    final damage field (the tip itself is recorded by :class:`History`)."""

    def __init__(self, spec: dk.CrackTip, model: Model) -> None:
        self.spec, self.model = spec, model

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        ct, cloud = self.spec, self.model.cloud
        pos = np.asarray(ctx.records["crack_tip_m"])
        speed = tip_speed(np.asarray(ctx.records["time_s"]), pos)
        results["crack_tip_position_m"] = pos.tolist()
        results["crack_tip_speed_m_per_s"] = speed.tolist()
        results["max_crack_tip_speed_m_per_s"] = float(speed.max()) if len(speed) else 0.0
        if cloud.dim == 2:
            origin = np.asarray(ct.origin, dtype=float)
            direction = np.asarray(ct.direction or [1.0, 0.0], dtype=float)
            direction = direction / np.linalg.norm(direction)
            n_br, dist = branching(
                cloud.x, ctx.damage(s), cloud.spacing, ct.damage_threshold, origin, direction
            )
            point = None if dist is None else (origin + dist * direction).tolist()
            results["crack_branches"] = n_br
            results["crack_branched"] = n_br >= 2
            results["branching_distance_m"] = dist
            results["branching_point_m"] = point
            results["branching_x_m"] = None if point is None else point[0]
        from peridynamics.io.observers_cracks import crack_tip_region, warn_threshold

        key = "output.crack_tip.damage_threshold"
        region = crack_tip_region(self.model, ct)
        warn_threshold(ctx, s, results, key, ct.damage_threshold, region)
        return []


class HybridSwitch(Observer):
    """Time at which a hybrid solver handed over to the peridynamic model."""

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if "switched" in result.events and "switch_time_s" not in ctx.records:
            ctx.records["switch_time_s"] = s.t

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        results["switch_time_s"] = ctx.records.get("switch_time_s")
        results["switched"] = s.phase == 1
        return []


# ---------------------------------------------------------------------- files
class Checkpoints(Observer):
    """An atomic checkpoint every ``every`` steps (State fields, records, fingerprint)."""

    def __init__(self, every: int) -> None:
        self.every = every

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if s.step % self.every == 0:
            ctx.write_checkpoint(s)


class CrashAtStep(Observer):
    """Test hook: kill the process (exit 137, no clean-up) after a given step, a
    deterministic stand-in for a power cut. Installed only when the environment
    variable PERIDYNAMICS_CRASH_AT_STEP is set."""

    def __init__(self, step: int) -> None:
        self.step = step

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if s.step == self.step:
            os._exit(137)


# --------------------------------------------------------------- end-of-run results
class WaveOutputs(Observer):
    """``results.period_s`` and the d'Alembert comparison (+ ``wave_profile.csv``)."""

    def __init__(self, deck: dk.Deck, model: Model) -> None:
        self.deck, self.model = deck, model

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        o = self.deck.output
        files: list[str] = []
        if o.period is not None:
            pr = results["probes"][o.period.probe]
            try:
                values = np.asarray(pr["values"])
                if o.period.of == "magnitude":
                    values = np.abs(values)
                elif o.period.of == "rate":
                    values = np.abs(np.gradient(values, np.asarray(pr["time_s"])))
                results["period_s"] = dominant_period(pr["time_s"], values, o.period.min_period)
            except ValueError as exc:
                results["period_s"] = None
                results["period_error"] = str(exc)
        wc = o.wave_comparison
        if wc is not None:
            mat = self.deck.material
            speed = float(np.sqrt(mat.youngs_modulus / mat.density))
            x = self.model.cloud.x[:, 0]
            exact, errors = pulse_comparison(
                x, s.u[:, 0], s.t, wc.shape, wc.amplitude, wc.duration, speed,
                wc.source_position, wc.tail_margin,
            )  # fmt: skip
            results.update(errors)
            half = 0.5 * abs(wc.amplitude)
            results["exact_front_m"] = wc.source_position + speed * s.t
            results["exact_half_amplitude_front_m"] = measured_front(x, exact, half)
            results["wave_front_m"] = measured_front(x, s.u[:, 0], half)
            path = ctx.out / "wave_profile.csv"
            np.savetxt(
                path,
                np.column_stack([x, s.u[:, 0], exact]),
                delimiter=",",
                header="x_m,u_m,u_exact_m",
                comments="",
            )
            files.append(path.name)
        return files


def measured_front(x: NDArray, u: NDArray, threshold: float) -> float | None:
    """Leading edge of a pulse travelling towards +x (m): the largest x at which |u|
    reaches ``threshold`` (half the amplitude in ``results``), linearly interpolated
    between the two grid points around the crossing; ``None`` when |u| nowhere reaches
    it. Applied to the simulated profile it gives ``wave_front_m``, to the exact one
    ``exact_half_amplitude_front_m`` (the value to compare it with)."""
    order = np.argsort(x)
    xs, a = x[order], np.abs(u[order])
    hit = np.flatnonzero(a >= threshold)
    if hit.size == 0 or threshold <= 0:
        return None
    k = int(hit[-1])
    if k + 1 >= len(xs):
        return float(xs[k])
    # |u| falls from >= threshold at k to < threshold at k + 1
    w = (a[k] - threshold) / (a[k] - a[k + 1])
    return float(xs[k] + w * (xs[k + 1] - xs[k]))


class BlastRecord(Observer):
    """The blast pressure parameters the run used (Kingery-Bulmash)."""

    def __init__(self, blasts: list[dk.BlastTF]) -> None:
        self.blasts = blasts

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        from peridynamics.loading.blast import BlastPulse

        with warnings.catch_warnings():  # already warned when the run was set up
            warnings.simplefilter("ignore")
            results["blast"] = [
                {
                    **BlastPulse(b.charge_kg, b.standoff_m, b.shape).parameters.as_dict(),
                    "shape": b.shape,
                    "delay_s": b.delay,
                }
                for b in self.blasts
            ]
        return []


def effective_modulus_ratio(model: Model) -> float:
    """E of the model as run over the nominal E: the median over points of the strain
    energy density under a uniform uniaxial strain (1e-6 along x) over the continuum
    value (PMB; 1.0 for other families). About 1 with the surface correction, 0.84-0.86
    in 2-D without it."""
    material = model.material
    energy = getattr(material, "uniaxial_energy_density", None)
    if energy is None:
        return 1.0
    cloud, eps = model.cloud, 1e-6
    u = np.zeros_like(cloud.x)
    u[:, 0] = eps * (cloud.x[:, 0] - cloud.x[:, 0].mean())
    w = model.strain_energy_density(u, model.bonds.bond_intact)
    w_inf = energy(eps, cloud.dim, model.bonds.horizon, cloud.cross_section, cloud.plane)
    return float(np.median(w) / w_inf)


class CrackPaths(Observer):
    """Cracks followed from seed points as polylines (``output.crack_paths``): the path
    length at every history record (for the tip speed) and, at the end, the path, its
    length, initial angle, angles along it and tip speeds, flagged above the Rayleigh
    speed of the model as run (:mod:`peridynamics.analysis.crack_path`)."""

    def __init__(self, deck: dk.Deck, model: Model) -> None:
        self.deck, self.model = deck, model
        self.specs = deck.output.crack_paths
        self._last: tuple[int, dict[str, Any]] | None = None  # (step, paths) of the last record
        self._broken = -1  # state.bonds_broken at the last record

    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        r = ctx.records
        r.setdefault("crack_path_time_s", [])
        r.setdefault("crack_path_length_m", {c.name: [] for c in self.specs})
        if not resumed:
            self.record(ctx, s)

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if ctx.history_due(s):
            self.record(ctx, s)

    def paths(self, ctx: RunContext, s: State) -> dict[str, Any]:
        """The current path of every crack, by name (cracks with the same threshold and
        region are extracted together, so a crack never runs on into another's)."""
        from peridynamics.analysis.crack_path import extract_crack_paths

        m = self.model
        damage = ctx.damage(s)
        groups: dict[tuple[float, str | None], list[dk.CrackPathSpec]] = {}
        for c in self.specs:
            groups.setdefault((c.damage_threshold, c.within), []).append(c)
        out: dict[str, Any] = {}
        for (thr, within), specs in groups.items():
            exclude = ctx.initial_damage() >= thr  # points notches and pre-cracks damage
            mask = None
            if within is not None:
                mask = np.zeros(m.n_points, dtype=bool)
                mask[m.cloud.node_set(within)] = True
            lengths = [c.initial_length for c in specs]
            found = extract_crack_paths(
                m.cloud.x, damage, [np.asarray(c.seed, dtype=float) for c in specs],
                m.cloud.spacing, thr, exclude=exclude, within=mask,
                reference_direction=[np.asarray(c.direction, dtype=float) for c in specs],
                initial_length=lengths[0] if len(set(lengths)) == 1 else None,
            )  # fmt: skip
            out.update({c.name: p for c, p in zip(specs, found, strict=True)})
        return out

    def record(self, ctx: RunContext, s: State) -> None:
        """Append the path lengths at this state (the paths of the last record are
        reused when no bond broke since: damage, and so the paths, are unchanged)."""
        r = ctx.records
        if self._last is not None and self._broken == s.bonds_broken:
            paths = self._last[1]
        else:
            paths = self.paths(ctx, s)
        self._broken = s.bonds_broken
        self._last = (s.step, paths)
        r["crack_path_time_s"].append(s.t)
        for name, p in paths.items():
            r["crack_path_length_m"][name].append(float(p.length))

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        from peridynamics.analysis.crack_speed import rayleigh_speed, tip_speed_from_paths
        from peridynamics.materials.bond_based import fixed_poisson_ratio

        m, r = self.model, ctx.records
        mat = m.material
        nu = getattr(mat, "poisson_ratio", None)
        if nu is None:
            nu = fixed_poisson_ratio(m.dim, m.cloud.plane if m.dim == 2 else None)
        ratio = effective_modulus_ratio(m)
        plane = m.cloud.plane if m.dim == 2 and m.cloud.plane else "3d"
        c_r = rayleigh_speed(ratio * mat.youngs_modulus, nu, mat.density, plane, "exact")
        t = np.asarray(r["crack_path_time_s"])
        out: dict[str, Any] = {}
        # the last record is usually of this very state: reuse its paths
        final = self._last[1] if self._last and self._last[0] == s.step else self.paths(ctx, s)
        for name, p in final.items():
            lengths = np.asarray(r["crack_path_length_m"][name])
            static = self.deck.solver.type in ("adr", "static")  # no physical time
            if len(t) >= 2 and not static:
                speed, flagged = tip_speed_from_paths(t, lengths, c_r)
            else:
                speed, flagged = np.zeros(len(t)), np.zeros(len(t), dtype=bool)
            out[name] = {
                "vertices_m": p.vertices.tolist(),
                "length_m": float(p.length),
                "initial_angle_deg": float(p.initial_angle_deg),
                "angles_deg": np.asarray(p.angles_deg).tolist(),
                "tip_m": np.asarray(p.tip).tolist(),
                "branches": len(p.branches),
                "time_s": t.tolist(),
                "length_history_m": lengths.tolist(),
                "tip_speed_m_per_s": speed.tolist(),
                "max_tip_speed_m_per_s": float(speed.max()) if len(speed) else 0.0,
                "above_rayleigh_speed": int(np.count_nonzero(flagged)),
            }
        results["crack_paths"] = out
        results["rayleigh_speed_m_per_s"] = c_r
        results["effective_modulus_ratio"] = ratio
        from peridynamics.io.observers_cracks import warn_threshold

        for k, c in enumerate(self.specs):  # over tracked cracks (a handful)
            region = None
            if c.within is not None:
                region = np.zeros(m.n_points, dtype=bool)
                region[m.cloud.node_set(c.within)] = True
            key = f"output.crack_paths[{k}].damage_threshold"
            warn_threshold(ctx, s, results, key, c.damage_threshold, region)
        return []


class BondList(Observer):
    """``bonds.npz``: the bond list of the run, each bond once (i < j), with its
    reference length and final status, and the reference points (see docs/output.md)."""

    def __init__(self, model: Model) -> None:
        self.model = model

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        if ctx.session is not None:  # every rank writes its owned bonds (global ids)
            return ctx.session.call("call", _write_rank_bonds, str(ctx.out))
        path = ctx.out / "bonds.npz"
        _save_bonds(path, half_bonds(self.model.bonds, s.intact), self.model)
        return [path.name]


def _save_bonds(path: Path, table: dict[str, NDArray], model: Any) -> None:
    """``bonds.npz`` of a bond table (:func:`half_bonds`)."""
    cloud = model.cloud
    np.savez(
        path,
        i=table["i"].astype(np.int32),
        j=table["j"].astype(np.int32),
        length_m=table["length_m"].astype(np.float64),
        intact=table["intact"].astype(np.uint8),
        initially_intact=table["ini"].astype(np.uint8),
        x_m=cloud.x,
        volume_m3=cloud.volume,
        horizon_m=np.float64(model.bonds.horizon),
    )


def read_bonds(folder: str | Path) -> dict[str, NDArray]:
    """The bond table of a run folder (``bonds.npz``; under MPI the per-rank files
    ``ranks/rankNNNN/bonds.npz`` joined), each bond once, sorted by (i, j): the same
    arrays whichever way the run was made."""
    folder = Path(folder)
    if (folder / "bonds.npz").exists():
        with np.load(folder / "bonds.npz") as f:
            return {k: f[k] for k in f.files}
    files = sorted(folder.glob("ranks/rank*/bonds.npz"))
    if not files:
        raise FileNotFoundError(f"no bonds.npz in {str(folder)!r} (output.bonds off?)")
    parts = []
    for p in files:
        with np.load(p) as f:
            parts.append({k: f[k] for k in f.files})
    keys = ("i", "j", "length_m", "intact", "initially_intact")
    out = {k: np.concatenate([p[k] for p in parts]) for k in keys}
    order = np.lexsort((out["j"], out["i"]))
    out = {k: v[order] for k, v in out.items()}
    for k in ("x_m", "volume_m3", "horizon_m"):
        out[k] = parts[0][k]
    return out


def half_bonds(
    b: Any, intact: NDArray, end: int | None = None, gid: NDArray | None = None
) -> dict[str, NDArray]:
    """Each bond of the families ``0:end`` once (i < j, by ``gid`` when given): end
    points, reference length, current and initial status."""
    from peridynamics.bonds.bonds import setup_chunk_bonds
    from peridynamics.bonds.search import bond_chunks

    end = int(b.offsets[-1]) if end is None else end
    parts: dict[str, list[NDArray]] = {k: [] for k in ("i", "j", "length_m", "intact", "ini")}
    for a, z in bond_chunks(b.offsets, setup_chunk_bonds(b.x.shape[1])):  # derived by range
        z = min(z, end)
        if a >= z:
            break
        bi, bj = b.bond_range("bond_i", a, z), b.bond_j[a:z]
        if gid is not None:
            bi, bj = gid[bi], gid[bj]
        half = bi < bj
        parts["i"].append(bi[half])
        parts["j"].append(bj[half])
        parts["length_m"].append(b.bond_range("bond_length", a, z)[half])
        parts["intact"].append(intact[a:z][half])
        parts["ini"].append(b.bond_intact[a:z][half])
    return {k: np.concatenate(v) if v else np.zeros(0) for k, v in parts.items()}


def _write_rank_bonds(session: Any, out: str) -> list[str]:
    """Every rank: ``ranks/rankNNNN/bonds.npz`` of its owned bonds, each once, in global
    ids (with the whole body's points: :func:`read_bonds` joins them); the names."""
    from peridynamics.parallel.session import rank_dir

    m, s, comm = session.model, session.state, session.comm
    end = m.owned_bonds
    folder = rank_dir(Path(out), comm.rank)
    folder.mkdir(parents=True, exist_ok=True)
    table = half_bonds(m.bonds, s.intact, end, m.cloud.global_ids)
    _save_bonds(folder / "bonds.npz", table, _WholeBody(session))
    names = comm.gather_objects(str((folder / "bonds.npz").relative_to(out)))
    return names if session.root else []


class _WholeBody:
    """The whole body's points and the horizon (what a bonds file stores beside the
    bonds)."""

    def __init__(self, session: Any) -> None:
        self.cloud = session.global_cloud
        self.bonds = session.model.bonds


def observers_for(deck: dk.Deck, model: Model, hybrid: bool, checkpoint_every: int) -> list:
    """The observers a deck asks for, in the order they run."""
    o = deck.output
    obs: list[Observer] = []
    if hybrid:
        obs.append(HybridSwitch())
    if o.fracture is not None:
        obs.append(Fracture(o.fracture, model))
    obs.append(History(deck, model))
    if getattr(model, "rigid", None) is not None:
        from peridynamics.io.observers_bodies import RigidBodyHistory

        obs.append(RigidBodyHistory(model))
    from peridynamics.io.figures import Figure
    from peridynamics.io.observers_frames import VTKFrames

    obs.append(VTKFrames(deck, model))
    blasts: list[dk.BlastTF] = []
    for spec in deck.boundary_conditions:
        fn = getattr(spec, "time_function", None)
        if isinstance(fn, dk.BlastTF):
            blasts.append(fn)
    if blasts:
        obs.append(BlastRecord(blasts))
    if o.crack_tip is not None:
        obs.append(CrackBranching(o.crack_tip, model))
    if o.crack_paths:
        obs.append(CrackPaths(deck, model))
    from peridynamics.io.observers_cracks import crack_length_observers

    obs += crack_length_observers(deck, model)  # after CrackPaths: adds to its results
    obs.append(Figure(deck, model))
    obs.append(WaveOutputs(deck, model))
    if o.bonds:
        obs.append(BondList(model))
    # last: a checkpoint holds the records of every observer for this step
    if checkpoint_every:
        obs.append(Checkpoints(checkpoint_every))
    crash = int(os.environ.get("PERIDYNAMICS_CRASH_AT_STEP", "-1"))
    if crash >= 0:
        obs.append(CrashAtStep(crash))
    return obs
