"""``peridynamics examples``: list the shipped examples, or copy one (its whole
folder)."""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path
from typing import Any

from peridynamics.app.checks import err
from peridynamics.app.examples import examples_dir, list_examples
from peridynamics.app.exit_codes import EXIT_INVALID, EXIT_OK


def cmd_examples(args: argparse.Namespace) -> int:
    """List the examples or copy one to a folder."""
    ex = list_examples()
    if args.action == "list" or args.action is None:
        for name, path in ex.items():
            print(f"{name:40s} {path}")
        return EXIT_OK
    if not args.name:
        err(
            "examples copy: give the NAME of an example (and a DEST folder), e.g. "
            f"peridynamics examples copy bar_wave_1d mine/; known: {', '.join(ex)}"
        )
        return EXIT_INVALID
    if args.name not in ex:
        err(f"unknown example {args.name!r}; known: {', '.join(ex)}")
        return EXIT_INVALID
    src = ex[args.name]
    dest = Path(args.dest or ".")
    if dest.exists() and not dest.is_dir():
        err(
            f"examples copy: {str(dest)!r} is a file; DEST is a folder to copy the example "
            f"into (e.g. peridynamics examples copy {args.name} mine/)"
        )
        return EXIT_INVALID
    try:
        dest.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        err(f"examples copy: cannot make the folder {str(dest)!r}: {exc.strerror}")
        return EXIT_INVALID
    # an example is its folder (decks, mesh files, scripts, README): copy all of it;
    # only a deck lying at the top of the examples tree is copied alone
    whole_folder = src.parent != examples_dir()
    target = dest / (src.parent.name if whole_folder else src.name)
    if target.exists() and not args.force:
        err(f"{str(target)!r} exists; not overwriting your copy (use --force to replace it)")
        return EXIT_INVALID
    if whole_folder:
        shutil.copytree(src.parent, target, dirs_exist_ok=True)
        if src.stem == "deck" or src.suffix == ".py":
            print(f"copied {args.name} to {target}")
        else:  # one deck of a folder of decks
            print(
                f"copied {args.name} with its folder to {target}; the deck is {target / src.name}"
            )
    else:
        shutil.copy2(src, target)
        print(f"copied {args.name} to {target}")
    return EXIT_OK


def register(sub: Any) -> None:
    """The parser of ``examples``."""
    e = sub.add_parser(
        "examples", help="list the examples, or copy one (its whole folder): examples copy NAME DIR"
    )
    e.add_argument("action", nargs="?", choices=["list", "copy"], default="list")
    e.add_argument("name", nargs="?")
    e.add_argument("dest", nargs="?")
    e.add_argument("--force", action="store_true", help="replace an existing copy")
    e.set_defaults(func=cmd_examples)
