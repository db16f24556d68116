"""The observers by name (:data:`OBSERVERS`) and the list a run gets
(:func:`observers_for`), in the order they run. Imported by the run loop; the observer
modules never import it."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from peridynamics.io.observers.base import Observer, RunOptions
from peridynamics.io.observers.bodies import RigidBodyHistory
from peridynamics.io.observers.bonds import BondList
from peridynamics.io.observers.crack_paths import CrackBranching, CrackPaths
from peridynamics.io.observers.cracks import CrackLength, crack_length_observers
from peridynamics.io.observers.events import Checkpoints, CrashAtStep, Fracture, HybridSwitch
from peridynamics.io.observers.figures import Figure
from peridynamics.io.observers.frames import VTKFrames
from peridynamics.io.observers.history import History
from peridynamics.io.observers.waves import BlastRecord, WaveOutputs

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator

#: every observer class by name (the order of a run is :func:`observers_for`'s)
OBSERVERS: dict[str, type[Observer]] = {
    "hybrid_switch": HybridSwitch,
    "fracture": Fracture,
    "history": History,
    "rigid_bodies": RigidBodyHistory,
    "frames": VTKFrames,
    "blast": BlastRecord,
    "crack_branching": CrackBranching,
    "crack_paths": CrackPaths,
    "crack_length": CrackLength,
    "figure": Figure,
    "waves": WaveOutputs,
    "bonds": BondList,
    "checkpoints": Checkpoints,
    "crash_at_step": CrashAtStep,
}


def observers_for(
    run: RunOptions, model: Evaluator, step_events: tuple[str, ...], checkpoint_every: int
) -> list[Observer]:
    """The observers a run asks for, in the order they run.

    Parameters
    ----------
    run : RunOptions
        The run's output options and plain values.
    model : the evaluator the observers read (the whole body's view under MPI).
    step_events : tuple of str
        The named events the solver's steps report (its declared ``step_events``:
        ``"switched"`` for a hybrid solver).
    checkpoint_every : int
        Steps between checkpoints (0: none).
    """
    o = run.output
    obs: list[Observer] = []
    if "switched" in step_events:
        obs.append(HybridSwitch())
    if o.fracture is not None:
        obs.append(Fracture(o.fracture, model))
    obs.append(History(run, model))
    if getattr(model, "rigid", None) is not None:
        obs.append(RigidBodyHistory(model))
    obs.append(VTKFrames(run, model))
    if run.blasts:
        obs.append(BlastRecord(run.blasts))
    if o.crack_tip is not None:
        obs.append(CrackBranching(o.crack_tip, model))
    if o.crack_paths:
        obs.append(CrackPaths(run, model))
    obs += crack_length_observers(run, model)  # after CrackPaths: adds to its results
    obs.append(Figure(run, model))
    obs.append(WaveOutputs(run, model))
    if o.bonds:
        obs.append(BondList(model))
    # last: a checkpoint holds the records of every observer for this step
    if checkpoint_every:
        obs.append(Checkpoints(checkpoint_every))
    crash = int(os.environ.get("PERIDYNAMICS_CRASH_AT_STEP", "-1"))
    if crash >= 0:
        obs.append(CrashAtStep(crash))
    return obs
