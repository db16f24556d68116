"""The entry point of the ``peridynamics`` console script."""

from __future__ import annotations

import os
import signal
import sys
import warnings

from peridynamics.app.checks import err, out_of_memory
from peridynamics.app.exit_codes import EXIT_INTERRUPTED, EXIT_OK, exit_for_signal
from peridynamics.app.run_progress import signal_name
from peridynamics.cli.parser import build_parser


def _format_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    line: str | None = None,
) -> str:
    return f"warning: {message}\n"


def run_command(argv: list[str] | None = None) -> int:
    """Parse ``argv`` and run the command (:func:`peridynamics.cli.main` imports this
    module once the stop signals are set to raise :class:`KeyboardInterrupt`)."""
    # warnings of the package read as messages, not as source lines
    warnings.formatwarning = _format_warning  # type: ignore[assignment]
    try:
        args = build_parser().parse_args(argv)
        return int(args.func(args))
    except KeyboardInterrupt as exc:  # outside a run's loop (set-up), or a second one
        signum = getattr(exc, "signum", None)
        if signum is None or signum == signal.SIGINT:
            err("interrupted (Ctrl-C); nothing more was written")
            return EXIT_INTERRUPTED
        err(f"interrupted ({signal_name(signum)}); nothing more was written")
        return exit_for_signal(signum)
    except MemoryError as exc:
        return out_of_memory(exc)
    except BrokenPipeError:  # the reader went away (peridynamics help deck | head)
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - no flush error at exit
        return EXIT_OK
