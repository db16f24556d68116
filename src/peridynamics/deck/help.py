"""``peridynamics help``: the deck reference and the output contract, from the installed
package.

The reference pages (``docs/deck.md``, ``docs/output.md`` of the source tree; the
wheel carries them as ``peridynamics/_docs/``) are the pages of the documentation site.
``peridynamics help deck.material`` prints the section *material* of the deck reference
followed by the keys of the schema of this version; ``help deck.solver.adr`` one
subsection; ``help output.summary_json`` a section of the output page. Error messages
name these topics (:func:`hint`). The keys of the schema are listed by
:mod:`peridynamics.deck.reference`.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterable
from pathlib import Path

from peridynamics.deck.reference import deck_reference
from peridynamics.deck.schema import Deck

#: help topic -> page of the site
PAGES = {"deck": "deck.md", "output": "output.md"}
#: deck keys explained under a heading other than their own name
_KEY_HEADING = {
    "name": "name_and_description",
    "description": "name_and_description",
    "bodies": "several_bodies",
    "interfaces": "several_bodies",
    "rigid_bodies": "several_bodies",
    "time_function": "time_functions",
}


class HelpTopicError(KeyError):
    """An unknown help topic; the message lists the known ones."""

    def __str__(self) -> str:
        return str(self.args[0])


@functools.cache
def page_text(page: str) -> str:
    """The Markdown source of a reference page (``"deck.md"``, ``"output.md"``): the
    installed copy first, then the source tree's ``docs/``."""
    here = Path(__file__).resolve().parents[1]
    for cand in (here / "_docs" / page, here.parents[1] / "docs" / page):
        if cand.is_file():
            return cand.read_text(encoding="utf-8")
    raise FileNotFoundError(f"the reference page {page} is not installed")


def slug(heading: str) -> str:
    """A heading as a topic word: ``"type: adr"`` -> ``"type_adr"``."""
    return re.sub(r"[^a-z0-9]+", "_", heading.lower()).strip("_")


def anchor(heading: str) -> str:
    """The anchor the site gives a heading (MyST's GitHub-style slug)."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _sections(text: str, level: int) -> list[tuple[str, str]]:
    """(heading, body with the heading line) of every heading of ``level`` in ``text``,
    skipping fenced code blocks."""
    out: list[tuple[str, list[str]]] = []
    fence = False
    mark = "#" * level + " "
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            fence = not fence
        if not fence and re.match(rf"#{{1,{level}}} ", line):
            if line.startswith(mark):
                out.append((line[len(mark) :].strip(), [line]))
                continue
            out.append(("", []))  # a higher heading ends the section
            continue
        if out:
            out[-1][1].append(line)
    return [(h, "\n".join(body).rstrip() + "\n") for h, body in out if h]


def _match(word: str, heading: str) -> bool:
    s = slug(heading)
    return s == word or s.endswith("_" + word) or s.startswith(word + "_")


def topics(page: str = "deck") -> list[str]:
    """The section topics of a page: ``deck.geometry``, ``deck.material``, ..."""
    return [f"{page}.{slug(h)}" for h, _ in _sections(page_text(PAGES[page]), 2)]


def section(topic: str) -> tuple[str, str]:
    """(Markdown text, site address) of a topic: ``deck``, ``deck.material``,
    ``deck.solver.adr``, ``output.summary_json``.

    Raises
    ------
    HelpTopicError
        For an unknown topic; the message lists the topics of the page.
    """
    page, *parts = topic.split(".")
    if page not in PAGES:
        raise HelpTopicError(f"unknown help topic {topic!r}; topics: {', '.join(PAGES)}")
    text = page_text(PAGES[page])
    html = PAGES[page].replace(".md", ".html")
    if not parts:
        return text, html
    word = _KEY_HEADING.get(parts[0], parts[0]) if page == "deck" else parts[0]
    found = [(h, body) for h, body in _sections(text, 2) if _match(word, h)]
    if not found:
        known = ", ".join(topics(page))
        raise HelpTopicError(f"unknown help topic {topic!r}; topics: {known}")
    heading, body = found[0]
    if len(parts) > 1:
        subs = [(h, b) for h, b in _sections(body, 3) if _match(parts[1], h)]
        if not subs:
            known = ", ".join(f"{page}.{parts[0]}.{slug(h)}" for h, _ in _sections(body, 3))
            raise HelpTopicError(
                f"unknown help topic {topic!r}; "
                + (f"topics: {known}" if known else f"{page}.{parts[0]} has no subsections")
            )
        heading, body = subs[0]
    return body, f"{html}#{anchor(heading)}"


def help_text(topic: str) -> str:
    """What ``peridynamics help TOPIC`` prints: the section, the schema's keys of a
    deck section (this version's), and the section's address on the site."""
    body, address = section(topic)
    page, *parts = topic.split(".")
    out = [body.rstrip()]
    if page == "deck" and len(parts) == 1:
        heading = slug(body.splitlines()[0].removeprefix("## "))
        keys = [k for k in Deck.model_fields if _KEY_HEADING.get(k, k) == heading]
        if keys:
            out += ["", "Keys in this version (from the schema):", ""]
            out += [deck_reference(k) for k in keys]
    out += ["", f"On the documentation site: {address}"]
    return "\n".join(out)


def hint(paths: Iterable[str]) -> str:
    """One line naming the help topics of the deck sections in ``paths`` (key paths of
    errors), e.g. ``help: peridynamics help deck.geometry (likewise deck.solver)``; empty
    when none is known."""
    try:
        known = {t.split(".", 1)[1] for t in topics("deck")}
    except FileNotFoundError:
        return ""
    tops = dict.fromkeys(path.split(".")[0] for path in paths)  # in order, once each
    shown = [n for n in tops if _KEY_HEADING.get(n, n) in known]
    if not shown:
        return ""
    more = f" (likewise deck.{', deck.'.join(shown[1:])})" if len(shown) > 1 else ""
    return f"help: peridynamics help deck.{shown[0]}{more}"
