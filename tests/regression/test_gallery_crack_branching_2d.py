"""The figure script of the crack-branching example (``examples/crack_branching_2d/
make_figures.py``) on the run of the fast test in ``test_examples.py`` (16 000 points,
46 us; ``--no-run`` on a copy of the session's shared run, ``tests/conftest.py``): the
numbers the script adds to the run's summary (Rayleigh speeds of the model as run, the
crack start, the mean tip speed) and its figure. The run's own results are checked by
``test_examples.py::test_crack_branching_small``.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.helpers import BRANCHING, EXAMPLES, load_script

pytestmark = pytest.mark.long  # the 16 000-point run (CI: pytest -m long)

SCRIPT = EXAMPLES / "crack_branching_2d" / "make_figures.py"


def test_make_figures_small(tmp_path: Path, example_run: Callable[..., Path]) -> None:
    mod = load_script(SCRIPT, "cb_figures")
    out = shutil.copytree(
        example_run("crack_branching_2d", "deck.yaml", *BRANCHING), tmp_path / "run"
    )
    sets = [a for s in BRANCHING for a in ("--set", s)]
    assert mod.main(["--out", str(out), "--no-run", *sets]) == 0
    res = json.loads((out / "crack_branching_2d.json").read_text())
    assert (out / "crack_branching_2d.png").stat().st_size > 1000
    # Rayleigh speeds (exact root, plane stress, nu = 1/3): 0.855 E (static solves,
    # docs/deck.md) 2807.5 m/s, the constant of test_examples.py; the library's energy
    # ratio 0.8774 (a property of the m = 4 grid family) 2844.0 m/s; nominal E 3036.3 m/s
    assert res["rayleigh_speed_model_m_per_s"] == pytest.approx(2807.5, rel=1e-4)
    assert res["modulus_ratio_energy"] == pytest.approx(0.8774, rel=1e-3)
    assert res["rayleigh_speed_nominal_E_m_per_s"] == pytest.approx(3036.3, rel=1e-4)
    # measured with 0.3.0's Lanczos step: the tip leaves the pre-crack tip at 8.48 us
    # (records every 1.7 us: slack of about two), mean speed 1244 m/s over 12-40 us
    # (0.443 c_R), peak 1376 m/s (0.490 c_R; 5 % as in test_examples.py; 0.2.0's
    # shorter step: 7.73 us, 1243 m/s, 0.538 c_R), no record above c_R, branched
    assert res["crack_start_time_s"] == pytest.approx(8.48e-6, abs=3.4e-6)
    assert res["mean_crack_tip_speed_m_per_s"] == pytest.approx(1243.9, rel=0.1)
    assert res["max_speed_over_rayleigh_model"] == pytest.approx(0.490, rel=0.05)
    assert res["records_above_rayleigh_model"] == 0
    assert res["crack_branched"] is True
