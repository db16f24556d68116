"""The text of a deck and the YAML loader decks are read with.

A deck file is UTF-8 text, with or without a byte-order mark; UTF-16 and UTF-32 are read
when they start with their byte-order mark (what Windows editors write as "Unicode").
Other bytes are refused with their line, column and byte offset.

The loader (:class:`DeckLoader`) is PyYAML's safe loader with the rules of a deck: a key
given twice in one mapping is an error; numbers in scientific notation are floats (as in
YAML 1.2); integers fit in 64 bits; values nest at most :data:`MAX_DEPTH` levels and
expand (aliases included) to at most :data:`MAX_VALUES` values; a value that YAML cannot
build (``2001-02-30``, ``!!int abc``) is an error that names its key path instead of a
Python exception.
"""

from __future__ import annotations

import codecs
import re
from pathlib import Path
from typing import Any

import yaml

#: deepest nesting of lists and mappings in a deck (the schema needs fewer than 10)
MAX_DEPTH = 64
#: most values (scalars, lists and mappings, aliases expanded) in one deck or value
MAX_VALUES = 1_000_000
#: the largest deck or cases file read (bytes)
MAX_BYTES = 64 << 20
#: an integer is refused outside -2**63 <= n < 2**63 (what the solvers' arrays hold)
INT_BOUND = 2**63
#: (byte-order mark, codec, name), longest first: UTF-32 LE starts with UTF-16 LE's mark
_BOMS = (
    (codecs.BOM_UTF32_LE, "utf-32-le", "UTF-32"),
    (codecs.BOM_UTF32_BE, "utf-32-be", "UTF-32"),
    (codecs.BOM_UTF8, "utf-8", "UTF-8"),
    (codecs.BOM_UTF16_LE, "utf-16-le", "UTF-16"),
    (codecs.BOM_UTF16_BE, "utf-16-be", "UTF-16"),
)
#: a lone surrogate: a ``\\ud800`` escape, or what Python makes of a byte that is not
#: UTF-8 in a command-line argument
SURROGATE = re.compile("[\ud800-\udfff]")
_SAVE_AS = "save the file as UTF-8 (in the editor: save with encoding UTF-8)"


class TextError(ValueError):
    """Bytes that are not text of a known encoding; ``str(exc)`` says where and the fix."""


class ValueProblem(yaml.YAMLError):
    """A value YAML reads but a deck cannot hold.

    Attributes
    ----------
    path
        Key path of the value inside the document (``solver.steps``; ``""``: the
        document itself).
    message
        What is wrong and what to write instead.
    mark
        Where the value starts in the text (line and column), or ``None``.
    """

    def __init__(self, path: str, message: str, mark: Any = None) -> None:
        self.path, self.message, self.mark = path, message, mark
        super().__init__(f"{path}: {message}{where(mark)}" if path else message + where(mark))


def where(mark: Any) -> str:
    """`` (line L, column C)`` of a YAML mark (``""`` for none)."""
    if mark is None:
        return ""
    return f" (line {mark.line + 1}, column {mark.column + 1})"


def short(text: str, limit: int = 40) -> str:
    """``repr`` of ``text`` cut to about ``limit`` characters (long values in messages)."""
    if len(text) <= limit:
        return repr(text)
    return f"{text[:limit]!r}... ({len(text)} characters)"


def cut(parts: Any, keep: int = 8) -> str:
    """A key path from its parts, cut after ``keep`` parts (a deep path in a message)."""
    parts = list(parts)
    return ".".join(parts[:keep] + (["..."] if len(parts) > keep else []))


def decode(data: bytes, what: str) -> str:
    """The text of a file's bytes: UTF-8 (a byte-order mark dropped), or UTF-16/32 that
    start with their byte-order mark.

    Parameters
    ----------
    data
        The file's bytes.
    what
        The file, for messages (``deck 'x.yaml'``).

    Raises
    ------
    TextError
        Bytes that are not text of that encoding (line, column and byte offset of the
        first), or NUL bytes in UTF-8 (UTF-16 or UTF-32 without a byte-order mark).
    """
    codec, name, skip = "utf-8", "UTF-8", 0
    for bom, bom_codec, bom_name in _BOMS:
        if data.startswith(bom):
            codec, name, skip = bom_codec, bom_name, len(bom)
            break
    body = data[skip:]
    if codec == "utf-8" and b"\0" in body:
        line, col = _line_col(body[: body.index(b"\0")].decode(codec, errors="replace"))
        raise TextError(
            f"{what} holds NUL bytes (first at line {line}, column {col}): UTF-16 or UTF-32 "
            f"without a byte-order mark, or not a text file; {_SAVE_AS}"
        )
    try:
        text = body.decode(codec)
    except UnicodeDecodeError as exc:
        bad = body[exc.start : exc.end][:4].hex(" ")
        line, col = _line_col(body[: exc.start].decode(codec, errors="replace"))
        raise TextError(
            f"{what} is not {name} text: line {line}, column {col} (byte {skip + exc.start}) "
            f"holds byte(s) 0x{bad} ({exc.reason}); {_SAVE_AS}"
        ) from None
    return text


def read_text(path: Path, what: str) -> str:
    """The text of a file (:func:`decode`), read up to :data:`MAX_BYTES` (a pipe or a
    device too: ``<(...)``, ``/dev/stdin``).

    Raises
    ------
    OSError
        The file cannot be read.
    TextError
        It is larger than :data:`MAX_BYTES`, or not text (:func:`decode`).
    """
    with path.open("rb") as fh:
        raw = fh.read(MAX_BYTES + 1)
    if len(raw) > MAX_BYTES:
        raise TextError(
            f"{what} is larger than {MAX_BYTES >> 20} MiB: a deck or a cases file is a few "
            "kB of text (point data go in the files a deck names: a mesh, an initial field)"
        )
    return decode(raw, what)


def _line_col(before: str) -> tuple[int, int]:
    """Line and column (from 1) of the character after ``before``."""
    return before.count("\n") + 1, len(before) - (before.rfind("\n") + 1) + 1


def _children(node: yaml.Node) -> list[yaml.Node]:
    if isinstance(node, yaml.MappingNode):
        return [n for pair in node.value for n in pair]
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    return []


def _path_of(node: yaml.Node) -> str:
    """The key path a node was composed at, cut (:func:`cut`)."""
    return cut(p for p in getattr(node, "key_path", "").split(".") if p)


def _measure(root: yaml.Node) -> None:
    """Refuse a document whose values, aliases expanded, contain themselves, nest deeper
    than :data:`MAX_DEPTH` or number more than :data:`MAX_VALUES` (without expanding
    them: each node is visited once)."""
    size: dict[int, int] = {}
    depth: dict[int, int] = {}
    open_: set[int] = set()
    stack: list[tuple[yaml.Node, bool]] = [(root, False)]
    while stack:
        node, done = stack.pop()
        key = id(node)
        if done:
            kids = _children(node)
            size[key] = 1 + sum(size[id(k)] for k in kids)
            depth[key] = 1 + max((depth[id(k)] for k in kids), default=0)
            open_.discard(key)
            if depth[key] > MAX_DEPTH:
                msg = f"nests deeper than {MAX_DEPTH} levels (lists in lists, aliases expanded)"
                raise ValueProblem(_path_of(node), f"{msg}; check the brackets", node.start_mark)
            if size[key] > MAX_VALUES:
                msg = f"expands to more than {MAX_VALUES} values (aliases to aliases?)"
                raise ValueProblem(_path_of(node), f"{msg}; write the values out", node.start_mark)
        elif key in open_:
            raise ValueProblem(
                _path_of(node), "an alias refers to the value it is in; a deck value cannot "
                "contain itself", node.start_mark,
            )  # fmt: skip
        elif key not in size:
            open_.add(key)
            stack.append((node, True))
            stack.extend((k, False) for k in _children(node) if id(k) not in size)


class DeckLoader(yaml.SafeLoader):
    """SafeLoader with the rules of a deck (the module's docstring): each node knows its
    key path (``node.key_path``) so that a refused value names it."""

    def __init__(self, stream: Any) -> None:
        super().__init__(stream)
        self._path: list[str] = []

    def compose_node(self, parent: Any, index: Any) -> Any:
        """A node, its key path recorded; refused past :data:`MAX_DEPTH` levels."""
        if isinstance(index, yaml.ScalarNode):
            part = str(index.value)
        elif isinstance(index, int):
            part = str(index)
        else:  # the root, or a mapping key
            part = ""
        self._path.append(part)
        try:
            if len(self._path) > MAX_DEPTH + 1:
                path = cut(p for p in self._path[:-1] if p)
                raise ValueProblem(
                    path, f"nests deeper than {MAX_DEPTH} levels; check the brackets",
                    self.peek_event().start_mark,
                )  # fmt: skip
            alias = self.check_event(yaml.AliasEvent)  # type: ignore[no-untyped-call]
            node = super().compose_node(parent, index)  # type: ignore[no-untyped-call]
        finally:
            self._path.pop()
        if not alias:  # an alias's node keeps the path of its anchor
            node.key_path = ".".join(p for p in [*self._path, part] if p)
        return node

    def compose_document(self) -> Any:
        """The document's root node, measured (``_measure``)."""
        node = super().compose_document()  # type: ignore[no-untyped-call]
        if node is not None:
            _measure(node)
        return node

    def construct_object(self, node: Any, deep: bool = False) -> Any:
        """A value built from its node; what YAML cannot build, an integer past 64 bits
        or a string with a lone surrogate is a :class:`ValueProblem` naming its key."""
        path = getattr(node, "key_path", "")
        try:
            value = super().construct_object(node, deep=deep)  # type: ignore[no-untyped-call]
        except yaml.YAMLError:
            raise
        except (ValueError, TypeError, KeyError, AttributeError, OverflowError) as exc:
            text = short(str(node.value)) if isinstance(node, yaml.ScalarNode) else "the value"
            raise ValueProblem(
                path, f"YAML cannot read {text} as {node.tag.rsplit(':', 1)[-1]} "
                f"({type(exc).__name__}: {str(exc)[:80]}); check the value", node.start_mark,
            ) from None  # fmt: skip
        if isinstance(value, str) and SURROGATE.search(value):
            raise ValueProblem(
                path, f"{short(value)} holds a lone surrogate (\\ud800-\\udfff escape, or "
                "bytes that are not UTF-8 in a --set value): not text", node.start_mark,
            )  # fmt: skip
        return value

    def construct_yaml_int(self, node: Any) -> int:
        """An integer, refused outside 64 bits (before Python converts a long text)."""
        digits = str(node.value).replace("_", "").lstrip("+-")
        if len(digits) > 70:  # 64 binary digits and '0b' fit
            value = None
        else:
            value = super().construct_yaml_int(node)  # type: ignore[no-untyped-call]
        if value is None or not -INT_BOUND <= value < INT_BOUND:
            raise ValueProblem(
                getattr(node, "key_path", ""),
                f"the integer {short(str(node.value), 30)} is outside the 64-bit range "
                "(|n| < 9.2e18); write a large number as a float, e.g. 1.0e+30",
                node.start_mark,
            )
        return int(value)

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
        """A mapping; a key given twice is an error (YAML would keep the last)."""
        seen: dict[Any, Any] = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            try:
                twice = key in seen
            except TypeError:  # a list or mapping as a key: construct_mapping refuses it
                continue
            if twice:
                raise yaml.constructor.ConstructorError(
                    None,
                    None,
                    f"key {key!r} appears twice in one section "
                    f"(line {seen[key] + 1} and line {key_node.start_mark.line + 1})",
                    key_node.start_mark,
                )
            seen[key] = key_node.start_mark.line
        return super().construct_mapping(node, deep=deep)


DeckLoader.add_constructor("tag:yaml.org,2002:int", DeckLoader.construct_yaml_int)

# YAML 1.1 (PyYAML) reads a float only with a dot and a signed exponent (1.0e+6):
# `1e6`, `1.0e6`, `6.02e23` or `.5e3` would be strings, and an integer key would refuse
# `steps: 1e3`. Read every number in scientific notation as a float, as YAML 1.2 does.
DeckLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(
        r"""^(?:[-+]?[0-9][0-9_]*(?:\.[0-9_]*)?[eE][-+]?[0-9]+
            |[-+]?\.[0-9][0-9_]*[eE][-+]?[0-9]+)$""",
        re.X,
    ),
    list("-+0123456789."),
)


def yaml_load(text: str) -> Any:
    """Parse YAML as decks are read (:class:`DeckLoader`): safe, a repeated key is an
    error, numbers in scientific notation (1e6, 1.0e6, -2.5E-3) are floats, and a value
    a deck cannot hold is a :class:`ValueProblem`."""
    return yaml.load(text, Loader=DeckLoader)  # noqa: S506 - a SafeLoader
