"""docs/deck.md against the schema: every YAML block is a valid deck or a valid section of
one, every key of every section model is named, and the defaults its tables show are the
schema's (the reference is written by hand and tested against the schemas)."""

from __future__ import annotations

import copy
import math
import re
from pathlib import Path

import pytest
import yaml

from peridynamics.deck import parse_deck

DOC = Path(__file__).resolve().parents[2] / "docs" / "deck.md"
BLOCKS = re.findall(r"```yaml\n(.*?)```", DOC.read_text(), flags=re.S)
BASE = {
    "name": "doc_block",
    "geometry": {"type": "rectangle", "size": [0.01, 0.005]},
    "discretisation": {"spacing": 5.0e-4, "horizon_factor": 3.015},
    "material": {"youngs_modulus": 70.0e9, "density": 2700.0},
    "node_sets": {
        name: {"box": {"min": [0.0, 0.0], "max": [0.01, 0.001]}}
        for name in ("top", "bottom", "left", "right", "gauge", "every_point", "loaded")
    },
    "solver": {"steps": 10},
}


def test_there_are_blocks() -> None:
    assert len(BLOCKS) > 20


@pytest.mark.parametrize("n", range(len(BLOCKS)))
def test_doc_block_is_valid(n: int) -> None:
    data = yaml.safe_load(BLOCKS[n])
    if not isinstance(data, dict) or "geometry" in data and "name" in data:
        if isinstance(data, dict) and data.get("geometry", {}).get("type") == "mesh":
            pytest.skip("mesh example needs its mesh file")
        if isinstance(data, dict):
            parse_deck(data)
        return
    deck = copy.deepcopy(BASE)
    for key, value in data.items():
        if key == "node_sets":
            deck["node_sets"].update(value)
        elif key == "geometry" and value.get("type") != "rectangle":
            deck["geometry"] = value
            dim = {"bar": 1, "box": 3, "cylinder": 3, "surface": 3}.get(
                value.get("type"), value.get("dim", 2)
            )
            lo, hi = [0.0] * dim, [1e-3] * dim
            deck["node_sets"] = {k: {"box": {"min": lo, "max": hi}} for k in deck["node_sets"]}
        elif key == "geometry" and value.get("type") == "mesh":
            pytest.skip("mesh example needs its mesh file")
        else:
            deck[key] = value
    parse_deck(deck)


# ------------------------------------------------- the reference against the schemas
def _schema_keys() -> list[tuple[str, str, object]]:
    """(key path, key, default or None) of every key of every section model of the
    deck schema, each (model, key) once."""
    from pydantic_core import PydanticUndefined

    from peridynamics.deck import Deck
    from peridynamics.deck.reference import _sub_models

    out: list[tuple[str, str, object]] = []
    seen: set[tuple[object, str]] = set()

    def walk(fields: dict, owner: object, path: str) -> None:
        for name, f in fields.items():
            key = f.alias or name
            if (owner, key) in seen:
                continue
            seen.add((owner, key))
            d = f.default
            scalar = not f.is_required() and d is not PydanticUndefined and d is not None
            scalar = scalar and isinstance(d, int | float | str | bool)
            out.append((f"{path}{key}", key, d if scalar else None))
            for sub in _sub_models(f.annotation):
                walk(sub.model_fields, sub, f"{path}{key}.")

    walk(Deck.model_fields, Deck, "")
    return out


def _table_rows() -> dict[str, list[str]]:
    """Rows of the reference's tables by the key they document (first or second cell)."""
    rows: dict[str, list[str]] = {}
    for line in DOC.read_text().splitlines():
        cells = (
            [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else []
        )
        for cell in cells[:2]:
            m = re.fullmatch(r"`(\w+)`", cell)
            if m:
                rows.setdefault(m.group(1), []).append(line)
                break
    return rows


def _values(row: str) -> set[object]:
    out: set[object] = set()
    for t in re.findall(r"`([^`]*)`", row):
        t = t.strip().strip('"').lower()
        try:
            out.add(float(t))
        except ValueError:
            out.add(t)
    return out


def test_every_key_of_the_schema_is_in_the_reference() -> None:
    text = DOC.read_text()
    missing = [
        path
        for path, key, _ in _schema_keys()
        if f"`{key}`" not in text and not re.search(rf"\b{key}:|`{key}[.:=]", text)
    ]
    assert not missing, f"keys of the schema that docs/deck.md does not name: {missing}"


def test_defaults_in_the_reference_tables_are_the_schemas() -> None:
    rows = _table_rows()
    wrong = []
    for path, key, default in _schema_keys():
        if default is None or key not in rows:
            continue
        if isinstance(default, bool | str):
            want: object = str(default).lower()
            ok = any(want in _values(r) for r in rows[key])
        else:
            ok = any(
                isinstance(v, float)
                and math.isclose(v, float(default), rel_tol=1e-3, abs_tol=0)
                or v == float(default)
                for r in rows[key]
                for v in _values(r)
            )
        if not ok:
            wrong.append(f"{path} = {default!r}")
    assert not wrong, f"defaults the tables of docs/deck.md do not show: {wrong}"
