"""Every YAML block of docs/deck.md is a valid deck or a valid section of one."""

from __future__ import annotations

import copy
import re
from pathlib import Path

import pytest
import yaml

from peridynamics.io.deck import parse_deck

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
            dim = {"bar": 1, "box": 3, "cylinder": 3}.get(value.get("type"), 2)
            lo, hi = [0.0] * dim, [1e-3] * dim
            deck["node_sets"] = {k: {"box": {"min": lo, "max": hi}} for k in deck["node_sets"]}
        elif key == "geometry" and value.get("type") == "mesh":
            pytest.skip("mesh example needs its mesh file")
        else:
            deck[key] = value
    parse_deck(deck)
