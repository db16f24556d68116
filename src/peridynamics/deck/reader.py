"""Reading a deck: YAML as decks are read (safe, no repeated key, scientific notation
as floats), ``--set key.path=value`` overrides, validation into a
:class:`~peridynamics.deck.schema.Deck` with the cross-section checks, and the files a
deck names (mesh, initial fields) resolved relative to its folder."""

from __future__ import annotations

import contextlib
import io
from pathlib import Path
from typing import Any

import yaml
from pydantic import ValidationError

from peridynamics.deck.checks import cross_check
from peridynamics.deck.errors import DeckError, validation_errors
from peridynamics.deck.geometry import MeshGeometry
from peridynamics.deck.geometry_files import resolve_geometry_files
from peridynamics.deck.loading import InitialVelocityBC
from peridynamics.deck.schema import Deck
from peridynamics.deck.yaml_source import (
    MAX_DEPTH,
    SURROGATE,
    TextError,
    ValueProblem,
    cut,
    read_text,
    short,
    where,
    yaml_load,
)


def apply_overrides(data: dict[str, Any], overrides: list[str]) -> dict[str, Any]:
    """Apply ``key.path=value`` overrides (value parsed as YAML) to a raw deck dict."""
    for item in overrides:
        if "=" not in item:
            raise DeckError([(item, "an override is key.path=value")])
        key, raw = item.split("=", 1)
        key = key.strip()
        if not key:
            raise DeckError([(item, "an override is key.path=value; the key path is empty")])
        if SURROGATE.search(item):
            what = "key path" if SURROGATE.search(key) else "value"
            raise DeckError(
                [
                    (
                        ascii(key) if what == "key path" else key,
                        f"the --set {what} holds bytes that are not UTF-8 text; type it in UTF-8",
                    )
                ]
            )
        if key.count(".") >= MAX_DEPTH:
            raise DeckError([(cut(key.split(".")), f"more than {MAX_DEPTH} parts in a key path")])
        value = _override_value(key, raw)
        node: Any = data
        parts = key.split(".")
        for n, part in enumerate(parts):
            last = n == len(parts) - 1
            if isinstance(node, list):
                try:
                    idx = int(part)
                    if idx < 0:
                        raise IndexError
                    node[idx]  # noqa: B018 - existence check
                except (ValueError, IndexError):
                    raise DeckError(
                        [(key, f"no list item {part!r} (indices start at 0)")]
                    ) from None
                if last:
                    node[idx] = value
                else:
                    node = node[idx]
            else:
                if not isinstance(node, dict):
                    raise DeckError([(key, f"{'.'.join(parts[:n])} is not a section")])
                if last:
                    node[part] = value
                else:
                    node = node.setdefault(part, {})
    return data


def _override_value(key: str, raw: str) -> Any:
    """The value of ``--set key=raw`` (YAML, read as a deck's values are)."""
    try:
        return yaml_load(raw)
    except ValueProblem as exc:
        path = f"{key}.{exc.path}" if exc.path else key
        raise DeckError([(path, f"--set value: {exc.message}")]) from None
    except yaml.YAMLError as exc:
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise DeckError(
            [
                (
                    key,
                    f"--set value {short(raw)} is not valid YAML ({problem}); quote the "
                    "argument in the shell and close brackets: key=[1, 2]",
                )
            ]
        ) from None


def parse_deck(data: Any, base_dir: Path | None = None) -> Deck:
    """Validate a raw mapping into a :class:`~peridynamics.deck.schema.Deck`; raise
    :class:`DeckError`."""
    if not isinstance(data, dict):
        raise DeckError([("", "a deck is a YAML mapping of sections (name, geometry, ...)")])
    try:
        deck = Deck.model_validate(data)
    except ValidationError as exc:
        raise DeckError(validation_errors(exc)) from None
    if isinstance(deck.geometry, MeshGeometry) and (
        base_dir is not None or deck.geometry.dim is None
    ):  # without base_dir and with dim given, the file is not looked up
        deck = _resolve_mesh(deck, base_dir or Path.cwd())
    deck = resolve_geometry_files(deck, base_dir)
    deck = _resolve_field_files(deck, base_dir or Path.cwd())
    errors = cross_check(deck)
    if errors:
        raise DeckError(errors)
    return deck


def _resolve_mesh(deck: Deck, base_dir: Path) -> Deck:
    """Make the mesh path absolute and fill ``dim`` from the mesh's cells if omitted."""
    import meshio

    g = deck.geometry
    assert isinstance(g, MeshGeometry)
    path = Path(g.file)
    if not path.is_absolute():
        path = base_dir / path
    if not path.exists():
        raise DeckError([("geometry.file", f"mesh file {str(path)!r} does not exist")])
    update: dict[str, Any] = {"file": str(path)}
    if g.dim is None:
        said = io.StringIO()  # meshio prints its reason and then raises SystemExit(1)
        try:
            with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said):
                kinds = {blk.type for blk in meshio.read(path).cells}
        except (Exception, SystemExit) as exc:
            reason = " ".join(said.getvalue().split()).removeprefix("Error: ")
            if not isinstance(exc, SystemExit) and str(exc):
                reason = f"{reason}; {exc}" if reason else str(exc)
            detail = f": {reason}" if reason else " (not a mesh format meshio recognises)"
            raise DeckError(
                [("geometry.file", f"meshio cannot read {str(path)!r}{detail}")]
            ) from None
        update["dim"] = 3 if kinds & {"tetra", "hexahedron"} else 2
    return deck.model_copy(update={"geometry": g.model_copy(update=update)})


def _resolve_field_files(deck: Deck, base_dir: Path) -> Deck:
    """Make the ``file`` of initial fields absolute (relative to the deck's folder) and
    check that it exists; its rows are checked against the node set when it is built."""
    bcs = list(deck.boundary_conditions)
    errors = []
    for n, spec in enumerate(bcs):
        if isinstance(spec, InitialVelocityBC) and spec.file is not None:
            path = Path(spec.file)
            if not path.is_absolute():
                path = base_dir / path
            if not path.is_file():
                errors.append((f"boundary_conditions.{n}.file", f"no file {str(path)!r}"))
            bcs[n] = spec.model_copy(update={"file": str(path)})
    if errors:
        raise DeckError(errors)
    return deck.model_copy(update={"boundary_conditions": bcs})


def load_deck(path: str | Path, overrides: list[str] | None = None) -> Deck:
    """Read and validate a YAML deck file, applying ``key.path=value`` overrides."""
    path = Path(path)
    try:
        text = read_text(path, f"deck {str(path)!r}")
        data = yaml_load(text)
    except OSError as exc:
        raise DeckError([("", f"cannot read deck {str(path)!r}: {exc.strerror}")]) from None
    except TextError as exc:
        raise DeckError([("", str(exc))]) from None
    except ValueProblem as exc:
        raise DeckError([(exc.path, exc.message + where(exc.mark))]) from None
    except yaml.YAMLError as exc:
        raise DeckError([("", f"not valid YAML: {_yaml_message(exc, text, path)}")]) from None
    if overrides:
        if not isinstance(data, dict):
            raise DeckError([("", "a deck is a YAML mapping")])
        data = apply_overrides(data, overrides)
    return parse_deck(data, base_dir=path.parent)


def _yaml_message(exc: yaml.YAMLError, text: str, path: Path) -> str:
    """PyYAML's message, with the file's name and a refused character's line."""
    if isinstance(exc, yaml.reader.ReaderError) and isinstance(exc.character, int):
        before = text[: exc.position]
        line = before.count("\n") + 1
        col = len(before) - (before.rfind("\n") + 1) + 1
        return (
            f"character U+{exc.character:04X} at line {line}, column {col} is not allowed "
            "in YAML (a control character); delete it, or write it as an escape in a "
            'double-quoted string ("\\x07")'
        )
    return str(exc).replace('"<unicode string>"', repr(str(path)))
