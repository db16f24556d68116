"""What the run loop shows and hears while it steps: the progress bar (steps per second
and the time left) and the Ctrl-C request that stops a run between two steps."""

from __future__ import annotations

import signal
import threading
import time
from typing import Any


class StopRequest:
    """While active (a context manager, main thread only), the first SIGINT only sets
    ``requested`` so that the run loop stops between two steps; a second one raises
    KeyboardInterrupt at once. Elsewhere SIGINT keeps its handler."""

    def __init__(self) -> None:
        self.requested = False
        self._previous: Any = None
        self._installed = False

    def _handler(self, signum: int, frame: Any) -> None:
        if self.requested:
            raise KeyboardInterrupt
        self.requested = True

    def __enter__(self) -> StopRequest:
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, self._handler)
            self._installed = True
        return self

    def __exit__(self, *exc: object) -> None:
        if self._installed:
            signal.signal(signal.SIGINT, self._previous)
            self._installed = False


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


def progress_bar(off: bool, total: int, start: int, label: str) -> _NoBar | _RichBar:
    return _NoBar() if off else _RichBar(total, start, label)
