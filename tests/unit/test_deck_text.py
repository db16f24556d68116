"""The text of a deck and the YAML rules of a deck (:mod:`peridynamics.deck.yaml_source`):
encodings, integers past 64 bits, nesting, aliases, values YAML cannot build. The
command-line outcomes are in ``tests/hostile/cases_decks.yaml``."""

from __future__ import annotations

import codecs

import pytest

from peridynamics.deck.yaml_source import (
    MAX_DEPTH,
    TextError,
    ValueProblem,
    decode,
    yaml_load,
)

TEXT = "name: bar\nvalues: [1, 2.5e3]\nnote: café\n"


@pytest.mark.parametrize(
    ("bom", "codec"),
    [
        (b"", "utf-8"),
        (codecs.BOM_UTF8, "utf-8"),
        (codecs.BOM_UTF16_LE, "utf-16-le"),
        (codecs.BOM_UTF16_BE, "utf-16-be"),
        (codecs.BOM_UTF32_LE, "utf-32-le"),
        (codecs.BOM_UTF32_BE, "utf-32-be"),
    ],
)
def test_utf8_and_text_with_a_byte_order_mark_are_read(bom: bytes, codec: str) -> None:
    assert decode(bom + TEXT.encode(codec), "deck") == TEXT


def test_other_bytes_are_refused_with_their_place() -> None:
    with pytest.raises(TextError) as info:
        decode(TEXT.encode("latin-1"), "deck 'x.yaml'")
    msg = str(info.value)
    assert "not UTF-8 text: line 3, column 10 (byte 38)" in msg and "0xe9" in msg
    with pytest.raises(TextError, match="NUL bytes .*line 1, column 2"):
        decode(TEXT.encode("utf-16-le"), "deck")  # UTF-16 without its mark


@pytest.mark.parametrize(
    ("text", "path", "fragment"),
    [
        ("a:\n  b: " + "9" * 5000, "a.b", "64-bit"),
        ("a: 0x" + "f" * 17, "a", "64-bit"),
        ("a: [" + "[" * MAX_DEPTH + "]" * MAX_DEPTH + "]", "a.0.0.0.0.0.0.0....", "deeper"),
        ("a: &x [1, *x]", "a", "contain itself"),
        ("a: [1, 2001-02-30]", "a.1", "cannot read '2001-02-30' as timestamp"),
        ("a: !!int abc", "a", "cannot read 'abc' as int"),
        ('a: {b: "\\udc80"}', "a.b", "lone surrogate"),
    ],
)
def test_values_a_deck_cannot_hold_name_their_key(text: str, path: str, fragment: str) -> None:
    with pytest.raises(ValueProblem) as info:
        yaml_load(text)
    assert info.value.path == path and fragment in info.value.message


def test_the_limits_keep_what_decks_use() -> None:
    assert yaml_load("a: 9223372036854775807") == {"a": 2**63 - 1}
    assert yaml_load("a: " + "[" * (MAX_DEPTH - 1) + "]" * (MAX_DEPTH - 1)) is not None
    assert yaml_load("m: &m {E: 1.0e9}\nn: *m\nk: [*m, *m]") == {
        "m": {"E": 1e9},
        "n": {"E": 1e9},
        "k": [{"E": 1e9}, {"E": 1e9}],
    }
