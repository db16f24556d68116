"""``.. cli-help:: [subcommand]``: the ``--help`` text of the ``peridynamics`` command
(or one subcommand) as printed by the installed argument parser, so the command-line
reference of the site cannot drift from the code; ``.. deck-keys:: SECTION``: the keys
of one deck section with types and defaults, from the deck schema (what
``peridynamics help deck`` prints)."""

from __future__ import annotations

import argparse
from typing import Any

from docutils import nodes
from sphinx.util.docutils import SphinxDirective


def _parser() -> argparse.ArgumentParser:
    from peridynamics.cli import build_parser

    return build_parser()


def help_text(sub: str | None) -> str:
    """``peridynamics [sub] --help`` as text (80 columns)."""
    import os

    os.environ["COLUMNS"] = "88"
    p = _parser()
    if sub is None:
        return p.format_help()
    for action in p._actions:  # the subparsers action holds the subcommands
        if isinstance(action, argparse._SubParsersAction):
            return action.choices[sub].format_help()
    raise KeyError(sub)


class CliHelp(SphinxDirective):
    """The help text of ``peridynamics`` or of one subcommand, as a literal block."""

    optional_arguments = 1

    def run(self) -> list[Any]:
        sub = self.arguments[0] if self.arguments else None
        text = help_text(sub)
        block = nodes.literal_block(text, text)
        block["language"] = "text"
        return [block]


class DeckKeys(SphinxDirective):
    """The keys of one top-level deck section from the schema, as a literal block."""

    required_arguments = 1

    def run(self) -> list[Any]:
        from peridynamics.deck.reference import deck_reference

        text = deck_reference(self.arguments[0])
        block = nodes.literal_block(text, text)
        block["language"] = "text"
        return [block]


def setup(app: Any) -> dict[str, Any]:
    app.add_directive("cli-help", CliHelp)
    app.add_directive("deck-keys", DeckKeys)
    return {"parallel_read_safe": True, "version": "1"}
