"""Deck errors: :class:`DeckError`, and pydantic's validation errors as (key path,
message) pairs that name the key and say what is allowed."""

from __future__ import annotations

from typing import Any

from pydantic import ValidationError

from peridynamics.deck.help import hint
from peridynamics.deck.materials import MATERIAL_SCHEMAS
from peridynamics.deck.solver import SOLVER_SCHEMAS


class DeckError(ValueError):
    """An invalid deck. ``errors`` is a list of (key path, message).

    Examples
    --------
    >>> import peridynamics as pd
    >>> try:
    ...     pd.Deck.example("bar_wave_1d", {"material.density": -1.0})
    ... except pd.DeckError as exc:
    ...     print(exc.errors[0][0])
    material.density
    """

    def __init__(self, errors: list[tuple[str, str]]) -> None:
        self.errors = errors
        lines = [f"{path}: {msg}" if path else msg for path, msg in errors]
        see = hint(path for path, _ in errors)
        super().__init__("invalid deck:\n  " + "\n  ".join(lines) + (f"\n{see}" if see else ""))


def _format_loc(loc: tuple[Any, ...]) -> str:
    parts = []
    for p in loc:
        if isinstance(p, str) and p.endswith("]"):
            continue  # pydantic's union-member tags, e.g. 'function-after[...]'
        parts.append("not" if p == "not_" else str(p))
    return ".".join(parts)


_TYPE_TAGS = {
    "bar",
    "rectangle",
    "disc",
    "box",
    "cylinder",
    "mesh",
    "surface",
    "gmsh",
    "image",
    "constant",
    "ramp",
    "table",
    "triangular_pulse",
    "displacement",
    "velocity",
    "fixed",
    "initial_velocity",
    "body_force",
    "traction",
    "pressure",
}
#: tags of the callable-discriminated sections (model families, solvers)
_SECTION_TAGS = {"material": set(MATERIAL_SCHEMAS), "solver": set(SOLVER_SCHEMAS)}


def _clean_loc(loc: tuple[Any, ...]) -> tuple[Any, ...]:
    # drop discriminator tags that pydantic inserts into the location
    out = []
    for n, p in enumerate(loc):
        if n > 0 and loc[n - 1] in _SECTION_TAGS and p in _SECTION_TAGS[loc[n - 1]]:
            continue
        if isinstance(p, str) and p in _TYPE_TAGS and n > 0 and loc[n - 1] not in ("type",):
            prev = loc[n - 1]
            if isinstance(prev, int) or prev in ("geometry", "time_function"):
                continue
        out.append(p)
    return tuple(out)


_ALLOWED_TYPES = {
    "geometry": "bar, rectangle, box, cylinder, mesh, disc",
    "boundary_conditions": "displacement, velocity, fixed, initial_velocity, body_force, "
    "traction, pressure",
    "time_function": "constant, ramp, table, triangular_pulse, sine_pulse, square_pulse, blast",
    "material": ", ".join(MATERIAL_SCHEMAS),
    "solver": ", ".join(SOLVER_SCHEMAS),
}
#: the key that names the kind of a section (``type`` unless listed)
_TAG_KEY = {"material": "model"}


def _section_of(path: str) -> str:
    parts = [p for p in path.split(".") if not p.isdigit()]
    return parts[-1] if parts else ""


def named_key(msg: str) -> tuple[str | None, str]:
    """``"[key] message"`` (a validator or solver naming the offending key) -> (key,
    message); (None, msg) for a message that names none."""
    if msg.startswith("[") and "] " in msg:
        key, rest = msg[1:].split("] ", 1)
        return key, rest
    return None, msg


def validation_errors(exc: ValidationError) -> list[tuple[str, str]]:
    """(key path, message) pairs from a pydantic error."""
    out = []
    for e in exc.errors():
        path = _format_loc(_clean_loc(tuple(e["loc"])))
        msg = e["msg"]
        if e["type"] == "extra_forbidden":
            section = path.split(".")[0] if "." in path else ""
            msg = (
                "unknown key (check the spelling; `peridynamics help deck"
                f"{'.' + section if section else ''}` lists the allowed keys)"
            )
        elif e["type"] == "missing":
            msg = "required key is missing"
        elif e["type"] in ("union_tag_not_found", "union_tag_invalid"):
            kinds = _ALLOWED_TYPES.get(_section_of(path), "")
            key = _TAG_KEY.get(_section_of(path), "type")
            missing = e["type"] == "union_tag_not_found"
            msg = (f"required key '{key}' is missing" if missing else f"unknown {key}") + (
                f"; one of: {kinds}" if kinds else ""
            )
            if not missing:
                path = f"{path}.{key}" if path else key
        msg = msg.removeprefix("Value error, ")
        named, msg = named_key(msg)
        if named is not None:  # relative to the section the validator checks
            path = f"{path}.{named}" if path else named
        if "input" in e and e["type"] not in ("missing", "extra_forbidden"):
            inp = e["input"]
            if not isinstance(inp, dict | list):
                msg += f" (got {inp!r})"
        out.append((path, msg))
    return out
