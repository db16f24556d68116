"""The entry point of the ``peridynamics`` console script."""

from __future__ import annotations

import os
import sys
import warnings

from peridynamics.app.checks import err, out_of_memory
from peridynamics.app.exit_codes import EXIT_INTERRUPTED, EXIT_OK
from peridynamics.cli.parser import build_parser


def _format_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    line: str | None = None,
) -> str:
    return f"warning: {message}\n"


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``peridynamics`` console script."""
    # warnings of the package read as messages, not as source lines
    warnings.formatwarning = _format_warning  # type: ignore[assignment]
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except KeyboardInterrupt:  # Ctrl-C outside a run's loop (set-up), or a second one
        err("interrupted (Ctrl-C); nothing more was written")
        return EXIT_INTERRUPTED
    except MemoryError as exc:
        return out_of_memory(exc)
    except BrokenPipeError:  # the reader went away (peridynamics help deck | head)
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - no flush error at exit
        return EXIT_OK
