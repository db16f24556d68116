"""The argument parser of the ``peridynamics`` command: each command group's module
adds its own subcommands."""

from __future__ import annotations

import argparse

from peridynamics import __version__
from peridynamics.cli import batch, calibrate, examples, run, tools, verify
from peridynamics.cli import help as help_cmd
from peridynamics.cli.common import EXIT_CODES, HELP_TOPICS


def build_parser() -> argparse.ArgumentParser:
    """The argument parser."""
    p = argparse.ArgumentParser(
        prog="peridynamics",
        description="Peridynamic simulation of fracture and waves.",
        epilog=EXIT_CODES + "\n\n" + HELP_TOPICS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--version", action="version", version=f"peridynamics {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    run.register(sub)
    batch.register(sub)
    calibrate.register(sub)
    run.register_check(sub)
    help_cmd.register(sub)
    examples.register(sub)
    tools.register_dispersion(sub)
    tools.register_bench(sub)
    verify.register(sub)
    return p
