"""A simulation driven from Python: :class:`Simulation` and user callbacks.

:class:`Simulation` builds a deck into a model and solver exactly as ``peridynamics
run`` does (the same size checks, the same run loop, the same output files and the
same bits) and returns a :class:`~peridynamics.api.result.Result`. Without ``out`` the
files go to a temporary folder that lives as long as the result does, so a script or
notebook leaves nothing behind unless it asks (:meth:`Result.save`).
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.api.deck import Deck
from peridynamics.api.result import Result
from peridynamics.app.checks import build_checked
from peridynamics.app.run import RunInterrupted
from peridynamics.app.run import Simulation as _RunSimulation
from peridynamics.build.errors import SetupError
from peridynamics.deck.schema import Deck as DeckSchema
from peridynamics.io.observers.base import Observer, RunContext
from peridynamics.io.observers.point_fields import POINT_FIELDS, point_fields
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

__all__ = ["Callback", "RunInterrupted", "Simulation"]


class Callback:
    """User code called by the run loop: subclass it and override any hook.

    A hook that returns ``True`` from :meth:`on_step` stops the run after that step
    (outputs and summary are written as for a finished run; the summary's ``results``
    then hold ``stopped_by: "callback"``). Under ``mpiexec`` the hooks run on rank 0 and
    see the whole body. A plain function ``f(state)`` passed as a callback is called as
    :meth:`on_step` is.

    Parameters
    ----------
    every : int
        Steps between calls of :meth:`on_step` (default 1: every step).

    Examples
    --------
    >>> import peridynamics as pd
    >>> class Peak(pd.Callback):
    ...     def __init__(self):
    ...         super().__init__(every=10)
    ...         self.peak = 0.0
    ...     def on_step(self, state, result):
    ...         self.peak = max(self.peak, float(abs(state.u).max()))
    >>> peak = Peak()
    >>> deck = pd.Deck.example("bar_wave_1d", {"solver.end_time": 5.0e-5})
    >>> result = pd.Simulation(deck, callbacks=[peak]).run()
    >>> peak.peak > 0.0
    True
    """

    def __init__(self, every: int = 1) -> None:
        if int(every) < 1:
            raise ValueError(f"Callback(every={every!r}): give a number of steps >= 1")
        self.every = int(every)

    def on_start(self, state: State) -> None:
        """Once, before the first step (after a resume: at the resumed step)."""

    def on_step(self, state: State, result: StepResult) -> bool | None:
        """After every ``every``-th step; return ``True`` to stop the run."""
        return None

    def on_finish(self, state: State, summary_results: dict[str, Any]) -> None:
        """Once, at the end: ``summary_results`` is the summary's ``results`` mapping
        (add entries to it to have them written to ``summary.json``)."""


class _FunctionCallback(Callback):
    """A plain function ``f(state)`` as a callback (its return value may stop the run)."""

    def __init__(self, fn: Callable[[State], Any]) -> None:
        super().__init__(1)
        self.fn = fn

    def on_step(self, state: State, result: StepResult) -> bool | None:
        return bool(self.fn(state))


class _CallbackObserver(Observer):
    """A :class:`Callback` as one of the run loop's observers."""

    def __init__(self, callback: Callback) -> None:
        self.callback = callback
        self.stopped = False

    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        self.callback.on_start(s)

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if s.step % self.callback.every == 0 and self.callback.on_step(s, result):
            self.stopped = ctx.stop = True

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        if self.stopped:
            results["stopped_by"] = "callback"
        self.callback.on_finish(s, results)
        return []


def _as_callback(cb: Callback | Callable[[State], Any]) -> Callback:
    if isinstance(cb, Callback):
        return cb
    if callable(cb):
        return _FunctionCallback(cb)
    raise TypeError(f"callbacks: {cb!r} is neither a peridynamics.Callback nor a function f(state)")


def _deck_of(deck: Deck | DeckSchema | str | Path | Mapping[str, Any], overrides: Any) -> Deck:
    """Any of the accepted forms of a deck as a validated :class:`Deck`."""
    if isinstance(deck, DeckSchema):
        plain = Deck._of(deck)
        return plain.with_(overrides) if overrides else plain
    if isinstance(deck, str | Path):
        return Deck.from_file(deck, overrides)
    if isinstance(deck, Mapping):
        return Deck.from_dict(deck, overrides)
    raise TypeError(
        f"Simulation(deck={type(deck).__name__}): give a peridynamics.Deck, a deck file's "
        "path or a mapping of sections"
    )


def _communicator(comm: Any) -> Any:
    """``"auto"``: COMM_WORLD under ``mpiexec -n N`` (N > 1), else ``None``."""
    if comm != "auto":
        return comm
    from peridynamics.parallel.launch import LaunchError, mpi_comm, share_cores

    try:
        got = mpi_comm()
    except LaunchError as exc:
        raise SetupError("mpiexec", str(exc)) from None
    if got is not None:
        share_cores(got)
    return got


class Simulation:
    """A deck built into a model and a solver, ready to run from Python.

    The build is the command line's: ``peridynamics run`` and :meth:`run` give the same
    results bit for bit, and write the same files.

    Parameters
    ----------
    deck : Deck, str, Path or mapping
        The deck, a deck file or a mapping of sections.
    overrides : mapping or list of str, optional
        Values changed by key path (``{"solver.end_time": 1e-4}``), as ``--set`` does.
    out : str or Path, optional
        The run folder. ``None`` (default): a temporary folder removed when the
        :class:`~peridynamics.api.result.Result` is garbage-collected
        (:meth:`Result.save` keeps a copy).
    callbacks : list of Callback or functions ``f(state)``, optional
        User code run after steps (:class:`Callback`).
    progress : bool
        A progress bar (in a terminal; in Jupyter an HTML bar). Default ``False``.
    allow_large : bool
        Build a model the size checks would refuse (``--allow-large``).
    comm : ``"auto"``, mpi4py communicator or None
        ``"auto"`` (default): decomposed over the ranks of ``mpiexec -n N`` when started
        so, as ``peridynamics run`` is; ``None``: serial.

    Raises
    ------
    peridynamics.DeckError
        An invalid deck (the messages of ``peridynamics check``).
    peridynamics.SetupError
        A valid deck whose model cannot be built, or one too large for this machine.

    Examples
    --------
    >>> import peridynamics as pd
    >>> sim = pd.Simulation(pd.Deck.example("bar_wave_1d"), {"solver.end_time": 5.0e-5})
    >>> sim.n_points, sim.n_bonds
    (201, 1194)
    >>> result = sim.run()
    >>> result.summary["results"]["steps"]
    50
    """

    def __init__(
        self,
        deck: Deck | DeckSchema | str | Path | Mapping[str, Any],
        overrides: Mapping[str, Any] | Iterable[str] | None = None,
        *,
        out: str | Path | None = None,
        callbacks: Iterable[Callback | Callable[[State], Any]] = (),
        progress: bool = False,
        allow_large: bool = False,
        comm: Any = "auto",
    ) -> None:
        self.deck = _deck_of(deck, overrides)
        self.callbacks = [_as_callback(cb) for cb in callbacks]
        self.progress = bool(progress)
        comm = self._comm = _communicator(comm)
        sim, problem = build_checked(self.deck, comm, allow_large)
        if problem:
            key, _, why = problem.partition(": ")
            raise SetupError(key, why.replace("pass --allow-large", "pass allow_large=True"))
        self._sim: _RunSimulation = sim
        self._tmp: tempfile.TemporaryDirectory[str] | None = None
        if out is None:  # under MPI: rank 0's temporary folder, shared by every rank
            rank = 0 if comm is None else int(comm.Get_rank())
            if rank == 0:
                self._tmp = tempfile.TemporaryDirectory(prefix=f"peridynamics_{self.deck.name}_")
            name = self._tmp.name if self._tmp is not None else None
            self.out = Path(str(name if comm is None else comm.bcast(name, root=0)))
        else:
            self.out = Path(out)
            self.out.mkdir(parents=True, exist_ok=True)
        self._ran = False

    # -- what was built ---------------------------------------------------------------
    @property
    def n_points(self) -> int:
        """Points of the model (the whole body under MPI)."""
        s = self._sim
        return int(s.session.global_cloud.n_points if s.session is not None else s.cloud.n_points)

    @property
    def n_bonds(self) -> int:
        """Directed bonds of the model (the whole body under MPI)."""
        s = self._sim
        return int(s.global_bonds() if s.session is not None else s.model.bonds.n_bonds)

    @property
    def model(self) -> Any:
        """The built model (:class:`~peridynamics.evaluation.evaluator.Evaluator`): ``model.cloud``
        (points), ``model.bonds`` (the directed bond list), ``model.force_model``."""
        return self._sim.model

    @property
    def solver(self) -> Any:
        """The built solver (``solver.describe()`` says which, with its step)."""
        return self._sim.solver

    @property
    def state(self) -> State:
        """The current state: the initial one before any step, then the latest
        (``state.u`` (n, dim) m, ``state.v`` m/s, ``state.t`` s, ``state.step``,
        ``state.intact`` per directed bond, any field by name: ``state["theta"]``)."""
        sim = self._sim
        if sim.state is None:
            sim.state = sim.start_state = sim.solver.init()
        return sim.state

    def field(self, name: str) -> NDArray[np.float64]:
        """A computed point field of the current state, by its frame field name:
        ``stress`` and ``strain`` (n, 3, 3) (Pa; dimensionless), ``von_mises`` and
        ``pressure`` (n,) (Pa), ``principal_stress`` (n, 3) (Pa, largest first),
        ``principal_direction`` (n, 3) (docs/stress.md). Serial runs only (under MPI
        the frames carry these fields: ``output.fields``).

        Raises
        ------
        KeyError
            For a name that is not a computed field (the message lists them).
        ValueError
            Under MPI, or for a model without a stress (micropolar).
        """
        if name not in POINT_FIELDS:
            raise KeyError(f"{name!r} is not a computed point field; known: {list(POINT_FIELDS)}")
        if self._sim.session is not None:
            raise ValueError("Simulation.field is serial; under MPI write it into the frames")
        values = point_fields([name], self.model, self.state)[name]
        if name in ("stress", "strain"):
            values = values.reshape(-1, 3, 3)
        return values

    @property
    def done(self) -> bool:
        """The solver has reached the end of the run (end time, steps or loading)."""
        return bool(self._sim.solver.done(self.state))

    def step(self, n: int = 1) -> State:
        """Advance the state by up to ``n`` solver steps (fewer at the end of the run).

        The deck's outputs are not recorded here (no frames or histories; :meth:`run`
        records from the state it starts at); the callbacks' :meth:`Callback.on_step`
        are called. Returns :attr:`state`.

        Examples
        --------
        >>> import peridynamics as pd
        >>> sim = pd.Simulation(pd.Deck.example("bar_wave_1d"))
        >>> sim.step(20).step
        20
        """
        if self._ran:
            raise RuntimeError("Simulation.step: this simulation has run; make a new one")
        if int(n) < 0:
            raise ValueError(f"Simulation.step(n={n!r}): give a number of steps >= 0")
        if self._sim.session is not None:
            raise SetupError(
                "mpiexec", "Simulation.step is serial; under mpiexec use run() with callbacks"
            )
        state, solver = self.state, self._sim.solver
        for _ in range(int(n)):
            if solver.done(state):
                break
            result = solver.step(state)
            for cb in self.callbacks:
                if state.step % cb.every == 0:
                    cb.on_step(state, result)
        return state

    def run(self, checkpoint_every: int = 0, resume: bool = False, quiet: bool = True) -> Result:
        """Run to the end (from :attr:`state` when :meth:`step` was called) and return the
        result; the run folder holds what ``peridynamics run`` writes.

        Parameters
        ----------
        checkpoint_every : int
            Steps between checkpoints (0: none), as ``--checkpoint-every``.
        resume : bool
            Continue the interrupted run of the folder ``out`` from its checkpoint, as
            ``--resume`` does.
        quiet : bool
            No messages (default ``True``; the progress bar is the ``progress`` argument).

        Raises
        ------
        peridynamics.RunInterrupted
            Ctrl-C or a stop signal ended the run after a complete step; its
            ``checkpoint`` (with ``checkpoint_every``) resumes it.
        peridynamics.SimulationUnstable
            The run went unstable (``summary.json`` and ``last_good.vtu`` are written).
        """
        if self._ran:
            raise RuntimeError("Simulation.run: this simulation has run; make a new one")
        if resume and self._tmp is not None:
            raise SetupError("out", "resume=True needs the folder of the interrupted run: out=")
        if int(checkpoint_every) < 0:
            raise ValueError("checkpoint_every must be >= 0 (0: no checkpoints)")
        sim = self._sim
        sim.extra_observers = tuple(_CallbackObserver(cb) for cb in self.callbacks)
        self._ran = True
        summary = sim.run(
            self.out,
            quiet=quiet and not self.progress,  # the run loop's bar needs quiet off
            checkpoint_every=int(checkpoint_every) if checkpoint_every or not resume else None,
            resume=resume,
            progress=self.progress,
        )
        if self._comm is not None:  # rank 0 wrote the summary: every rank returns it
            summary = self._comm.bcast(summary if self._comm.Get_rank() == 0 else None, root=0)
        result = Result(self.out, summary=summary)
        result._keep = self._tmp  # a temporary folder lives as long as the result
        return result

    def __repr__(self) -> str:
        return (
            f"Simulation({self.deck.name!r}: {self.n_points} points, {self.n_bonds} bonds, "
            f"{self.solver.describe()} -> {self.out})"
        )
