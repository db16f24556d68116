"""End-of-run wave results: the dominant period of a probe, the d'Alembert comparison
(``wave_profile.csv``) and the blast parameters a run used."""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.analysis.waves import dominant_period, pulse_comparison
from peridynamics.io.observers.base import Blast, Observer, RunContext, RunOptions
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


class WaveOutputs(Observer):
    """``results.period_s`` and the d'Alembert comparison (+ ``wave_profile.csv``)."""

    def __init__(self, run: RunOptions, model: Evaluator) -> None:
        self.run, self.model = run, model

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        o = self.run.output
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
            speed = self.run.wave_speed
            assert speed is not None
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

    def __init__(self, blasts: tuple[Blast, ...]) -> None:
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
