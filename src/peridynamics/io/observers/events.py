"""Run events and run control: fracture, the hybrid switch, checkpoints and the crash
hook of the tests."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any

import numpy as np

from peridynamics.io.observers.base import Observer, RunContext
from peridynamics.io.options import Fracture as FractureOptions
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


class Fracture(Observer):
    """Records when the largest damage first reaches ``output.fracture.damage_threshold``
    (and where); asks the run to stop there when ``stop`` is set."""

    def __init__(self, spec: FractureOptions, model: Evaluator) -> None:
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


class HybridSwitch(Observer):
    """Time at which a hybrid solver handed over to the peridynamic model."""

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if "switched" in result.events and "switch_time_s" not in ctx.records:
            ctx.records["switch_time_s"] = s.t

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        results["switch_time_s"] = ctx.records.get("switch_time_s")
        results["switched"] = s.phase == 1
        return []


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
