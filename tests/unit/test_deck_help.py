"""``peridynamics help deck.SECTION``: the reference pages from the installed package,
a topic for every key of the schema, and errors that name their topic."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from peridynamics.cli import main
from peridynamics.deck import Deck, DeckError, load_deck
from peridynamics.deck.help import anchor, hint, section, topics

ROOT = Path(__file__).resolve().parents[2]
BAR = ROOT / "examples" / "bar_wave_1d" / "deck.yaml"


@pytest.mark.parametrize("key", list(Deck.model_fields))
def test_every_top_level_key_has_a_help_section(key: str) -> None:
    body, address = section(f"deck.{key}")
    assert body.startswith("## ") and address.startswith("deck.html#")
    assert f"`{key}`" in body or f"## {key}" in body, key


def test_section_prints_the_page_text_and_the_schema_keys(capsys) -> None:
    assert main(["help", "deck.solver.adr"]) == 0
    out = capsys.readouterr().out
    page = (ROOT / "docs" / "deck.md").read_text()
    start = page.index("### type: adr")
    assert out.startswith(page[start : page.index("\n### ", start + 1)].rstrip())
    assert out.rstrip().endswith("On the documentation site: deck.html#type-adr")
    assert main(["help", "deck.material"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("## material") and "### model: lps" in out
    assert "Keys in this version (from the schema):" in out
    assert "youngs_modulus: number (required)" in out  # from the schema, not the page
    assert main(["help", "deck.time_function"]) == 0  # the key, the heading's topic
    assert capsys.readouterr().out.startswith("## Time functions")
    assert main(["help", "output.summary_json"]) == 0
    assert capsys.readouterr().out.startswith("## summary.json")


def test_unknown_topics_are_refused_with_the_known_ones(capsys) -> None:
    assert main(["help", "deck.materiel"]) == 2
    err = capsys.readouterr().err
    assert "unknown help topic 'deck.materiel'" in err and "deck.material" in err
    assert main(["help", "deck.solver.adrr"]) == 2
    assert "deck.solver.type_adr" in capsys.readouterr().err
    assert main(["help", "manual"]) == 2
    assert "topics: deck, output" in capsys.readouterr().err


def test_deck_errors_end_with_the_help_topics_of_their_sections() -> None:
    with pytest.raises(DeckError) as info:
        load_deck(BAR, ["geometry.thikness=1", "solver.safety_factor=-1"])
    last = str(info.value).splitlines()[-1]
    assert last == "help: peridynamics help deck.geometry (likewise deck.solver)"
    assert hint(["boundary_conditions.0.set"]) == "help: peridynamics help deck.boundary_conditions"
    assert hint(["nosuch.key", ""]) == ""


def test_anchors_follow_the_heading_slugs() -> None:
    assert anchor("type: adr") == "type-adr"
    assert anchor("bar (1-D)") == "bar-1-d"
    assert anchor("Command line: check, run and `--set`") == "command-line-check-run-and---set"
    assert "deck.several_bodies" in topics("deck")


def test_the_wheel_carries_the_pages_help_prints() -> None:
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())
    forced = cfg["tool"]["hatch"]["build"]["targets"]["wheel"]["force-include"]
    for page in ("deck.md", "output.md"):
        assert forced[f"docs/{page}"] == f"peridynamics/_docs/{page}"
        assert (ROOT / "docs" / page).is_file()


def test_help_of_the_command_line_names_the_reference_topics() -> None:
    from peridynamics.cli import build_parser

    parser = build_parser()
    assert "peridynamics help deck.SECTION" in parser.format_help()
    sub = parser._subparsers._group_actions[0].choices  # type: ignore[union-attr]
    assert "peridynamics help deck.SECTION" in sub["run"].format_help()
    assert "peridynamics help" in " ".join(sub["check"].format_help().split())


def test_the_sites_key_page_has_every_section_of_the_schema() -> None:
    page = (ROOT / "docs" / "deck_keys.md").read_text()
    for key in Deck.model_fields:
        assert f"## {key}\n" in page and f"```{{deck-keys}} {key}\n" in page, key
