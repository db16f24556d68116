"""Outputs of rigid bodies: reaction (contact force) histories and friction work."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from peridynamics.io.observers.base import Observer, RunContext
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


class RigidBodyHistory(Observer):
    """Per rigid body, at every history record: the contact force on it (its reaction,
    N), the torque about its reference point (N m), its displacement (m) and velocity
    (m/s); and the energy dissipated by friction (J). In 2-D forces are per model
    thickness times the thickness, i.e. the force on the whole specimen."""

    def __init__(self, model: Evaluator) -> None:
        self.model = model
        self.rigid = model.rigid

    def _rec(self, ctx: RunContext) -> dict[str, Any]:
        r = ctx.records.setdefault("rigid_bodies", {"time_s": [], "friction_work_J": []})
        for b in self.rigid.bodies:
            r.setdefault(
                b.name, {"force_N": [], "torque_Nm": [], "displacement_m": [], "velocity_m_s": []}
            )
        return r

    def record(self, ctx: RunContext, s: State) -> None:
        r = self._rec(ctx)
        d = self.model.dim
        r["time_s"].append(s.t)
        r["friction_work_J"].append(float(s["friction_work"][0]))
        for k, b in enumerate(self.rigid.bodies):
            e = r[b.name]
            e["force_N"].append(s["rigid_force"][k, :d].tolist())
            e["torque_Nm"].append(
                s["rigid_torque"][k].tolist() if d == 3 else [float(s["rigid_torque"][k, 2])]
            )
            e["displacement_m"].append(s["rigid_position"][k, :d].tolist())
            e["velocity_m_s"].append(s["rigid_velocity"][k, :d].tolist())

    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        if not resumed:
            self.record(ctx, s)

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if ctx.history_due(s):
            self.record(ctx, s)

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        r = self._rec(ctx)
        out: dict[str, Any] = {"time_s": r["time_s"], "friction_work_J": r["friction_work_J"]}
        for b in self.rigid.bodies:
            e = r[b.name]
            f = np.asarray(e["force_N"], dtype=float).reshape(len(e["force_N"]), -1)
            mag = np.linalg.norm(f, axis=1) if f.size else np.zeros(0)
            k = int(np.argmax(mag)) if mag.size else 0
            out[b.name] = {
                **e,
                "motion": b.motion,
                "seating_shift_m": self.rigid.seating.get(b.name),
                "peak_force_N": float(mag[k]) if mag.size else 0.0,
                "peak_force_time_s": float(r["time_s"][k]) if mag.size else None,
            }
        results["rigid_bodies"] = out
        return []
