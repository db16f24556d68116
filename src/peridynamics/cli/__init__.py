"""Command line: ``peridynamics run|check|examples|bench|dispersion|ensemble|sweep|help``.

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

#: the signals that end a command as Ctrl-C does (SIGTERM: a batch system's time limit
#: or ``kill``; SIGHUP: the terminal closed; SIGUSR1: Slurm's ``--signal`` warning)
_STOP = ("SIGTERM", "SIGHUP", "SIGUSR1")


class StopSignal(KeyboardInterrupt):
    """A stop signal (``signum``) received outside a run's time loop."""

    def __init__(self, signum: int) -> None:
        self.signum = signum
        super().__init__(signal.Signals(signum).name)


def _raise_stop(signum: int, frame: Any) -> None:
    raise StopSignal(signum)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``peridynamics`` console script (exit code returned)."""
    from threading import current_thread, main_thread

    if current_thread() is main_thread():
        for name in _STOP:
            if hasattr(signal, name):
                signal.signal(getattr(signal, name), _raise_stop)
    try:
        from peridynamics.cli.entry import run_command
    except KeyboardInterrupt as exc:
        signum = getattr(exc, "signum", int(signal.SIGINT))
        sys.stderr.write(
            f"interrupted ({signal.Signals(signum).name}) during start-up; nothing was written\n"
        )
        return 128 + signum
    code = run_command(argv)
    if argv is None and code > 128 and "mpi4py.MPI" not in sys.modules:
        _exit_now(code)
    return code


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
