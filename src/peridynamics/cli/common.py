"""What the commands' parsers share: the exit codes and help topics printed under
``--help``, and the arguments of every command that reads a deck."""

from __future__ import annotations

import argparse
from pathlib import Path

from peridynamics.app.checks import MAX_BOND_UPDATES, err

EXIT_CODES = """exit codes:
  0    success
  2    invalid deck or set-up (key.path: message on stderr), a model too large for
       this machine (see --allow-large), bad arguments
  3    run: the run went unstable (summary.json and last_good.vtu are written)
  130  run: interrupted by Ctrl-C (summary.json with status "interrupted"; with
       --checkpoint-every N also a checkpoint: peridynamics run DECK --resume DIR)
  143  run: stopped by SIGTERM, as by Ctrl-C (129 SIGHUP, 138 SIGUSR1: 128 + the
       signal's number)"""
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


def out_folder_problem(folder: str | None, what: str, create: bool = False) -> bool:
    """Print what makes ``folder`` (the value of option ``what``) unusable as an output
    folder: empty, a file, or (``create``: the folder is made now) a place where no
    folder can be made. ``True`` when something is; ``None`` (not given) is fine."""
    if folder is None:
        return False
    if not folder.strip():
        err(f"{what}: an empty folder name; give a folder, e.g. {what} results/mine")
        return True
    path = Path(folder)
    if path.exists() and not path.is_dir():
        err(f"{what}: {folder!r} exists and is not a folder; give a folder")
        return True
    if create:
        try:
            path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            err(
                f"{what}: cannot make the folder {folder!r} ({exc.strerror or exc}); give "
                f"a folder you can write, e.g. {what} results/mine"
            )
            return True
    return False
