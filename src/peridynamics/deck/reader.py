"""Reading a deck: YAML as decks are read (safe, no repeated key, scientific notation
as floats), ``--set key.path=value`` overrides, validation into a :class:`Deck` with
the cross-section checks, and the files a deck names (mesh, initial fields) resolved
relative to its folder."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path
from typing import Any

import yaml
from pydantic import ValidationError

from peridynamics.deck.checks import cross_check
from peridynamics.deck.errors import DeckError, validation_errors
from peridynamics.deck.geometry import MeshGeometry
from peridynamics.deck.loading import InitialVelocityBC
from peridynamics.deck.schema import Deck


def apply_overrides(data: dict[str, Any], overrides: list[str]) -> dict[str, Any]:
    """Apply ``key.path=value`` overrides (value parsed as YAML) to a raw deck dict."""
    for item in overrides:
        if "=" not in item:
            raise DeckError([(item, "an override is key.path=value")])
        key, raw = item.split("=", 1)
        key = key.strip()
        if not key:
            raise DeckError([(item, "an override is key.path=value; the key path is empty")])
        try:
            value = yaml.load(raw, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader
        except yaml.YAMLError as exc:
            problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
            raise DeckError(
                [
                    (
                        key,
                        f"--set value {raw!r} is not valid YAML ({problem}); quote the "
                        "argument in the shell and close brackets: key=[1, 2]",
                    )
                ]
            ) from None
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


def parse_deck(data: Any, base_dir: Path | None = None) -> Deck:
    """Validate a raw mapping into a :class:`Deck`; raise :class:`DeckError`."""
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


class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses a key given twice in one mapping (YAML keeps the last)."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
        seen: dict[Any, Any] = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)  # type: ignore[no-untyped-call]
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None,
                    None,
                    f"key {key!r} appears twice in one section "
                    f"(line {seen[key] + 1} and line {key_node.start_mark.line + 1})",
                    key_node.start_mark,
                )
            seen[key] = key_node.start_mark.line
        return super().construct_mapping(node, deep=deep)


# YAML 1.1 (PyYAML) reads a float only with a dot and a signed exponent (1.0e+6):
# `1e6`, `1.0e6`, `6.02e23` or `.5e3` would be strings, and an integer key would refuse
# `steps: 1e3`. Read every number in scientific notation as a float, as YAML 1.2 does.
_UniqueKeyLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(
        r"""^(?:[-+]?[0-9][0-9_]*(?:\.[0-9_]*)?[eE][-+]?[0-9]+
            |[-+]?\.[0-9][0-9_]*[eE][-+]?[0-9]+)$""",
        re.X,
    ),
    list("-+0123456789."),
)


def yaml_load(text: str) -> Any:
    """Parse YAML as decks are read: safe, a repeated key is an error, and numbers in
    scientific notation (1e6, 1.0e6, -2.5E-3) are floats."""
    return yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader


def load_deck(path: str | Path, overrides: list[str] | None = None) -> Deck:
    """Read and validate a YAML deck file, applying ``key.path=value`` overrides."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise DeckError([("", f"cannot read deck {str(path)!r}: {exc.strerror}")]) from None
    try:
        data = yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader
    except yaml.YAMLError as exc:
        raise DeckError([("", f"not valid YAML: {exc}")]) from None
    if overrides:
        if not isinstance(data, dict):
            raise DeckError([("", "a deck is a YAML mapping")])
        data = apply_overrides(data, overrides)
    return parse_deck(data, base_dir=path.parent)
