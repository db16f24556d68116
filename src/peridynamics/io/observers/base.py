"""The observer interface: :class:`Observer`, what observers share (:class:`RunContext`)
and what they know of the run (:class:`RunOptions`, plain values; no deck).

The run loop builds the list of observers
(:func:`peridynamics.io.observers.registry.observers_for`) and calls, in list order,
``on_start`` once, ``on_step`` after every solver step and ``finalize`` when the run
ends (completed, stopped or unstable). Histories live in one ``records`` mapping shared
by the observers, so a checkpoint saves and restores all of them at once. Adding an
output adds a class in a module of this package and one registry line, not a branch in
the run loop. This module imports no concrete observer.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from peridynamics.io.checkpoint import write_checkpoint
from peridynamics.io.observers.point_fields import POINT_FIELDS, point_field
from peridynamics.io.options import Output
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator

COMP = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class Blast:
    """The parameters of a blast load (Kingery-Bulmash) a run applies."""

    charge_kg: float
    standoff_m: float
    shape: Literal["triangular", "friedlander"]
    delay: float


@dataclass(frozen=True)
class RunOptions:
    """What the outputs know of the run: its name, the output options and a few plain
    values of the problem (the build layer makes them from the deck).

    Parameters
    ----------
    name : str
        The run's name (file names and figure titles).
    output : Output
        The output options.
    static : bool
        The solver has no physical time (``adr``, ``static``): steps are load steps.
    can_break : bool
        Some bond of the model can break (a damage model or a bonded interface).
    wave_speed : float or None
        sqrt(E / rho) of the nominal material (m/s; for ``output.wave_comparison``).
    blasts : tuple of Blast
        The blast loads of the run.
    """

    name: str
    output: Output
    static: bool = False
    can_break: bool = True
    wave_speed: float | None = None
    blasts: tuple[Blast, ...] = ()


@dataclass
class RunContext:
    """What observers share: the run's options, the model, the solver, the output folder,
    the records (histories, checkpointed) and the stop flag an observer may raise."""

    run: RunOptions
    model: Evaluator
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
        part, :mod:`peridynamics.io.rank_checkpoints`); its path."""
        if self.session is None:
            return write_checkpoint(self.out, s, self.records, self.fingerprint, meta)
        from peridynamics.io.rank_checkpoints import write_rank_checkpoints

        return self.session.call(
            "call", write_rank_checkpoints, str(self.out), self.records, self.fingerprint, meta
        )

    def history_due(self, s: State) -> bool:
        """True when histories are recorded after this step: every
        ``output.history_every`` steps, at the last step and when the run stops."""
        every = self.run.output.history_every
        if every is None:  # static solvers: every load step / solve; dynamics: every 10
            every = 1 if self.run.static else 10
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

    def rows(self, s: State, what: str, nodes: NDArray[np.intp]) -> NDArray:
        """The rows ``nodes`` (sorted point ids) of a per-point quantity of ``s``: a
        State field (``u``, ``force``, ``theta`` ...), ``damage``, ``volume`` (m^3),
        ``max_stretch`` or a computed point field (``stress``, ``strain``, ``von_mises``,
        ... of :mod:`peridynamics.io.observers.point_fields`). Under MPI only those rows
        reach rank 0 (the session's ``rows`` request), not the whole field."""
        if self.session is not None:
            how: Any = partial(point_field, what) if what in POINT_FIELDS else what
            return self.session.call("rows", how, np.asarray(nodes, dtype=np.int64))
        if what == "damage":
            return self.damage(s)[nodes]
        if what == "volume":
            return self.model.cloud.volume[nodes]
        if what == "max_stretch":
            return self.model.largest_stretch(s)[nodes]
        if what in POINT_FIELDS:  # stress, strain and what derives from them
            return point_field(what, self.model, s)[nodes]
        return s[what][nodes]

    def max_damage(self, s: State) -> float:
        """The largest point damage of ``s`` (a reduction over the ranks under MPI)."""
        if self.session is not None:
            return float(self.session.call("max_damage"))
        return float(self.damage(s).max())


class Observer:
    """Base class: every hook is optional."""

    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        """Once before the first step (``resumed``: continuing from a checkpoint)."""

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        """After every solver step."""

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        """At the end: add entries to ``results``; return the files written."""
        return []


def new_records(output: Output) -> dict[str, Any]:
    """Empty histories of a run."""
    return {
        "time_s": [],
        "kinetic_energy_J": [],
        "strain_energy_J": [],
        "max_damage": [],
        "probes": {p.name: [] for p in output.probes},
        "crack_tip_m": [],
        "vtk_frames": [],
        "stress_Pa": [],
        "strain": [],
    }
