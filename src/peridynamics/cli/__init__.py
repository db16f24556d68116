"""Command line: ``peridynamics run|check|examples|bench|dispersion|ensemble|sweep|help``.

Exit codes: 0 success; 2 invalid deck or model set-up (the key path is on stderr), a
model too large for this machine, bad arguments; 3 the run went unstable (a summary and
``last_good.vtu`` are written); 130 interrupted by Ctrl-C (a summary with status
``"interrupted"`` and, when checkpointing is on, a checkpoint to resume from).

One module per command group (:mod:`~peridynamics.cli.run`,
:mod:`~peridynamics.cli.batch`, :mod:`~peridynamics.cli.examples`,
:mod:`~peridynamics.cli.tools`, :mod:`~peridynamics.cli.help`), each adding its
subcommands to the parser (:mod:`~peridynamics.cli.parser`); the checks and exit codes
shared with the application layer live in :mod:`peridynamics.app.checks` and
:mod:`peridynamics.app.exit_codes`.
"""

from peridynamics.cli.entry import main
from peridynamics.cli.parser import build_parser

__all__ = ["build_parser", "main"]
