"""The figure script of the research example (``examples/research/make_figures.py``) at
the coarse grid of ``test_research_example.py`` (1000 points), re-analysing that test's
run (``--no-run`` on a copy of the session's shared run, ``tests/conftest.py``): the
load-CMOD numbers, the energy balance and the figure the script adds."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.helpers import EXAMPLES, RESEARCH, load_script

pytestmark = pytest.mark.long  # the research run and its figures (CI: pytest -m long)

SCRIPT = EXAMPLES / "research" / "make_figures.py"


def test_make_figures_small(tmp_path: Path, example_run: Callable[..., Path]) -> None:
    mod = load_script(SCRIPT, "research_figures")
    run = example_run("research", "notched_plate.yaml", *RESEARCH)  # test_research_example's
    out = shutil.copytree(run, tmp_path / "run")
    sets = [a for s in RESEARCH for a in ("--set", s)]
    assert mod.main(["--out", str(out), "--no-run", *sets]) == 0
    res = json.loads((out / "notched_plate.json").read_text())
    assert (out / "notched_plate.png").stat().st_size > 1000
    # measured at this grid with 0.3.0's Lanczos step (136 steps of 221 ns): peak 2141 N
    # (1 mm thick) with CMOD 12.9 um (0.2.0's shorter step: 2209 N, 14.3 um); 5 % for a
    # bond decision that flips elsewhere
    assert res["peak_load_N"] == pytest.approx(2140.7, rel=0.05)
    assert res["cmod_at_peak_m"] == pytest.approx(1.294e-5, rel=0.05)
    assert res["first_damage"]["load_N"] < res["fracture"]["load_N"] < res["peak_load_N"]
    # energy balance: grip work 0.02597 J less kinetic 0.00402 and strain 0.00819 J
    # leaves 0.01376 J, 0.758 x G0 t times the length of all broken bonds (0.884 at the
    # shipped grid). The grip work is the trapezoid rule over the history records, every
    # 10 steps: 2.2 us apart at this grid (1.5 us with 0.2.0's step, which measured
    # 0.921), too coarse for the load drop at fracture, so the bound is loose here
    e = res["energy"]
    assert e["dissipated_J"] > 0
    assert 0.7 < e["dissipated_over_g0_t_crack_length_all_bonds_m"] < 1.0
