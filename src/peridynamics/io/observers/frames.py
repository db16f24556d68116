"""Frames of a run: VTU files every N steps, at chosen times and at events, with the
PVD series ParaView opens, and optional PNGs of the damage on the deformed shape.

Events (``output.frames_on``):

* ``first_damage``: the first step in which a bond breaks during the run (pre-cracks
  do not count);
* ``fracture``: the first step at which the damage of a point reaches
  ``output.fracture.damage_threshold`` (0.3 when the deck has no ``fracture`` section),
  not counting points that pre-cracks and notches damage that much before the run;
* ``peak_load``: the state at the largest load (:func:`load_value`) over the history
  records; kept in memory while the load rises and written at the end of the run
  (and whenever a checkpoint is written, so a resumed run keeps it).

Event frames are ``event_<name>.vtu`` (not in the PVD series); ``results.events``
holds the time, step (and load) of each event that happened.

In a decomposed run (``mpiexec -n N``) a frame is ``<name>.pvtu`` with one piece per
rank, and every rank writes its own piece from its own state
(:mod:`peridynamics.io.observers.frame_pieces`), the kept ``peak_load`` frame included:
no field of a frame is gathered on rank 0. The PNGs of ``output.png_frames`` draw the
whole body: they still gather the displacement and the damage on rank 0.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.io.observers.base import Observer, RunContext, RunOptions
from peridynamics.io.observers.frame_pieces import (
    frame_fields,
    hold_frame,
    vtu_compression,
    write_frame,
)
from peridynamics.io.options import Output, load_source
from peridynamics.io.vtk import write_pvd, write_vtu
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


def load_value(output: Output, records: dict[str, Any]) -> float | None:
    """The load at the last history record: the probe ``output.load_probe``, else the
    stress of ``output.stress_strain``, else the first ``reaction_force`` probe."""
    src = load_source(output)
    if src is None:
        return None
    if src == "stress_strain":
        values = records.get("stress_Pa") or []
    else:
        values = records["probes"].get(src.split(":", 1)[1]) or []
    return float(values[-1]) if values else None


class VTKFrames(Observer):
    """VTU frames (``output.vtk_every`` steps, ``output.frames_at`` times,
    ``output.frames_on`` events, the first and the last state) and the PVD series."""

    def __init__(self, run: RunOptions, model: Evaluator) -> None:
        self.run, self.model = run, model
        o = run.output
        self.times = sorted(o.frames_at)
        self.events = set(o.frames_on)
        thr = o.fracture.damage_threshold if o.fracture is not None else 0.3
        self.fracture_threshold = thr
        self._peak: tuple[float, int, float, dict[str, NDArray]] | None = None
        self._peak_written = True

    # ------------------------------------------------------------------ writing
    def frame(self, ctx: RunContext, s: State, name: str | None = None) -> str:
        """Write one frame (``name``: a one-off file outside the series); returns its
        file name."""
        path = ctx.out / (name or f"frame_{s.step:07d}.vtu")
        if ctx.session is not None:  # a decomposed run: every rank writes its own piece
            fname = write_frame(ctx.session, path, self.run.output)
        else:
            fname = self._write(path, frame_fields(self.run.output, s, ctx.damage(s), self.model))
        if name is None:
            frames = [f for f in ctx.records["vtk_frames"] if f[1] != fname]
            frames.append((s.t, fname))
            ctx.records["vtk_frames"] = frames
            write_pvd(ctx.out / f"{self.run.name}.pvd", [tuple(f) for f in frames])
            if self.run.output.png_frames:
                self._png(ctx, s, fname)
        return fname

    def _write(self, path: Path, data: dict[str, NDArray]) -> str:
        """Write a frame of a serial run (the whole body's ``data``); its file name."""
        o = self.run.output
        write_vtu(path, self.model.cloud.x, data, precision=o.frame_precision,
                  compression=vtu_compression(o))  # fmt: skip
        return path.name

    def _png(self, ctx: RunContext, s: State, fname: str) -> None:
        from peridynamics.io.figures import deformed_figure

        folder = ctx.out / "png"
        folder.mkdir(exist_ok=True)
        if self.run.static:
            title = f"{self.run.name}: load step {s.step}"  # pseudo-time is no time
        else:
            title = f"{self.run.name}: step {s.step}, t = {s.t * 1e6:.3g} us"
        deformed_figure(folder / (Path(fname).stem + ".png"), self.run.output, self.model, s,
                        ctx.damage(s), title)  # fmt: skip

    def _event(self, ctx: RunContext, s: State, name: str, **extra: float) -> None:
        ev = ctx.records.setdefault("events", {})
        ev[name] = {"time_s": s.t, "step": s.step, **extra}
        if name in self.events:
            ev[name]["file"] = self.frame(ctx, s, name=f"event_{name}.vtu")

    # ------------------------------------------------------------------ hooks
    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        ctx.records.setdefault("events", {})
        ctx.records.setdefault("frames_at_done", 0)
        if not resumed:
            self.frame(ctx, s)
            self._due_times(ctx, s)
        else:  # the peak of the run before the interruption, if it was written
            pk = ctx.records["events"].get("peak_load")
            if pk is not None:
                self._peak = (pk["load"], pk["step"], pk["time_s"], {})

    def _due_times(self, ctx: RunContext, s: State) -> bool:
        """Advance past every ``frames_at`` time reached by ``s.t``; True if any."""
        k = ctx.records["frames_at_done"]
        hit = False
        while k < len(self.times) and s.t >= self.times[k] * (1 - 1e-12):
            k, hit = k + 1, True
        ctx.records["frames_at_done"] = k
        return hit

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        every = self.run.output.vtk_every
        due = bool(every and s.step % every == 0)
        if self._due_times(ctx, s):
            due = True
        if due:
            self.frame(ctx, s)
        ev = ctx.records["events"]
        if result.broken and "first_damage" not in ev:
            self._event(ctx, s, "first_damage")
        if result.broken and "fracture" not in ev:
            thr = self.fracture_threshold  # points a pre-crack already damaged don't count
            if np.any((ctx.damage(s) >= thr) & (ctx.initial_damage() < thr)):
                self._event(ctx, s, "fracture")
        if ctx.history_due(s) and load_source(self.run.output) is not None:
            self._track_peak(ctx, s)
        cp = int(ctx.records.get("checkpoint_every", 0) or 0)
        if cp and s.step % cp == 0:
            self._write_peak(ctx)

    def _track_peak(self, ctx: RunContext, s: State) -> None:
        load = load_value(self.run.output, ctx.records)
        if load is None or (self._peak is not None and abs(load) <= abs(self._peak[0])):
            return
        snap = {}
        if "peak_load" in self.events and ctx.session is not None:  # every rank its piece
            hold_frame(ctx.session, "peak_load", self.run.output)
        elif "peak_load" in self.events:
            data = frame_fields(self.run.output, s, ctx.damage(s), self.model)
            snap = {k: np.array(v, dtype=np.float32 if self._f32 else np.float64)
                    for k, v in data.items()}  # fmt: skip
        self._peak = (load, s.step, s.t, snap)
        self._peak_written = False
        ctx.records["events"]["peak_load"] = {"time_s": s.t, "step": s.step, "load": load}

    @property
    def _f32(self) -> bool:
        return self.run.output.frame_precision == "float32"

    def _write_peak(self, ctx: RunContext) -> None:
        if self._peak is None or self._peak_written or "peak_load" not in self.events:
            return
        path = ctx.out / "event_peak_load.vtu"
        if ctx.session is not None:  # every rank writes the piece it kept
            name = write_frame(ctx.session, path, self.run.output, held="peak_load")
        else:
            name = self._write(path, self._peak[3])
        ctx.records["events"]["peak_load"]["file"] = name
        self._peak_written = True

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        self._write_peak(ctx)
        results["events"] = ctx.records.get("events", {})
        every = self.run.output.vtk_every
        if ctx.status == "unstable":
            return []
        if not every or s.step % every:
            if not ctx.records["vtk_frames"] or Path(ctx.records["vtk_frames"][-1][1]).stem != (
                f"frame_{s.step:07d}"
            ):
                self.frame(ctx, s)
        return []
