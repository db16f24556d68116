"""What the commands' parsers share: the exit codes and help topics printed under
``--help``, and the arguments of every command that reads a deck."""

from __future__ import annotations

import argparse

from peridynamics.app.checks import MAX_BOND_UPDATES

EXIT_CODES = """exit codes:
  0    success
  2    invalid deck or set-up (key.path: message on stderr), a model too large for
       this machine (see --allow-large), bad arguments
  3    run: the run went unstable (summary.json and last_good.vtu are written)
  130  run: interrupted by Ctrl-C (summary.json with status "interrupted"; with
       --checkpoint-every N also a checkpoint: peridynamics run DECK --resume DIR)"""
HELP_TOPICS = """the reference, from the installed package (the documentation site's pages):
  peridynamics help deck               every key a deck accepts, type and default
  peridynamics help deck.SECTION       one section with units, ranges and examples,
                                       e.g. deck.material, deck.solver.adr, deck.bodies
  peridynamics help output             the files of a run and summary.json"""


def deck_args(sp: argparse.ArgumentParser) -> None:
    """The deck and its ``--set`` overrides."""
    sp.add_argument("deck", help="YAML deck")
    sp.add_argument(
        "--set",
        action="append",
        metavar="KEY.PATH=VALUE",
        help="override a deck value (repeatable), e.g. solver.steps=100; the keys: "
        "peridynamics help deck.SECTION",
    )


def large_arg(sp: argparse.ArgumentParser) -> None:
    """``--allow-large``: run a model the size checks would refuse."""
    sp.add_argument(
        "--allow-large",
        action="store_true",
        help="do not refuse a model estimated to exceed the available memory, or a run "
        f"of more than {MAX_BOND_UPDATES:.0e} bond updates (steps x bonds)",
    )
