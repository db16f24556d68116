"""Command line: ``peridynamics run|check|examples|bench|dispersion|ensemble|sweep|help``,
``calibrate`` and ``band``.

Exit codes: 0 success; 2 invalid deck or model set-up (the key path is on stderr), a
model too large for this machine, bad arguments; 3 the run went unstable (a summary and
``last_good.vtu`` are written); 130 interrupted by Ctrl-C, and 128 + the signal's number
for SIGTERM (143), SIGHUP (129) or SIGUSR1 (138) (a summary with status
``"interrupted"`` and, when checkpointing is on, a checkpoint to resume from).

One module per command group (:mod:`~peridynamics.cli.run`,
:mod:`~peridynamics.cli.batch`, :mod:`~peridynamics.cli.examples`,
:mod:`~peridynamics.cli.tools`, :mod:`~peridynamics.cli.help`), each adding its
subcommands to the parser (:mod:`~peridynamics.cli.parser`); the checks and exit codes
shared with the application layer live in :mod:`peridynamics.app.checks` and
:mod:`peridynamics.app.exit_codes`.

This module stays light: :func:`main` first makes every stop signal a
:class:`KeyboardInterrupt` and only then imports the commands (NumPy, Numba, the
models), so that Ctrl-C or SIGTERM during start-up ends with a message, not a traceback.
"""

from __future__ import annotations

import signal
import sys
from typing import Any

# light modules (the standard library only): the stop signals, their names, exit codes
from peridynamics.app.exit_codes import exit_for_signal
from peridynamics.app.run_progress import (
    STOP_SIGNALS,
    clear_startup_stop,
    note_startup_stop,
    signal_name,
    startup_stop,
)


class StopSignal(KeyboardInterrupt):
    """A stop signal (``signum``) received outside a run's time loop."""

    def __init__(self, signum: int) -> None:
        self.signum = signum
        super().__init__(signal_name(signum))


def _raise_stop(signum: int, frame: Any) -> None:
    note_startup_stop(signum)
    raise StopSignal(signum)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``peridynamics`` console script (exit code returned)."""
    from threading import current_thread, main_thread

    clear_startup_stop()
    previous: dict[int, Any] = {}
    if current_thread() is main_thread():
        for sig in STOP_SIGNALS:
            previous[sig] = signal.signal(sig, _raise_stop)
    try:
        code = _import_and_run(argv)
    finally:
        clear_startup_stop()
        for sig, handler in previous.items():  # in-process callers get theirs back
            signal.signal(sig, handler if handler is not None else signal.SIG_DFL)
    if argv is None and code > 128 and "mpi4py.MPI" not in sys.modules:
        _exit_now(code)
    return code


def _import_and_run(argv: list[str] | None) -> int:
    """Import the commands and run one. A stop signal during start-up ends with 128 +
    its number even when the KeyboardInterrupt it raised was wrapped on the way (an
    import's C code: pydantic-core, SciPy's pybind11 modules) or swallowed (then the
    run stops before its first step, :class:`~peridynamics.app.run_progress.StopRequest`)."""
    try:
        from peridynamics.cli.entry import run_command

        return run_command(argv)
    except SystemExit:
        raise
    except BaseException as exc:
        signum = _wrapped_signal(exc) or startup_stop()
        if signum is None:
            raise
        sys.stderr.write(
            f"interrupted ({signal_name(signum)}) during start-up; nothing more was written\n"
        )
        if argv is None:  # the interrupt may have landed in C code (an import's)
            _exit_now(exit_for_signal(signum))
        return exit_for_signal(signum)


def _wrapped_signal(exc: BaseException) -> int | None:
    """The stop signal behind an exception that wraps a KeyboardInterrupt (chained, or
    only named in the message, as pydantic-core's SchemaError does when the interrupt
    lands while it builds a validator); ``None`` for any other exception."""
    seen: BaseException | None = exc
    while seen is not None:
        if isinstance(seen, KeyboardInterrupt):
            return int(getattr(seen, "signum", signal.SIGINT))
        seen = seen.__cause__ or seen.__context__
    text = str(exc)
    for sig in STOP_SIGNALS:
        if sig != signal.SIGINT and f"StopSignal: {signal_name(sig)}" in text:
            return int(sig)
    return int(signal.SIGINT) if "KeyboardInterrupt" in text or "StopSignal" in text else None


def _exit_now(code: int) -> None:
    """End the process with ``code`` now. After a KeyboardInterrupt raised inside C code
    that ran Python source (a compiler's), the interpreter would end by killing itself
    with SIGINT whatever the exit code; an interrupted command's code is 128 + the
    signal's number (its outputs are closed and written by then)."""
    import os

    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


def build_parser() -> Any:
    """The argument parser (:func:`peridynamics.cli.parser.build_parser`)."""
    from peridynamics.cli.parser import build_parser as build

    return build()


__all__ = ["StopSignal", "build_parser", "main"]
