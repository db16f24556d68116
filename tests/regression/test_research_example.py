"""The research-outputs example ``examples/research/notched_plate.yaml`` at a coarser
grid: a derived crack-mouth opening, events and their frames, history.csv, several
figures and the broken-bond crack length, all from one run with the deck's own output
settings (the gallery test ``test_gallery_research.py`` re-analyses the same run)."""

from __future__ import annotations

import csv
import json
from collections.abc import Callable
from pathlib import Path

import meshio
import numpy as np
import pytest

from tests.helpers import EXAMPLES, RESEARCH

pytestmark = pytest.mark.long  # the research run (CI: pytest -m long)

DECK = EXAMPLES / "research" / "notched_plate.yaml"


@pytest.fixture(scope="module")
def run(example_run: Callable[..., Path]) -> tuple[Path, dict]:
    """The session's shared run (``tests/conftest.py``; the gallery test reads it too)."""
    out = example_run("research", DECK.name, *RESEARCH)
    return out, json.loads((out / "summary.json").read_text())


def test_events_happen_in_order_and_write_their_frames(run) -> None:
    out, summary = run
    ev = summary["results"]["events"]
    assert ev["first_damage"]["step"] <= ev["fracture"]["step"]
    assert 0 < ev["peak_load"]["time_s"] < summary["results"]["final_time_s"]
    for name in ("first_damage", "fracture", "peak_load"):
        frame = meshio.read(out / ev[name]["file"])
        assert set(frame.point_data) == {"displacement", "damage"}  # output.fields only
        assert frame.points.dtype == np.float32


def test_the_crack_mouth_opens_and_history_csv_holds_it(run) -> None:
    out, summary = run
    with open(out / "history.csv") as fh:
        rows = list(csv.reader(fh))
    header, body = rows[0], np.array(rows[1:], dtype=float)
    cmod = body[:, header.index("cmod [m]")]
    top, bottom = body[:, header.index("mouth_top [m]")], body[:, header.index("mouth_bottom [m]")]
    assert np.array_equal(cmod, top - bottom)
    assert cmod[-1] > 0 and cmod[-1] == cmod.max()


def test_the_crack_runs_from_the_notch_and_is_measured_by_broken_bonds(run) -> None:
    out, summary = run
    r = summary["results"]
    path = r["crack_paths"]["crack"]["length_m"]
    assert path > 0.005  # it grew at least 5 mm from the notch tip
    assert r["crack_length_m"] > 0
    for kind in ("damage", "deformed", "probes", "energies"):
        assert (out / f"notched_plate_{kind}.png").exists()
    frames = sorted(p.stem for p in out.glob("frame_*.vtu"))
    assert sorted(p.stem for p in (out / "png").glob("*.png")) == frames
