"""The run loop of a simulation: observers, checkpoints, Ctrl-C, progress, the summary.

:class:`Simulation` is a deck built into objects
(:class:`peridynamics.build.simulation.SimulationSetup`) that runs: :class:`RunLoop`
steps the built model, ``solver.step`` until ``solver.done``, every observer after
each step, checkpoints, ``summary.json``. Under MPI (``mpiexec -n N``) the same loop
runs on every rank; rank 0 runs the observers on views of the whole body while the
other ranks answer its requests (:mod:`peridynamics.parallel.session`).
"""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics import deck as dk
from peridynamics.app.run_folder import (
    final_stats,
    gather_rss,
    hold_folder,
    write_final_pieces,
)
from peridynamics.app.run_progress import StopRequest, progress_bar, signal_name
from peridynamics.app.run_resume import resume_point
from peridynamics.build.outputs import run_options
from peridynamics.build.simulation import SimulationSetup
from peridynamics.deck.changed_defaults import notices
from peridynamics.io.atomic import save_npz
from peridynamics.io.checkpoint import CHECKPOINT_NAME
from peridynamics.io.observers.base import Observer, RunContext, RunOptions, new_records
from peridynamics.io.observers.events import CrashAtStep
from peridynamics.io.observers.frames import VTKFrames
from peridynamics.io.observers.registry import observers_for
from peridynamics.io.summary import write_summary
from peridynamics.solvers.base import Solver
from peridynamics.solvers.explicit import SimulationUnstable
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator
    from peridynamics.geometry import PointCloud


class RunLoop:
    """Stepping, observing and finishing a built simulation (a base of
    :class:`Simulation`, whose :class:`SimulationSetup` supplies the attributes below)."""

    deck: dk.Deck
    cloud: PointCloud
    model: Evaluator
    solver: Solver
    setup_s: float
    session: Any
    global_cloud: Any
    #: the signal that stopped the run (SIGINT unless another was received)
    _stop_signal: int = int(signal.SIGINT)
    #: observers added to the deck's (the Python API's callbacks; they run first)
    extra_observers: tuple[Observer, ...] = ()
    #: where a new run starts (``None``: ``solver.init()``; the Python API's ``step``)
    start_state: State | None = None
    #: the state of the run in progress, then its last state (``None`` before a run)
    state: State | None = None

    def fingerprint(self) -> str:
        """Hash of what a checkpoint must match (:meth:`SimulationSetup.fingerprint`)."""
        raise NotImplementedError

    def run(
        self,
        out_dir: str | Path,
        quiet: bool = False,
        checkpoint_every: int | None = None,
        resume: bool = False,
        progress: bool = True,
    ) -> dict:
        """Run to the end, writing output into ``out_dir``; returns the summary mapping.

        The run holds ``out_dir`` while it writes (``.peridynamics.lock``,
        :class:`~peridynamics.io.run_lock.RunLock`): a second run on the same folder is
        refused (SetupError naming the process that holds it); a lock left by a killed
        run is taken over with a warning.

        The loop is generic: ``solver.step`` until ``solver.done``, every observer's
        ``on_step`` after each step. Raises SimulationUnstable after writing
        ``last_good.vtu`` and a summary whose ``status`` is ``"unstable"``.

        ``checkpoint_every``: steps between checkpoints (0: none; ``None``: 0 for a new
        run, the interval of the interrupted run when resuming). A checkpointed run also
        writes a checkpoint of its final state that records that the run finished, so a
        ``resume`` of a finished run is refused (SetupError).

        Ctrl-C (SIGINT, in the main thread), SIGTERM, SIGHUP or SIGUSR1 stops the run
        after the step in progress: the state after that step is complete (the solver
        and every observer have run), so a checkpoint of it is written when
        checkpointing is on, then the outputs and a summary with status
        ``"interrupted"`` and ``stop_signal``; :class:`RunInterrupted` is raised. A
        second signal aborts at once (KeyboardInterrupt, nothing more written).
        """
        out = Path(out_dir)
        lock = hold_folder(out, "--resume" if resume else "--out", self.session)
        try:
            return self._run(out, quiet, checkpoint_every, resume, progress)
        finally:
            if lock is not None:
                lock.release()

    def _run(
        self,
        out: Path,
        quiet: bool,
        checkpoint_every: int | None,
        resume: bool,
        progress: bool,
    ) -> dict:
        """:meth:`run` in a folder this run holds."""
        dist = self.session  # a decomposed run: rank 0 observes, the others serve
        root = dist is None or dist.root
        if root:
            (out / (CHECKPOINT_NAME + ".tmp")).unlink(missing_ok=True)  # left by a crash
        solver = self.solver
        if resume:
            state, records, finished, checkpoint_every = resume_point(
                solver, dist, self.fingerprint, out, checkpoint_every, not quiet and root
            )
        else:
            finished = False
            state = self.start_state if self.start_state is not None else solver.init()
            records = new_records(self.deck.output)
        self.state = state
        every = int(checkpoint_every or 0)
        records["checkpoint_every"] = every
        ctx = self._context(out, records, finished)
        observers: list[Observer] = []  # made inside the first hook: under MPI they may
        total = self._sync(state, 0, 0)[1]  # gather (the other ranks serve then)

        def start(v: State) -> None:
            observers.extend(self._observers(ctx.run, ctx.model, every))
            _on_start(observers, ctx, resume, v)

        self._observe(state, ctx, start, total)
        n_total = solver.total_steps()
        t_start = time.perf_counter()
        steps_done_here = 0
        work = 0  # force evaluations: steps, or iterations of a static solver
        bar = progress_bar(quiet or not progress or not root, n_total, state.step, self.deck.name)
        error = None
        stop = StopRequest()
        stopped = False  # a Ctrl-C on some rank, agreed after a step
        crash = _crash_hook(dist)
        try:
            with stop, bar:
                while not solver.done(state) and not ctx.stop and not stopped:
                    if dist is None and stop.requested:
                        break
                    before = state.bonds_broken
                    result = solver.step(state)
                    broken, total, stopped = self._sync(
                        state, state.bonds_broken - before, stop.signum if stop.requested else 0
                    )
                    result.broken = broken
                    steps_done_here += 1
                    work += result.iterations
                    self._observe(state, ctx, partial(_on_step, observers, ctx, result),
                                  total)  # fmt: skip
                    if crash is not None and state.step == crash:
                        os._exit(137)
                    if state.step % 50 == 0 or solver.done(state):
                        bar.update(state.step)
                stopped = stopped or (dist is None and stop.requested)
                if dist is None and stop.requested:
                    self._stop_signal = stop.signum
                if not stopped:
                    solver.check(state)  # the last steps are checked too
        except SimulationUnstable as exc:
            ctx.status, error = "unstable", str(exc)
            good = exc.last_good or state
            frames = VTKFrames(ctx.run, ctx.model)
            self._observe(good, ctx, lambda v: frames.frame(ctx, v, name="last_good.vtu"),
                          total)  # fmt: skip
            wall = time.perf_counter() - t_start
            self._finish(ctx, state, observers, wall, steps_done_here, work, error)
            raise
        wall = time.perf_counter() - t_start
        if stopped and not (solver.done(state) or ctx.stop):
            ctx.status = "interrupted"
            summary = self._finish(ctx, state, observers, wall, steps_done_here, work, None)
            checkpoint = None
            if every:  # after _finish: the records then list the frame it wrote
                checkpoint = self._checkpoint(ctx, state, {"finished": False})
            raise RunInterrupted(
                state.step, state.t, n_total, checkpoint, summary, self._stop_signal
            )
        summary = self._finish(ctx, state, observers, wall, steps_done_here, work, error)
        if every:  # the final state, marked finished: a --resume of it is refused
            self._checkpoint(ctx, state, {"finished": True})
        return summary

    def _context(self, out: Path, records: dict[str, Any], finished: bool) -> RunContext:
        """What the observers share; under MPI they see the whole body
        (:class:`~peridynamics.parallel.session.GlobalModel`)."""
        obs_model: Any = self.model
        if self.session is not None:
            from peridynamics.parallel.session import GlobalModel

            obs_model = GlobalModel(self.session, self.global_bonds())
        run = run_options(self.deck)
        ctx = RunContext(run, obs_model, self.solver, out, records, self.fingerprint())
        ctx.session = self.session
        ctx.stop = finished  # finished, but the outputs were not written: write them
        return ctx

    def _observers(self, run: RunOptions, obs_model: Any, every: int) -> list[Observer]:
        """The observers of this run (rank 0's under MPI)."""
        observers = observers_for(run, obs_model, getattr(self.solver, "step_events", ()), every)
        observers = [*self.extra_observers, *observers]  # Checkpoints stays last
        if self.session is not None:  # the crash hook of a decomposed run is _crash_hook
            observers = [ob for ob in observers if not isinstance(ob, CrashAtStep)]
        return observers

    # -- the decomposed run's collective steps (no-ops or plain calls when serial) -------
    def global_bonds(self) -> int:
        """Directed bonds of the whole body (owned families of every rank)."""
        return int(self.session.comm.sum(float(self.model.owned_bonds)))

    def _sync(self, state: State, broken: int, stop: int) -> tuple[int, int, bool]:
        """(bonds broken by this step, bonds broken in the run, a stop signal somewhere)
        over every rank (one ``Allreduce``); ``stop``: the number of the signal this
        rank received (0: none), kept in ``_stop_signal``."""
        if self.session is None:
            return broken, state.bonds_broken, stop > 0
        v = self.session.comm.sum_array(
            np.array([broken, state.bonds_broken, stop, stop > 0], dtype=np.float64)
        )
        if v[3] > 0:  # the signal the ranks that received one received (mpiexec forwards)
            self._stop_signal = int(round(v[2] / v[3]))
        return int(v[0]), int(v[1]), bool(v[3] > 0)

    def _observe(
        self, state: State, ctx: RunContext, work: Callable[[State], Any], total: int
    ) -> None:
        """Run ``work`` (observer hooks) on rank 0 with the whole body's view of
        ``state`` while the other ranks answer its requests; ``ctx.stop`` is agreed."""
        dist = self.session
        if dist is None:
            work(state)
            return
        from peridynamics.parallel.session import GlobalState

        dist.state = state
        if not dist.root:
            ctx.stop, failure = dist.serve()
            if failure:
                raise RuntimeError(f"rank 0 failed while writing outputs: {failure}")
            return
        failure = None
        try:
            work(GlobalState(dist, state, total))
        except BaseException as exc:
            failure = f"{type(exc).__name__}: {exc}"
            raise
        finally:
            dist.end_step((ctx.stop, failure))

    def _checkpoint(self, ctx: RunContext, state: State, meta: dict[str, Any]) -> Path | None:
        """A checkpoint of ``state`` (every rank its own part under MPI)."""
        got: list[Path | None] = [None]

        def work(v: State) -> None:
            got[0] = ctx.write_checkpoint(v, meta)

        self._observe(state, ctx, work, state.bonds_broken)
        return got[0]

    def _finish(
        self,
        ctx: RunContext,
        s: State,
        observers: list[Observer],
        wall: float,
        steps: int,
        work: int,
        error: str | None,
    ) -> dict:
        """final_state.npz, the results every run has, then each observer's (rank 0
        under MPI, the other ranks serving; they return an empty mapping)."""
        got: dict[str, Any] = {}
        total = self._sync(s, 0, 0)[1]
        ranks: dict[str, Any] | None = None
        if self.session is not None:  # the halo time of the slowest rank, memory per rank
            comm = self.session.comm
            ranks = {
                "ranks": comm.size,
                "halo_exchange_s": comm.max(comm.exchange_s),
                "halo_exchanges": comm.exchanges,
                "points_per_rank": comm.gather_objects(comm.n_owned),
                "ghosts_per_rank": comm.gather_objects(comm.layout.n_local - comm.n_owned),
                "set_up": self.session.set_up,
            }

        def finish(v: State) -> None:
            got.update(self._finish_root(ctx, v, observers, wall, steps, work, error, ranks))

        self._observe(s, ctx, finish, total)
        return got

    def _write_final_state(self, ctx: RunContext, s: State, damage: NDArray) -> None:
        """``final_state.npz`` of a serial run."""
        m = ctx.model
        extra_fields: dict[str, Any] = {}
        try:  # the per-point random field (Weibull) a run drew, and no-fail points (inf)
            extra_fields["critical_stretch"] = m.point_s0
        except AttributeError:
            pass
        for group in m.force_model.dofs()[1:]:  # micropolar: theta (rad), moment (N m/m^3)
            extra_fields[group.value] = s[group.value]
            extra_fields[group.force] = s[group.force]
        for name in ("interface_intact", "bond_kappa"):  # several bodies, softening bonds
            if name in s:
                extra_fields[name] = s[name]
        if "T" in s:  # a heat solver's temperature (K)
            extra_fields["temperature"] = s["T"]
        save_npz(
            ctx.out / "final_state.npz",
            u=s.u,
            v=s.v,
            damage=damage,
            t=s.t,
            step=s.step,
            x=m.cloud.x,
            intact=s.intact,
            **extra_fields,
        )

    def _finish_root(
        self,
        ctx: RunContext,
        s: State,
        observers: list[Observer],
        wall: float,
        steps: int,
        work: int,
        error: str | None,
        ranks: dict[str, Any] | None = None,
    ) -> dict:
        m = ctx.model
        if self.session is not None:  # every rank writes its piece; numbers reduced
            self.session.call("call", write_final_pieces, str(ctx.out))
            max_damage, max_u, damaged = self.session.call("call", final_stats)
        else:
            damage = ctx.damage(s)
            self._write_final_state(ctx, s, damage)
            max_damage, max_u = float(damage.max()), float(np.abs(s.u).max())
            damaged = float(np.mean(damage >= 0.3))
        kinetic, strain = ctx.energies(s)
        results: dict[str, Any] = {
            "n_points": m.cloud.n_points,
            "n_bonds": m.bonds.n_bonds,
            "spacing_m": m.cloud.spacing,
            "horizon_m": m.bonds.horizon,
            **self.solver.summary_fields(s),
            "steps": s.step,
            "final_time_s": s.t,
            "max_damage": max_damage,
            "bonds_broken": s.bonds_broken,
            "max_displacement_m": max_u,
            "kinetic_energy_J": kinetic,
            "strain_energy_J": strain,
            "damaged_area_fraction": damaged,
        }
        if m.cloud.grid_fit:  # lengths that were not whole multiples of the spacing
            results["geometry_fit"] = [f.as_dict() for f in m.cloud.grid_fit]
        files: list[str] = []
        for ob in observers:
            files += ob.finalize(ctx, s, results)
        if ranks is not None and self.session is not None:  # the peak after every output
            ranks["peak_rss_gib_per_rank"] = self.session.call("call", gather_rss)
            ranks["to_root"] = self.session.to_root()  # the gather audit (docs/mpi.md)
        n_b = m.bonds.n_bonds
        timing: dict[str, Any] = {
            "wall_s": wall,
            "steps": steps,
            "setup_s": self.setup_s,
            "bond_updates_per_s": n_b * work / wall if wall > 0 and work else 0.0,
            "seconds_per_step": wall / steps if steps else 0.0,
        }
        if work != steps:  # a static solver: iterations per step vary
            timing["iterations"] = work
        if ranks is not None:  # a decomposed run
            timing.update(ranks)
        extra: dict[str, Any] = {"status": ctx.status, "files": files}
        changed = notices(self.deck)
        if changed:  # defaults this deck relies on that changed (deck.changed_defaults)
            extra["notices"] = changed
        if ctx.status == "interrupted":
            extra["stop_signal"] = signal_name(self._stop_signal)
        if error:
            extra["error"] = error
        return write_summary(
            ctx.out / "summary.json",
            self.deck.model_dump(mode="json", by_alias=True),
            results,
            timing,
            extra,
        )


def _on_start(observers: list[Observer], ctx: RunContext, resumed: bool, s: State) -> None:
    """Every observer's ``on_start`` hook."""
    for ob in observers:
        ob.on_start(ctx, s, resumed)


def _on_step(observers: list[Observer], ctx: RunContext, result: Any, s: State) -> None:
    """Every observer's ``on_step`` hook."""
    for ob in observers:
        ob.on_step(ctx, s, result)


def _crash_hook(dist: Any) -> int | None:
    """Test hook of a decomposed run: the step after which rank
    ``PERIDYNAMICS_CRASH_RANK`` (default 0) dies (exit 137, like SIGKILL), from
    ``PERIDYNAMICS_CRASH_AT_STEP``; ``None`` when unset or serial (serial runs use the
    :class:`~peridynamics.io.observers.events.CrashAtStep` observer)."""
    if dist is None or "PERIDYNAMICS_CRASH_AT_STEP" not in os.environ:
        return None
    if int(os.environ.get("PERIDYNAMICS_CRASH_RANK", "0")) != dist.comm.rank:
        return None
    return int(os.environ["PERIDYNAMICS_CRASH_AT_STEP"])


class RunInterrupted(KeyboardInterrupt):
    """The run stopped at a user's or a batch system's request (Ctrl-C, SIGTERM, SIGHUP,
    SIGUSR1: ``signum``) after a complete step; the outputs and a summary with status
    ``"interrupted"`` are written, and ``checkpoint`` is the checkpoint of that state
    (``None`` when checkpointing was off).

    Examples
    --------
    >>> import os, signal
    >>> import peridynamics as pd
    >>> sim = pd.Simulation(pd.Deck.example("bar_wave_1d"),
    ...                     callbacks=[lambda s: os.kill(os.getpid(), signal.SIGINT)])
    >>> try:
    ...     sim.run()
    ... except pd.RunInterrupted as stop:
    ...     print(stop.step, stop.summary["status"])
    1 interrupted
    """

    def __init__(
        self,
        step: int,
        t: float,
        total: int,
        checkpoint: Path | None,
        summary: dict,
        signum: int = int(signal.SIGINT),
    ) -> None:
        self.step, self.t, self.total = step, t, total
        self.checkpoint, self.summary, self.signum = checkpoint, summary, signum
        super().__init__(f"interrupted after step {step} of {total} (t = {t:.6g} s)")


class Simulation(SimulationSetup, RunLoop):
    """A deck turned into objects (:meth:`SimulationSetup.from_deck`), ready to
    :meth:`~RunLoop.run`."""
