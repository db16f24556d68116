"""Build a simulation from a deck and run it with observers, checkpoints and output.

``Simulation.from_deck(deck)`` builds geometry -> bonds -> model -> solver;
``Simulation.run(out_dir)`` steps it, records histories, writes VTK frames, the
figure, ``final_state.npz`` and ``summary.json``.
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.analysis.crack import branching, crack_tip, tip_speed
from peridynamics.analysis.waves import dominant_period, pulse_comparison
from peridynamics.bonds import build_bonds, make_crack
from peridynamics.bonds.bonds import Bonds
from peridynamics.damage import NO_DAMAGE, CriticalStretch, SEDSoftening, WeibullField
from peridynamics.geometry import PointCloud, bar, box, cylinder, from_mesh, rectangle
from peridynamics.io import deck as dk
from peridynamics.io.checkpoint import read_checkpoint, write_checkpoint
from peridynamics.io.plots import plot_damage, plot_histories
from peridynamics.io.regions import to_region
from peridynamics.io.summary import write_summary
from peridynamics.io.vtk import write_pvd, write_vtu
from peridynamics.loading import conditions as bc
from peridynamics.loading import time_functions as tf
from peridynamics.materials import MATERIALS
from peridynamics.materials.viscosity import BondViscosity
from peridynamics.model import Model
from peridynamics.solvers.explicit import ExplicitSolver, SimulationUnstable
from peridynamics.solvers.fdm import FDMModel1D
from peridynamics.solvers.hybrid import HybridSolver, SwitchAtStretch
from peridynamics.solvers.state import State

COMP = {"x": 0, "y": 1, "z": 2}
#: Tests set PERIDYNAMICS_CRASH_AT_STEP to kill the process (exit 137, no clean-up) at a
#: given step, a deterministic stand-in for a power cut; unset in normal use.
_CRASH_AT_STEP = int(os.environ.get("PERIDYNAMICS_CRASH_AT_STEP", "-1"))


class SetupError(ValueError):
    """The deck is valid but the model it describes is not (empty node set, ...)."""

    def __init__(self, path: str, message: str) -> None:
        self.path = path
        super().__init__(f"{path}: {message}")


# ------------------------------------------------------------------------ building
def build_cloud(deck: dk.Deck) -> PointCloud:
    """Geometry section -> PointCloud with the deck's node sets (plus 'all')."""
    g = deck.geometry
    dx = deck.discretisation.spacing
    try:
        if isinstance(g, dk.BarGeometry):
            cloud = bar(
                g.length, dx, area=g.area, origin=g.origin, nodes_on_boundary=g.nodes_on_boundary
            )
        elif isinstance(g, dk.RectangleGeometry):
            cloud = rectangle(
                g.size,
                dx,
                thickness=g.thickness,
                origin=g.origin,
                plane=g.plane,
                holes=[to_region(h) for h in g.holes],
            )
        elif isinstance(g, dk.BoxGeometry):
            cloud = box(g.size, dx, origin=g.origin, holes=[to_region(h) for h in g.holes])
        elif isinstance(g, dk.CylinderGeometry):
            cloud = cylinder(
                g.radius, g.length, dx, origin=g.origin, holes=[to_region(h) for h in g.holes]
            )
        else:
            cloud = from_mesh(g.file, dim=g.dim, thickness=g.thickness, plane=g.plane, spacing=dx)
    except ValueError as exc:
        raise SetupError("geometry", str(exc)) from None
    sets: dict[str, NDArray[np.intp]] = {"all": np.arange(cloud.n_points)}
    visiting: set[str] = set()

    def resolve(name: str) -> NDArray[np.intp]:
        if name in sets:
            return sets[name]
        if name in visiting:
            raise SetupError(f"node_sets.{name}", "node sets refer to each other in a cycle")
        visiting.add(name)
        spec = deck.node_sets[name]
        _collect_refs(spec, resolve)
        try:
            idx = cloud.select(to_region(spec, sets, cloud.spacing))
        except ValueError as exc:
            raise SetupError(f"node_sets.{name}", str(exc)) from None
        if idx.size == 0:
            raise SetupError(
                f"node_sets.{name}",
                "selects no point; check the region against the geometry "
                f"(points span {cloud.bounds[0].tolist()} .. "
                f"{cloud.bounds[1].tolist()} m)",
            )
        sets[name] = idx
        return idx

    for name in deck.node_sets:
        resolve(name)
    return cloud.with_node_sets(**sets)


def _collect_refs(spec: dk.RegionSpec, resolve: Callable[[str], Any]) -> None:
    k = spec.kind()
    v = getattr(spec, k)
    if k == "set":
        resolve(v)
    elif k in ("all_of", "any_of"):
        for s in v:
            _collect_refs(s, resolve)
    elif k == "not_":
        _collect_refs(v, resolve)


def _solver_options(s: dk.Solver, kin: list, init: list, time_step: float | None) -> dict[str, Any]:
    """Keyword arguments of :class:`ExplicitSolver` from the deck's solver section."""
    return dict(
        time_step=time_step,
        integrator=s.integrator,
        constraints=kin,
        initial_velocities=init,
        safety_factor=s.safety_factor,
        allow_unstable=s.allow_unstable,
        blowup_factor=s.blowup_factor,
        max_stretch=s.max_stretch,
        check_every=s.check_every,
    )


def _hybrid_solver(
    deck: dk.Deck, cloud: PointCloud, second: Model, body: list, kin: list, init: list
) -> HybridSolver:
    """The first (cheap) model and the hybrid solver around it and the deck's model."""
    s, h = deck.solver, deck.solver.hybrid
    assert h is not None
    material = second.material
    first: Model
    if h.first == "fdm":
        first = FDMModel1D(cloud, material, body)
    else:
        bonds = build_bonds(
            cloud, h.first_horizon_factor * cloud.spacing, deck.discretisation.partial_volume
        )
        first = Model(cloud, bonds, material, NO_DAMAGE, body)
    limit = min(first.stable_time_step(), second.stable_time_step())
    dt = s.time_step if s.time_step is not None else s.safety_factor * limit
    common = _solver_options(s, kin, init, time_step=dt)
    return HybridSolver(
        ExplicitSolver(first, **common),
        ExplicitSolver(second, **common),
        SwitchAtStretch(h.switch_fraction),
    )


def time_function(spec: Any) -> tf.TimeFunction:
    """Deck time function -> object."""
    if isinstance(spec, dk.ConstantTF):
        return tf.Constant(spec.value)
    if isinstance(spec, dk.RampTF):
        return tf.Ramp(end=spec.end, start=spec.start)
    if isinstance(spec, dk.TableTF):
        return tf.Table(tuple(spec.times), tuple(spec.values))
    if isinstance(spec, dk.SinePulseTF):
        return tf.SinePulse(spec.duration)
    if isinstance(spec, dk.SquarePulseTF):
        return tf.SquarePulse(spec.duration)
    if isinstance(spec, dk.BlastTF):
        from peridynamics.loading.blast import BlastPulse

        return BlastPulse(spec.charge_kg, spec.standoff_m, spec.shape, spec.delay)
    return tf.TriangularPulse(spec.peak, spec.rise_time, spec.duration)


def _kinematic_components(spec: Any, dim: int) -> list[int]:
    """Components a displacement / velocity / fixed condition prescribes ([] otherwise)."""
    if isinstance(spec, dk.DisplacementBC | dk.VelocityBC):
        return [COMP[c] for c in spec.components]
    if isinstance(spec, dk.FixedBC):
        return [COMP[c] for c in spec.components] if spec.components else list(range(dim))
    return []


def build_conditions(deck: dk.Deck, cloud: PointCloud) -> tuple[list, list, list]:
    """(body forces, kinematic constraints, initial velocities)."""
    body: list[bc.BodyForce] = []
    kin: list[bc.PrescribedDisplacement | bc.PrescribedVelocity | bc.Fixed] = []
    init: list[bc.InitialVelocity] = []
    owner = np.full((cloud.n_points, cloud.dim), -1)  # which kinematic BC holds a dof
    for ibc, spec in enumerate(deck.boundary_conditions):
        nodes = cloud.node_set(spec.set)
        comps = np.asarray(_kinematic_components(spec, cloud.dim), dtype=np.intp)
        if comps.size:
            taken = owner[np.ix_(nodes, comps)]
            if np.any(taken >= 0):
                other = int(taken[taken >= 0][0])
                raise SetupError(
                    f"boundary_conditions.{ibc}",
                    f"prescribes the same node and component as boundary_conditions.{other} "
                    f"(sets {spec.set!r} and {deck.boundary_conditions[other].set!r} "
                    "overlap); a degree of freedom can have one kinematic condition only",
                )
            owner[np.ix_(nodes, comps)] = ibc
        if isinstance(spec, dk.DisplacementBC | dk.VelocityBC):
            kind = (
                bc.PrescribedDisplacement
                if isinstance(spec, dk.DisplacementBC)
                else bc.PrescribedVelocity
            )
            values = {str(k): v for k, v in spec.components.items()}
            kin.append(kind(nodes, values, time_function(spec.time_function)))
        elif isinstance(spec, dk.FixedBC):
            kin.append(bc.Fixed(nodes, tuple(spec.components) if spec.components else None))
        elif isinstance(spec, dk.InitialVelocityBC):
            init.append(bc.InitialVelocity(nodes, tuple(spec.value)))
        elif isinstance(spec, dk.BodyForceBC):
            body.append(bc.BodyForce(nodes, tuple(spec.value), time_function(spec.time_function)))
        elif isinstance(spec, dk.PressureBC) and spec.center is not None:
            body.append(
                bc.cavity_pressure_as_body_force(
                    nodes,
                    spec.scale,
                    cloud.x,
                    cloud.volume,
                    np.asarray(spec.center, dtype=float),
                    cloud.spacing,
                    thickness=cloud.cross_section,
                    layer_thickness=spec.layer_thickness,
                    function=time_function(spec.time_function),
                )
            )
        else:  # traction or pressure on a flat face
            normal: NDArray[np.float64] | None
            if isinstance(spec, dk.PressureBC):
                assert spec.normal is not None
                n = np.asarray(spec.normal, dtype=float)
                traction = -spec.scale * n / np.linalg.norm(n)
                normal = n
            else:
                traction = np.asarray(spec.value, dtype=float)
                normal = None if spec.normal is None else np.asarray(spec.normal, dtype=float)
            body.append(
                bc.traction_as_body_force(
                    nodes,
                    traction,
                    cloud.x,
                    cloud.spacing,
                    normal=normal,
                    layer_thickness=spec.layer_thickness,
                    function=time_function(spec.time_function),
                )
            )
    return body, kin, init


def build_bonds_for(deck: dk.Deck, cloud: PointCloud) -> Bonds:
    """Bonds with partial volumes and pre-cracks."""
    d = deck.discretisation
    try:
        cracks = [make_crack(c.points) for c in deck.precracks]
        return build_bonds(cloud, d.delta, d.partial_volume, cracks)
    except ValueError as exc:
        raise SetupError("discretisation", str(exc)) from None


def build_model(deck: dk.Deck, cloud: PointCloud, bonds: Bonds, body: list) -> Model:
    """Material + damage + loads -> Model."""
    m = deck.material
    material = MATERIALS[m.model](
        m.youngs_modulus, m.density, m.micromodulus_profile, m.micromodulus
    )
    dmg = deck.damage
    if dmg.model == "none":
        damage = NO_DAMAGE
    else:
        s0 = dmg.critical_stretch
        if s0 is None:
            assert dmg.fracture_energy is not None
            s0 = material.critical_stretch(
                dmg.fracture_energy, cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane
            )
        no_fail = (
            np.unique(np.concatenate([cloud.node_set(n) for n in dmg.no_fail]))
            if dmg.no_fail
            else None
        )
        w = dmg.weibull
        weibull = None if w is None else WeibullField(w.shape, w.seed, w.variable, w.u0_is)
        damage = CriticalStretch(s0, no_fail, weibull)
    sed = dmg.sed_softening
    softening = (
        None
        if sed is None
        else SEDSoftening(sed.levels, sed.k_c, sed.residual, sed.threshold_stretch, sed.energy)
    )
    contact = None
    if deck.contact is not None:
        from peridynamics.contact import ShortRangeContact

        c0 = material.micromodulus_constant(
            cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane
        )
        d_c = deck.contact.distance_factor * cloud.spacing
        contact = ShortRangeContact(
            cloud.x,
            cloud.volume,
            bonds,
            contact_distance=d_c,
            stiffness=ShortRangeContact.parks_stiffness(
                c0, d_c, bonds.horizon, deck.contact.stiffness_factor
            ),
        )
    return Model(
        cloud,
        bonds,
        material,
        damage,
        body,
        surface_correction=deck.discretisation.surface_correction,
        viscosity=None
        if m.viscosity is None
        else BondViscosity(m.viscosity.linear, m.viscosity.quadratic),
        softening=softening,
        contact=contact,
        damping=deck.solver.damping,
    )


# ------------------------------------------------------------------------ recording
@dataclass
class Recorder:
    """Histories recorded every ``every`` steps (time, probes, energies, damage, crack tip)."""

    deck: dk.Deck
    model: Model
    records: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not self.records:
            self.records = {
                "time_s": [],
                "kinetic_energy_J": [],
                "strain_energy_J": [],
                "max_damage": [],
                "probes": {p.name: [] for p in self.deck.output.probes},
                "crack_tip_m": [],
                "vtk_frames": [],
                "stress_Pa": [],
                "strain": [],
            }
        self._pre_damaged: NDArray[np.bool_] | None = None
        ct = self.deck.output.crack_tip
        self._tip = (
            None
            if ct is None
            else (
                np.asarray(ct.origin, dtype=float),
                None if ct.direction is None else np.asarray(ct.direction, dtype=float),
                ct.damage_threshold,
            )
        )

    def probe_value(self, probe: dk.Probe, s: State, damage: NDArray) -> float:
        """One number for a probe at the current state."""
        q = probe.quantity
        if q == "section_stress":
            assert probe.position is not None
            return self.model.section_stress(s.u, s.intact, probe.position)
        nodes = self.model.cloud.node_set(probe.set)
        if q in ("damage", "max_stretch"):
            vals = damage[nodes] if q == "damage" else s.max_stretch[nodes]
            return float(_reduce(vals, probe.reduce or "max"))
        if q == "reaction_force":
            f = -s.force[nodes] * self.model.cloud.volume[nodes, None]
            vec = f.sum(axis=0)
            return float(
                np.linalg.norm(vec)
                if probe.component == "magnitude"
                else vec[COMP[probe.component]]
            )
        arr = {"displacement": s.u, "velocity": s.v, "force_density": s.force}[q][nodes]
        vals = (
            np.linalg.norm(arr, axis=1)
            if probe.component == "magnitude"
            else arr[:, COMP[probe.component]]
        )
        return float(_reduce(vals, probe.reduce or "mean"))

    def check_fracture(self, s: State, broken_before: int) -> bool:
        """Record the fracture time and damaged zone the first time the largest damage
        reaches the threshold (only evaluated when bonds broke in this step)."""
        fr = self.deck.output.fracture
        if fr is None or "fracture_time_s" in self.records or s.bonds_broken == broken_before:
            return False
        damage = self.model.point_damage(s.intact)
        hit = damage >= fr.damage_threshold
        if not np.any(hit):
            return False
        x = self.model.cloud.x[hit]
        self.records["fracture_time_s"] = s.t
        self.records["fracture_step"] = s.step
        if self.model.dim == 1:
            self.records["fracture_position_m"] = [float(x[:, 0].min()), float(x[:, 0].max())]
        else:
            self.records["fracture_position_m"] = [x.min(axis=0).tolist(), x.max(axis=0).tolist()]
        self.records["fracture_damage"] = damage.tolist() if self.model.dim == 1 else None
        return True

    def record(self, s: State) -> None:
        """Append one record."""
        m, r = self.model, self.records
        damage = m.point_damage(s.intact)
        r["time_s"].append(s.t)
        r["kinetic_energy_J"].append(m.kinetic_energy(s.v))
        r["strain_energy_J"].append(m.strain_energy(s.u, s.intact))
        r["max_damage"].append(float(damage.max()))
        for p in self.deck.output.probes:
            r["probes"][p.name].append(self.probe_value(p, s, damage))
        ss = self.deck.output.stress_strain
        if ss is not None:
            nodes = m.cloud.node_set(ss.set)
            d = np.asarray(ss.direction, dtype=float)
            d /= np.linalg.norm(d)
            push = (s.force[nodes] * m.cloud.volume[nodes, None]).sum(axis=0)
            r.setdefault("stress_Pa", []).append(float(-np.sum(push * d) / ss.area))
            r.setdefault("strain", []).append(
                float(np.sum(s.u[nodes].mean(axis=0) * d) / ss.length)
            )
        if self._tip is not None:
            origin, direction, thr = self._tip
            if self._pre_damaged is None:  # points a pre-crack damages at t = 0
                self._pre_damaged = m.point_damage(m.bonds.bond_intact) >= thr
            r["crack_tip_m"].append(
                crack_tip(m.cloud.x, damage, origin, direction, thr, self._pre_damaged)
            )


def _reduce(vals: NDArray, how: str) -> float:
    if how == "mean":
        return float(np.mean(vals))
    if how == "sum":
        return float(np.sum(vals))
    return float(np.max(vals) if how == "max" else np.min(vals))


# ---------------------------------------------------------------------- simulation
@dataclass
class Simulation:
    """A deck turned into objects, ready to run."""

    deck: dk.Deck
    cloud: PointCloud
    model: Model
    solver: ExplicitSolver | HybridSolver
    setup_s: float = 0.0

    @classmethod
    def from_deck(cls, deck: dk.Deck) -> Simulation:
        """Build geometry -> bonds -> model -> solver. Raises SetupError / DeckError."""
        t0 = time.perf_counter()
        cloud = build_cloud(deck)
        bonds = build_bonds_for(deck, cloud)
        body, kin, init = build_conditions(deck, cloud)
        s = deck.solver
        if s.method == "fdm":
            material = MATERIALS[deck.material.model](
                deck.material.youngs_modulus,
                deck.material.density,
                deck.material.micromodulus_profile,
            )
            model: Model = FDMModel1D(cloud, material, body)
        else:
            model = build_model(deck, cloud, bonds, body)
        try:
            solver: ExplicitSolver | HybridSolver
            if s.hybrid is not None:
                solver = _hybrid_solver(deck, cloud, model, body, kin, init)
                return cls(deck, cloud, model, solver, setup_s=time.perf_counter() - t0)
            solver = ExplicitSolver(model, **_solver_options(s, kin, init, s.time_step))
        except ValueError as exc:
            raise SetupError("solver.time_step", str(exc)) from None
        return cls(deck, cloud, model, solver, setup_s=time.perf_counter() - t0)

    @property
    def n_steps(self) -> int:
        """Total number of steps of the run."""
        s = self.deck.solver
        return s.steps if s.steps is not None else self.solver.steps_for(s.end_time or 0.0)

    def fingerprint(self) -> str:
        """Hash of the validated deck, the package version and (for mesh geometries) the
        mesh file: a checkpoint only resumes the same problem with the same code."""
        from peridynamics import __version__

        text = json.dumps(self.deck.model_dump(mode="json", by_alias=True), sort_keys=True)
        h = hashlib.sha256(text.encode())
        h.update(__version__.encode())
        if isinstance(self.deck.geometry, dk.MeshGeometry):
            h.update(Path(self.deck.geometry.file).read_bytes())
        return h.hexdigest()

    def _frame(self, out: Path, s: State, records: dict, name: str | None = None) -> None:
        m = self.model
        fields = self.deck.output.fields
        data: dict[str, NDArray] = {}
        if "displacement" in fields:
            data["displacement"] = s.u
        if "velocity" in fields:
            data["velocity"] = s.v
        if "damage" in fields:
            data["damage"] = m.point_damage(s.intact)
        if "force_density" in fields:
            data["force_density"] = s.force
        fname = name or f"frame_{s.step:07d}.vtu"
        write_vtu(out / fname, self.cloud.x, data)
        if name is None:
            frames = [f for f in records["vtk_frames"] if f[1] != fname]
            frames.append((s.t, fname))
            records["vtk_frames"] = frames
            write_pvd(out / f"{self.deck.name}.pvd", [tuple(f) for f in frames])

    def run(
        self,
        out_dir: str | Path,
        quiet: bool = False,
        checkpoint_every: int = 0,
        resume: bool = False,
        progress: bool = True,
    ) -> dict:
        """Run to the end, writing output into ``out_dir``; returns the summary mapping.

        Raises SimulationUnstable after writing ``last_good.vtu`` and a summary whose
        ``status`` is ``"unstable"``.
        """
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        o = self.deck.output
        if resume:
            state, records, fp, model_state = read_checkpoint(out)
            if fp != self.fingerprint():
                raise SetupError(
                    "--resume",
                    f"the checkpoint in {str(out)!r} was written by "
                    "a different deck; resume with the same deck and overrides",
                )
            if state.step >= self.n_steps and (out / "summary.json").exists():
                raise SetupError(
                    "--resume",
                    f"the run in {str(out)!r} has already finished "
                    f"({state.step} steps); nothing to resume",
                )
            self.model.restore_history(model_state)
            self.solver._last_good = state.copy()
            recorder = Recorder(self.deck, self.model, records)
        else:
            state = self.solver.init()
            recorder = Recorder(self.deck, self.model)
            recorder.record(state)
            self._frame(out, state, recorder.records)
        n_total = self.n_steps
        t_start = time.perf_counter()
        steps_done_here = 0
        bar = _progress(quiet or not progress, n_total, state.step, self.deck.name)
        status, error = "completed", None
        try:
            with bar:
                while state.step < n_total:
                    broken_before = state.bonds_broken
                    self.solver.step(state)
                    steps_done_here += 1
                    if state.phase == 1 and "switch_time_s" not in recorder.records:
                        recorder.records["switch_time_s"] = state.t  # hybrid handed over
                    fractured = recorder.check_fracture(state, broken_before)
                    if fractured and o.fracture is not None and o.fracture.stop:
                        recorder.record(state)
                        break
                    if state.step % o.history_every == 0 or state.step == n_total:
                        recorder.record(state)
                    if o.vtk_every and state.step % o.vtk_every == 0:
                        self._frame(out, state, recorder.records)
                    if checkpoint_every and state.step % checkpoint_every == 0:
                        write_checkpoint(
                            out,
                            state,
                            recorder.records,
                            self.fingerprint(),
                            self.model.history_arrays(),
                        )
                    if state.step == _CRASH_AT_STEP:  # test hook: a hard crash mid-run
                        os._exit(137)
                    if state.step % 50 == 0 or state.step == n_total:
                        bar.update(state.step)
                if state.step % self.solver.check_every:
                    self.solver.check(state)  # the last steps are checked too
        except SimulationUnstable as exc:
            status, error = "unstable", str(exc)
            good = exc.last_good or state
            self._frame(out, good, recorder.records, name="last_good.vtu")
            wall = time.perf_counter() - t_start
            self._finish(out, state, recorder, wall, steps_done_here, status, error)
            raise
        wall = time.perf_counter() - t_start
        if not o.vtk_every or state.step % o.vtk_every:
            self._frame(out, state, recorder.records)
        return self._finish(out, state, recorder, wall, steps_done_here, status, error)

    def _finish(
        self,
        out: Path,
        s: State,
        recorder: Recorder,
        wall: float,
        steps: int,
        status: str,
        error: str | None,
    ) -> dict:
        m, r = self.model, recorder.records
        damage = m.point_damage(s.intact)
        np.savez(
            out / "final_state.npz",
            u=s.u,
            v=s.v,
            damage=damage,
            intact=s.intact,
            t=s.t,
            step=s.step,
        )
        results: dict[str, Any] = {
            "n_points": self.cloud.n_points,
            "n_bonds": m.bonds.n_bonds,
            "spacing_m": self.cloud.spacing,
            "horizon_m": m.bonds.horizon,
            "time_step_s": self.solver.dt,
            "stable_time_step_s": self.solver.stable_time_step,
            "steps": s.step,
            "final_time_s": s.t,
            "max_damage": float(damage.max()),
            "bonds_broken": s.bonds_broken,
            "max_displacement_m": float(np.abs(s.u).max()),
            "kinetic_energy_J": m.kinetic_energy(s.v),
            "strain_energy_J": m.strain_energy(s.u, s.intact),
            "history": {
                k: r[k] for k in ("time_s", "kinetic_energy_J", "strain_energy_J", "max_damage")
            },
            "probes": {},
        }
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
        blasts: list[dk.BlastTF] = []
        for spec in self.deck.boundary_conditions:
            fn = getattr(spec, "time_function", None)
            if isinstance(fn, dk.BlastTF):
                blasts.append(fn)
        if blasts:  # the pressure histories the run used (Kingery-Bulmash parameters)
            import warnings

            from peridynamics.loading.blast import BlastPulse

            with warnings.catch_warnings():  # already warned when the run was set up
                warnings.simplefilter("ignore")
                results["blast"] = [
                    {
                        **BlastPulse(b.charge_kg, b.standoff_m, b.shape).parameters.as_dict(),
                        "shape": b.shape,
                        "delay_s": b.delay,
                    }
                    for b in blasts
                ]
        results["damaged_area_fraction"] = float(np.mean(damage >= 0.3))
        ke = np.asarray(r["kinetic_energy_J"])
        se = np.asarray(r["strain_energy_J"])
        # quasi-static check: KE / SE once the body is loaded (SE >= 10 % of its maximum)
        loaded = se >= 0.1 * se.max() if se.size and se.max() > 0 else np.zeros(0, bool)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = ke[loaded] / se[loaded]
        results["max_kinetic_to_strain_energy"] = float(ratio.max()) if ratio.size else 0.0
        if self.deck.output.stress_strain is not None and r.get("stress_Pa"):
            stress = np.asarray(r["stress_Pa"])
            k = int(np.argmax(stress))
            results["peak_stress_Pa"] = float(stress[k])
            results["strain_at_peak"] = float(r["strain"][k])
            results["stress_strain"] = {"strain": r["strain"], "stress_Pa": r["stress_Pa"]}
        if isinstance(self.solver, HybridSolver):
            results["switch_time_s"] = r.get("switch_time_s")
            results["switched"] = s.phase == 1
        if self.deck.output.fracture is not None:
            results["fracture_time_s"] = r.get("fracture_time_s")
            results["fracture_position_m"] = r.get("fracture_position_m")
            results["fracture_step"] = r.get("fracture_step")
            if r.get("fracture_damage") is not None:
                results["damage_at_fracture"] = r["fracture_damage"]
        ct = self.deck.output.crack_tip
        if ct is not None:
            pos = np.asarray(r["crack_tip_m"])
            speed = tip_speed(t, pos)
            results["crack_tip_position_m"] = pos.tolist()
            results["crack_tip_speed_m_per_s"] = speed.tolist()
            results["max_crack_tip_speed_m_per_s"] = float(speed.max()) if len(speed) else 0.0
            if self.cloud.dim == 2:
                origin = np.asarray(ct.origin, dtype=float)
                direction = np.asarray(ct.direction or [1.0, 0.0], dtype=float)
                direction = direction / np.linalg.norm(direction)
                n_br, dist = branching(
                    self.cloud.x, damage, self.cloud.spacing, ct.damage_threshold, origin, direction
                )
                point = None if dist is None else (origin + dist * direction).tolist()
                results["crack_branches"] = n_br
                results["crack_branched"] = n_br >= 2
                results["branching_distance_m"] = dist
                results["branching_point_m"] = point
                results["branching_x_m"] = None if point is None else point[0]
        files = self._figure(out, s, damage, r)
        files += self._wave_outputs(out, s, results)
        n_b = m.bonds.n_bonds
        timing = {
            "wall_s": wall,
            "steps": steps,
            "setup_s": self.setup_s,
            "bond_updates_per_s": n_b * steps / wall if wall > 0 and steps else 0.0,
            "seconds_per_step": wall / steps if steps else 0.0,
        }
        extra: dict[str, Any] = {"status": status, "files": files}
        if error:
            extra["error"] = error
        return write_summary(
            out / "summary.json",
            self.deck.model_dump(mode="json", by_alias=True),
            results,
            timing,
            extra,
        )

    def _wave_outputs(self, out: Path, s: State, results: dict[str, Any]) -> list[str]:
        """results.period_s and the d'Alembert comparison (+ wave_profile.csv)."""
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
            x = self.cloud.x[:, 0]
            exact, errors = pulse_comparison(
                x, s.u[:, 0], s.t, wc.shape, wc.amplitude, wc.duration, speed,
                wc.source_position, wc.tail_margin,
            )  # fmt: skip
            results.update(errors)
            results["wave_front_m"] = wc.source_position + speed * s.t
            path = out / "wave_profile.csv"
            np.savetxt(
                path,
                np.column_stack([x, s.u[:, 0], exact]),
                delimiter=",",
                header="x_m,u_m,u_exact_m",
                comments="",
            )
            files.append(path.name)
        return files

    def _figure(self, out: Path, s: State, damage: NDArray, r: dict) -> list[str]:
        kind = self.deck.output.plot
        if kind == "none":
            return []
        if kind == "auto":
            kind = "probes" if self.cloud.dim == 1 else "damage"
        path = out / f"{self.deck.name}_{kind}.png"
        if kind == "damage":
            if self.cloud.dim == 1:
                series = {"damage": damage.tolist()}
                plot_histories(
                    path,
                    self.cloud.x[:, 0].tolist(),
                    series,
                    f"{self.deck.name}: damage at t = {s.t * 1e6:.2f} us",
                    xlabel="x (m)",
                    xscale=1.0,
                )
            else:
                plot_damage(
                    path,
                    self.cloud.x,
                    damage,
                    self.cloud.spacing,
                    f"{self.deck.name}: damage at t = {s.t * 1e6:.2f} us",
                )
        else:
            units = {
                "displacement": "m",
                "velocity": "m/s",
                "force_density": "N/m^3",
                "reaction_force": "N",
                "section_stress": "Pa",
                "max_stretch": "-",
                "damage": "-",
            }
            series = {
                f"{p.name} ({units[p.quantity]})": r["probes"][p.name]
                for p in self.deck.output.probes
            }
            series = series or {"kinetic energy (J)": r["kinetic_energy_J"]}
            plot_histories(path, r["time_s"], series, f"{self.deck.name}: probes")
        return [path.name]


class _NoBar:
    def __enter__(self) -> _NoBar:
        return self

    def __exit__(self, *a: object) -> None:
        return None

    def update(self, step: int) -> None:
        return None


class _RichBar:
    def __init__(self, total: int, start: int, label: str) -> None:
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.p = Progress(
            TextColumn(f"[bold]{label}"),
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("steps"),
            TimeElapsedColumn(),
            TimeRemainingColumn(),
        )
        self.task = self.p.add_task(label, total=total, completed=start)

    def __enter__(self) -> _RichBar:
        self.p.__enter__()
        return self

    def __exit__(self, *a: Any) -> None:
        self.p.__exit__(*a)

    def update(self, step: int) -> None:
        self.p.update(self.task, completed=step)


def _progress(off: bool, total: int, start: int, label: str) -> _NoBar | _RichBar:
    return _NoBar() if off else _RichBar(total, start, label)
