"""What the run loop shows and hears while it steps: the progress bar (steps per second
and the time left) and the stop request (Ctrl-C, SIGTERM, SIGHUP, SIGUSR1) that ends a
run between two steps."""

from __future__ import annotations

import signal
import threading
import time
from typing import Any

#: the signals that stop a run between two steps as Ctrl-C does: SIGINT (Ctrl-C),
#: SIGTERM (a batch system's time limit, ``kill``), SIGHUP (the terminal closed) and
#: SIGUSR1 (Slurm's ``--signal=USR1@SECONDS`` warning before the time limit)
STOP_SIGNALS = tuple(
    getattr(signal, name)
    for name in ("SIGINT", "SIGTERM", "SIGHUP", "SIGUSR1")
    if hasattr(signal, name)
)


def signal_name(signum: int) -> str:
    """``SIGTERM`` for 15, and so on."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


#: a stop signal that the command line's start-up handler received
#: (:func:`peridynamics.cli.main`) and that no run loop has acted on yet
_startup_stops: list[int] = []


def note_startup_stop(signum: int) -> None:
    """Record a stop signal received during start-up. The handler also raises
    KeyboardInterrupt, but library code may swallow it (C code that clears every error)
    or wrap it (pybind11's and PyO3's module initialisers turn it into an ImportError or
    a panic); the record lets the command line still end with 128 + the signal's number
    and makes the next :class:`StopRequest` start as requested."""
    _startup_stops[:] = [int(signum)]


def startup_stop() -> int | None:
    """The stop signal recorded by :func:`note_startup_stop` and not yet acted on."""
    return _startup_stops[-1] if _startup_stops else None


def clear_startup_stop() -> None:
    """Forget a recorded start-up stop signal (each command starts without one)."""
    _startup_stops.clear()


class StopRequest:
    """While active (a context manager, main thread only), the first of the
    :data:`STOP_SIGNALS` only sets ``requested`` (and ``signum``) so that the run loop
    stops between two steps; a second one raises KeyboardInterrupt at once. Elsewhere
    the signals keep their handlers. A stop signal recorded during start-up and lost
    on the way (:func:`note_startup_stop`) makes it start as requested: the run then
    stops before its first step."""

    def __init__(self) -> None:
        self.requested = False
        self.signum = int(signal.SIGINT)
        self._previous: dict[int, Any] = {}

    def _handler(self, signum: int, frame: Any) -> None:
        if self.requested:
            raise KeyboardInterrupt
        self.requested = True
        self.signum = signum

    def __enter__(self) -> StopRequest:
        if _startup_stops:
            self.requested, self.signum = True, _startup_stops.pop()
            _startup_stops.clear()
        if threading.current_thread() is threading.main_thread():
            for sig in STOP_SIGNALS:
                self._previous[sig] = signal.signal(sig, self._handler)
        return self

    def __exit__(self, *exc: object) -> None:
        for sig, previous in self._previous.items():
            signal.signal(sig, previous)
        self._previous = {}


class _NoBar:
    def __enter__(self) -> _NoBar:
        return self

    def __exit__(self, *a: object) -> None:
        return None

    def update(self, step: int) -> None:
        return None


def _clock(seconds: float) -> str:
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    return f"{h}:{rest // 60:02d}:{rest % 60:02d}"


class _RateColumn:
    """Steps per second and the time left, from the average rate since this process
    started stepping (rich's own estimate uses the last few updates and jumps about when
    the machine is shared)."""

    def __init__(self, start: int) -> None:
        self.start = start
        self.t0 = time.perf_counter()

    def text(self, completed: float, total: float | None) -> str:
        done = completed - self.start
        elapsed = time.perf_counter() - self.t0
        if done <= 0 or elapsed <= 0:
            return "-- steps/s"
        rate = done / elapsed
        left = f" ETA {_clock((total - completed) / rate)}" if total else ""
        return f"{rate:.3g} steps/s{left}"


class _RichBar:
    def __init__(self, total: int, start: int, label: str) -> None:
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            ProgressColumn,
            TextColumn,
            TimeElapsedColumn,
        )
        from rich.text import Text

        rate = _RateColumn(start)

        class RateColumn(ProgressColumn):
            def render(self, task: Any) -> Text:
                return Text(rate.text(task.completed, task.total), style="progress.remaining")

        self.p = Progress(
            TextColumn(f"[bold]{label}"),
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("steps"),
            TimeElapsedColumn(),
            RateColumn(),
        )
        self.task = self.p.add_task(label, total=total, completed=start)

    def __enter__(self) -> _RichBar:
        self.p.__enter__()
        return self

    def __exit__(self, *a: Any) -> None:
        self.p.__exit__(*a)

    def update(self, step: int) -> None:
        self.p.update(self.task, completed=step)


class _NotebookBar:
    """The progress bar in a Jupyter notebook: an HTML ``<progress>`` element updated in
    place (IPython's display handle; no widget library), at most four times a second."""

    def __init__(self, total: int, start: int, label: str) -> None:
        self.total, self.label, self.rate = max(int(total), 1), label, _RateColumn(start)
        self.step, self.shown = start, 0.0
        self.handle: Any = None

    def _html(self) -> Any:
        from html import escape

        from IPython.display import HTML

        return HTML(
            f"<div><b>{escape(self.label)}</b> <progress value='{self.step}' "
            f"max='{self.total}' style='width:40%'></progress> {self.step}/{self.total} "
            f"steps, {escape(self.rate.text(self.step, self.total))}</div>"
        )

    def __enter__(self) -> _NotebookBar:
        from IPython.display import display

        self.handle = display(self._html(), display_id=True)
        return self

    def __exit__(self, *a: object) -> None:
        if self.handle is not None:
            self.handle.update(self._html())

    def update(self, step: int) -> None:
        self.step = step
        now = time.perf_counter()
        if self.handle is not None and now - self.shown >= 0.25:
            self.shown = now
            self.handle.update(self._html())


def in_notebook() -> bool:
    """True inside a Jupyter kernel (IPython's ZMQ shell)."""
    import sys

    if "IPython" not in sys.modules:
        return False
    from IPython import get_ipython

    shell = get_ipython()
    return shell is not None and type(shell).__name__ == "ZMQInteractiveShell"


def progress_bar(off: bool, total: int, start: int, label: str) -> _NoBar | _RichBar | _NotebookBar:
    """The run's progress bar: none (``off``), an HTML bar in a Jupyter notebook, else
    rich's bar in the terminal."""
    if off:
        return _NoBar()
    return _NotebookBar(total, start, label) if in_notebook() else _RichBar(total, start, label)
