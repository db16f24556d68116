"""What the fuzzer knows of the deck's schema (``Deck.model_json_schema()``): each
model's keys, the values a key is documented with (its constants, choices, default and
the edges of its range), and a skeleton of each model (its required keys filled in) to
graft a new section of any kind into a deck."""

from __future__ import annotations

import functools
import math
from typing import Any

from peridynamics.deck import Deck

#: a key's edge values just inside and outside its range
_EPS = 1e-9


@functools.cache
def schema() -> dict[str, Any]:
    """The deck's JSON schema (pydantic)."""
    return Deck.model_json_schema()


def _defs() -> dict[str, Any]:
    return dict(schema()["$defs"]) | {"Deck": schema()}


def _members(prop: dict[str, Any]) -> list[dict[str, Any]]:
    """A property's schema and the members of its unions, arrays and references."""
    out, todo = [], [prop]
    while todo:
        p = todo.pop()
        out.append(p)
        for key in ("anyOf", "oneOf", "allOf"):
            todo.extend(p.get(key, []))
        if isinstance(p.get("items"), dict):
            todo.append(p["items"])
        if isinstance(p.get("additionalProperties"), dict):
            todo.append(p["additionalProperties"])
    return out


def _edges(p: dict[str, Any]) -> list[Any]:
    """The edges of a number's range: each bound, and just inside and outside it."""
    out: list[Any] = []
    for key in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
        if key in p:
            b = p[key]
            out += [b, b - _EPS * max(1.0, abs(b)), b + _EPS * max(1.0, abs(b))]
            if p.get("type") == "integer":
                out += [int(b) - 1, int(b) + 1]
    return out


@functools.cache
def key_values() -> dict[str, tuple[Any, ...]]:
    """Key name -> the values the schema documents for it (any model)."""
    found: dict[str, list[Any]] = {}
    for model in _defs().values():
        for key, prop in model.get("properties", {}).items():
            vals = found.setdefault(key, [])
            for p in _members(prop):
                vals += [p["const"]] if "const" in p else []
                vals += list(p.get("enum", []))
                vals += _edges(p)
                if "default" in p and p["default"] not in ([], {}, None):
                    vals.append(p["default"])
    return {k: tuple(_unique(v)) for k, v in found.items() if v}


def _unique(vals: list[Any]) -> list[Any]:
    out: list[Any] = []
    for v in vals:
        if not any(type(v) is type(o) and repr(v) == repr(o) for o in out):
            out.append(v)
    return out


@functools.cache
def model_keys() -> tuple[frozenset[str], ...]:
    """The keys of each model of the schema."""
    return tuple(frozenset(m.get("properties", {})) for m in _defs().values())


def keys_for(mapping: dict[str, Any]) -> list[str]:
    """Keys a mapping of the deck may take: those of every model that has all its
    present keys (every key of the schema when none has)."""
    have = {k for k in mapping if isinstance(k, str)}
    fits = [keys for keys in model_keys() if have <= keys]
    pool = set().union(*fits) if fits else set().union(*model_keys())
    return sorted(pool - have) or sorted(pool)


def _sample(prop: dict[str, Any], depth: int) -> Any:
    """A plausible value of a property (its constant, first choice, default, a number
    inside its range, a model's skeleton)."""
    for p in _members(prop):
        if "const" in p:
            return p["const"]
        if p.get("enum"):
            return p["enum"][0]
    if "default" in prop and prop["default"] is not None:
        return prop["default"]
    for p in _members(prop):
        if "$ref" in p and depth < 4:
            return skeleton(p["$ref"].rsplit("/", 1)[-1], depth + 1)
        kind = p.get("type")
        if kind in ("number", "integer"):
            low = p.get("minimum", p.get("exclusiveMinimum", 0))
            value = low + 1 if math.isfinite(low) else 1
            return int(value) if kind == "integer" else float(value)
        if kind == "array":
            item = _sample(p.get("items", {}), depth + 1) if "items" in p else 0.0
            return [item] * max(int(p.get("minItems", 2)), 1)
        if kind == "string":
            return "x"
        if kind == "boolean":
            return True
        if kind == "object":
            return {}
    return None


def skeleton(name: str, depth: int = 0) -> dict[str, Any]:
    """A mapping of model ``name`` with its required keys filled in."""
    model = _defs()[name]
    props = model.get("properties", {})
    return {k: _sample(props[k], depth) for k in model.get("required", []) if k in props}


@functools.cache
def model_names() -> tuple[str, ...]:
    """The names of the schema's models (``Deck`` excluded)."""
    return tuple(sorted(schema()["$defs"]))


@functools.cache
def section_names() -> tuple[str, ...]:
    """The top-level keys of a deck."""
    return tuple(schema()["properties"])
