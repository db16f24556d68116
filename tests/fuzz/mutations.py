"""Hypothesis strategies of hostile decks: small copies of the examples (the bases)
changed at one to three places (a value replaced by a hostile one, a key deleted, a key
of the schema added, a section of another kind or of another example grafted, a node
wrapped in a list or a mapping, raw YAML text that Python cannot dump), and byte-level
damage of a deck file (flips, insertions, deletions, truncation, control characters,
byte-order marks and other encodings)."""

from __future__ import annotations

import codecs
import copy
import functools
import math
from typing import Any

import yaml
from hypothesis import strategies as st

from tests.fuzz import schema_values as sv
from tests.helpers import EXAMPLES

#: example decks (under examples/) and the overrides that make each small (<= about
#: 1000 points, a check --bonds in well under a second)
BASES: dict[str, dict[str, Any]] = {
    "bar_wave_1d/deck.yaml": {"discretisation.spacing": 0.01},
    "research/notched_plate.yaml": {"discretisation.spacing": 2e-3},
    "rock_compression/flaw45.yaml": {"discretisation.spacing": 2.5e-3},
    "bodies/striker_plate.yaml": {"discretisation.spacing": 2e-3},
    "bodies/brazilian_disc.yaml": {"discretisation.spacing": 2.5e-3},
    "bodies/three_point_bend_softening.yaml": {"discretisation.spacing": 5e-3},
    "bodies/inclusions.yaml": {"discretisation.spacing": 2e-3},
    "correspondence/plate_hole_damage.yaml": {"discretisation.spacing": 2.5e-3},
    "lps/plate_hole.yaml": {"discretisation.spacing": 2.5e-3},
    "micropolar/cantilever.yaml": {"discretisation.spacing": 0.02},
    "static_fracture/notched_plate_adr.yaml": {},
    "spalling/table1_case1.yaml": {"discretisation.spacing": 0.005},
    "spalling/test_bar_fdm_pd3.yaml": {},
    "waves/blast_bar_1kg.yaml": {"discretisation.spacing": 0.005},
    "waves/ring_blast.yaml": {"discretisation.spacing": 0.02},
    "plate_tension_2d/adr.yaml": {"discretisation.spacing": 2e-3},
    "crack_branching_2d/deck.yaml": {
        "discretisation.spacing": 2e-3,
        "discretisation.horizon": 6e-3,
    },
    "kalthoff_winkler/deck.yaml": {"discretisation.spacing": 5e-3},
}
#: YAML text a mutation puts in place of a value (what yaml.safe_dump cannot write)
RAW = (
    "9" * 5000,
    "-" + "9" * 30,
    "0x" + "f" * 300,
    "0b" + "1" * 80,
    "1:2:3:4:5:6:7:8:9:10:11:12:13:14",
    "[" * 5000 + "]" * 5000,
    "{a: " * 200 + "1" + "}" * 200,
    "1e99999",
    "-1e99999",
    ".nan",
    ".inf",
    "2001-02-30",
    "2001-12-14t21:59:43.10-05:00",
    "!!int abc",
    "!!float x",
    "!!timestamp x",
    "!!bool maybe",
    "!!binary AAAA",
    "!!set {a, b}",
    "!!omap [a]",
    "!!python/object/apply:os.system [echo]",
    "!custom 1",
    "&x [*x]",
    "*undefined",
    '"\\ud800"',
    '"\\0"',
    '"\\x1b[31m"',
    "'unclosed",
    "[1, 2",
    "~",
    "0o17",
    "017",
    "1_000",
    "+.5",
)
#: the placeholder of a raw text in the dumped deck (a plain scalar YAML keeps as is)
PLACEHOLDER = "fuzzrawvalue{}zz"


@functools.cache
def _base(name: str) -> dict[str, Any]:
    data = yaml.safe_load((EXAMPLES / name).read_text(encoding="utf-8"))
    for key, value in BASES[name].items():
        node = data
        *parts, last = key.split(".")
        for part in parts:
            node = node.setdefault(part, {})
        node[last] = value
    return data


def base(name: str) -> dict[str, Any]:
    """A fresh copy of base deck ``name`` (a key of :data:`BASES`)."""
    return copy.deepcopy(_base(name))


def dump(data: Any, raws: list[str]) -> str:
    """YAML text of ``data`` with each placeholder replaced by its raw text."""
    text = yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=1 << 30)
    for n, raw in enumerate(raws):
        text = text.replace(PLACEHOLDER.format(n), raw)
    return text


def nodes(data: Any, path: tuple[Any, ...] = ()) -> list[tuple[tuple[Any, ...], Any]]:
    """(path, node) of every node below the root, depth first."""
    out: list[tuple[tuple[Any, ...], Any]] = []
    if isinstance(data, dict):
        items: Any = data.items()
    else:
        items = enumerate(data) if isinstance(data, list) else []
    for key, value in items:
        out.append(((*path, key), value))
        out += nodes(value, (*path, key))
    return out


def _parent(data: Any, path: tuple[Any, ...]) -> Any:
    for key in path[:-1]:
        data = data[key]
    return data


_NUMBERS = (
    *(0, -1, 1, 0.0, -0.0, math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, 1e-300),
    *(2**63 - 1, -(2**63), 2**63, 2**31, 10**30, 1e30, 1e-30, True, False, None),
)
_STRINGS = (
    *("", " ", "x" * 5000, "ünïcödé", "名前", "\u202e", "a/b", "../..", "all", "-1", "1e3"),
    *("nan", "none", "\t", "\x00", "\x1b[2J", "a\nb", "${HOME}", "*", "CON"),
    *("x / 0", "1e300 * 1e300", "sqrt(-1)", "9**9**9", "__import__('os')", "x * 1e99"),
)


def plausible(orig: Any, key: Any) -> st.SearchStrategy[Any]:
    """A replacement of ``orig`` of its own kind: a number scaled or its sign flipped,
    each number of a list scaled, a value the schema documents for ``key``."""
    options: list[st.SearchStrategy[Any]] = []
    if isinstance(key, str) and key in sv.key_values():
        options.append(st.sampled_from(sv.key_values()[key]))
    scales = st.sampled_from(
        (-1, 0, 1e-300, 1e-12, 1e-6, 1e-3, 0.5, 0.99, 1.01, 2, 10, 1e3, 1e6, 1e50, 1e300)
    )
    if isinstance(orig, int | float) and not isinstance(orig, bool):
        options.append(scales.map(lambda s: _scaled(orig, s)))
    if isinstance(orig, list) and orig and all(_is_number(v) for v in orig):
        options.append(st.tuples(st.integers(0, len(orig) - 1), scales).map(
            lambda ns: [v * ns[1] if i == ns[0] else v for i, v in enumerate(orig)]))  # fmt: skip
    if isinstance(orig, list) and orig:
        options.append(st.sampled_from([orig + orig[-1:], orig[:-1], orig[::-1], orig * 10]))
    if isinstance(orig, str):
        options.append(st.sampled_from([orig.upper(), orig + "x", orig * 100, f" {orig}"]))
    return st.one_of(options) if options else hostile(orig, key)


def _scaled(v: float, s: float) -> float:
    """``v * s``, an integer kept an integer where the product is finite."""
    return type(v)(v * s) if math.isfinite(v * s) else v * s


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def hostile(orig: Any, key: Any) -> st.SearchStrategy[Any]:
    """A hostile replacement of value ``orig`` at key ``key``: any type, any size."""
    return st.one_of(
        st.sampled_from(_NUMBERS),
        st.sampled_from(_STRINGS),
        st.text(max_size=12),
        st.floats(allow_nan=True, allow_infinity=True),
        st.integers(min_value=-(2**70), max_value=2**70),
        st.sampled_from(([], {}, [[]], [1, 2, 3, 4], [math.nan], [orig], {"type": "x"})),
        st.sampled_from(([orig], {"value": orig}, [orig, orig])),
    )


def value_for(orig: Any, key: Any) -> st.SearchStrategy[Any]:
    """A replacement: of its own kind (:func:`plausible`) two times in three, else any
    (:func:`hostile`)."""
    return st.one_of(plausible(orig, key), plausible(orig, key), hostile(orig, key))


_OPS = ("leaf", "leaf", "replace", "replace", "delete", "insert", "insert", "graft", "wrap", "raw")


@st.composite
def mutated_deck(
    draw: st.DrawFn,
    bases: tuple[str, ...] = tuple(BASES),
    ops: tuple[str, ...] = _OPS,
    fixed: dict[str, Any] | None = None,
) -> tuple[str, str]:
    """(base name, deck text): a base deck changed at one to three places by ``ops``,
    then the dotted keys of ``fixed`` set where their sections are still mappings."""
    name = draw(st.sampled_from(bases))
    data, raws = base(name), []
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(ops))
        if op == "graft":
            _graft(draw, data)
            continue
        found = nodes(data)
        if op == "leaf":  # a number, a list of numbers or a string: of its own kind
            found = [(p, n) for p, n in found if not isinstance(n, dict)
                     and not (isinstance(n, list) and not all(map(_is_number, n)))]  # fmt: skip
        path, node = draw(st.sampled_from(found)) if found else ((), data)
        parent = _parent(data, path) if path else None
        if op == "leaf" and path:
            parent[path[-1]] = _fresh(draw(plausible(node, path[-1])))
        elif op == "replace" and path:
            parent[path[-1]] = _fresh(draw(value_for(node, path[-1])))
        elif op == "delete" and path:
            del parent[path[-1]]
        elif op == "insert":
            target = node if isinstance(node, dict) else data
            key = draw(st.sampled_from(sv.keys_for(target) + ["unknown_key", "", "Name"]))
            target[key] = _fresh(draw(value_for(target.get(key), key)))
        elif op == "wrap" and path:
            parent[path[-1]] = _fresh(
                draw(st.sampled_from([[node], {"value": node}, [node, node]]))
            )
        elif op == "raw" and path:
            parent[path[-1]] = PLACEHOLDER.format(len(raws))
            raws.append(draw(st.sampled_from(RAW)))
    for key, value in (fixed or {}).items():
        *parts, last = key.split(".")
        node = data
        for part in parts:
            node = node.get(part) if isinstance(node, dict) else None
        if isinstance(node, dict):
            node[last] = value
    return name, dump(data, raws)


def _fresh(value: Any) -> Any:
    """A deep copy of a drawn value: a value shared with the schema's cached defaults
    (or with another node of the deck) and changed in place by a later mutation would
    change what the next example draws (hypothesis's ``FlakyStrategyDefinition``)."""
    return copy.deepcopy(value)


def _graft(draw: st.DrawFn, data: dict[str, Any]) -> None:
    """Put a section of another example, or a skeleton of a schema model, into the
    deck: at the top level, as a list item, or in place of a node."""
    if draw(st.booleans()):
        donor = base(draw(st.sampled_from(tuple(BASES))))
        key = draw(st.sampled_from(sorted(donor)))
        value = donor[key]
        if isinstance(value, list) and value and isinstance(data.get(key), list):
            data[key].append(_fresh(draw(st.sampled_from(value))))
        else:
            data[key] = value
        return
    piece = _fresh(sv.skeleton(draw(st.sampled_from(sv.model_names()))))
    found = [(p, n) for p, n in nodes(data) if isinstance(n, dict | list)]
    if not found:
        data[draw(st.sampled_from(sv.section_names()))] = piece
        return
    path, node = draw(st.sampled_from(found))
    if isinstance(node, list):
        node.append(piece)
    else:
        _parent(data, path)[path[-1]] = piece


# ---------------------------------------------------------------- bytes of a deck
_BOMS = (codecs.BOM_UTF8, codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE, codecs.BOM_UTF32_LE,
         codecs.BOM_UTF32_BE)  # fmt: skip
_CODECS = ("utf-16", "utf-16-le", "utf-16-be", "utf-32", "utf-8-sig", "latin-1", "cp1252")
_CONTROL = tuple(bytes([c]) for c in (*range(0, 9), 11, 12, *range(14, 32), 127)) + (
    b"\r", b"\r\n", b"\t", b"\xc2\x85", b"\xe2\x80\xa8", b"\xef\xbb\xbf", b"\xed\xa0\x80",
)  # fmt: skip


@st.composite
def damaged_bytes(draw: st.DrawFn, bases: tuple[str, ...] = tuple(BASES)) -> tuple[str, bytes]:
    """(base name, deck bytes): a base deck's text damaged at one to three places."""
    name = draw(st.sampled_from(bases))
    text = dump(base(name), [])
    if draw(st.integers(0, 9)) == 0:  # another encoding of the text, with or without BOM
        enc = draw(st.sampled_from(_CODECS))
        data = text.replace("é", "é").encode(enc, errors="replace")
    else:
        data = text.encode()
    for _ in range(draw(st.integers(1, 3))):
        data = _damage(draw, data)
    return name, data


def _damage(draw: st.DrawFn, data: bytes) -> bytes:
    pos = draw(st.integers(0, len(data)))
    op = draw(st.sampled_from(("flip", "insert", "delete", "truncate", "control", "bom",
                               "line", "indent")))  # fmt: skip
    if op == "flip" and pos < len(data):
        bit = 1 << draw(st.integers(0, 7))
        return data[:pos] + bytes([data[pos] ^ bit]) + data[pos + 1 :]
    if op == "insert":
        return data[:pos] + draw(st.binary(min_size=1, max_size=8)) + data[pos:]
    if op == "delete":
        return data[:pos] + data[pos + draw(st.integers(1, 64)) :]
    if op == "truncate":
        return data[:pos]
    if op == "control":
        return data[:pos] + draw(st.sampled_from(_CONTROL)) + data[pos:]
    if op == "bom":
        return draw(st.sampled_from(_BOMS)) + data
    lines = data.split(b"\n")
    n = draw(st.integers(0, len(lines) - 1))
    if op == "line":  # a line repeated, or moved
        lines.insert(draw(st.integers(0, len(lines))), lines[n])
    else:  # an indentation changed
        lines[n] = draw(st.sampled_from((b" ", b"  ", b"\t", b""))) + lines[n].lstrip(b" ")
    return b"\n".join(lines)
