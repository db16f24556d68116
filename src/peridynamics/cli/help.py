"""``peridynamics help``: the deck reference and the output page, from the installed
package (:mod:`peridynamics.deck.help`)."""

from __future__ import annotations

import argparse
from typing import Any

from peridynamics.app.checks import err
from peridynamics.app.exit_codes import EXIT_INVALID, EXIT_OK
from peridynamics.deck.help import HelpTopicError, help_text, topics
from peridynamics.deck.reference import deck_reference


def cmd_help(args: argparse.Namespace) -> int:
    """Print a section of the deck reference or of the output page, from the installed
    package, with the keys of the schema of this version (``help deck.material``); or
    every key a deck accepts (``help deck``)."""
    topic = args.topic if args.section is None else f"{args.topic}.{args.section}"
    if topic == "deck":
        print(deck_reference())
        print(
            "\nEach section with its units, allowed ranges and examples: "
            "`peridynamics help deck.SECTION`\n(sections: "
            + ", ".join(t.split(".", 1)[1] for t in topics("deck"))
            + ");\nthe outputs and summary.json: `peridynamics help output`; complete decks: "
            "`peridynamics examples copy NAME DIR`."
        )
        return EXIT_OK
    try:
        text = help_text(topic)
    except HelpTopicError as exc:
        err(str(exc))
        return EXIT_INVALID
    print(text)
    return EXIT_OK


def register(sub: Any) -> None:
    """The parser of ``help``."""
    hp = sub.add_parser(
        "help",
        help="the deck reference from the installed package: help deck.material, "
        "help deck.solver.adr, help output.summary_json; help deck lists every key",
    )
    hp.add_argument(
        "topic",
        help="deck (every key), deck.SECTION[.KIND] (a section of the deck reference with "
        "its keys), output[.SECTION] (files of a run, summary.json)",
    )
    hp.add_argument("section", nargs="?", help="a deck section (the older form: help deck solver)")
    hp.set_defaults(func=cmd_help)
