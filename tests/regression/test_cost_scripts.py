"""The cost-per-evaluation scripts of the history-dependent models run to the end at a
tiny size (their timings are benchmarks, not asserted): ``long`` tier."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tests.helpers import EXAMPLES, subprocess_env

SCRIPTS = [
    ("plasticity/cost_per_step.py", ["6"]),
    ("plasticity/cost_per_step_lps.py", ["8", "2"]),
    ("viscoelastic/cost_per_step.py", ["6"]),
]


@pytest.mark.long
@pytest.mark.parametrize(("script", "args"), SCRIPTS, ids=[s for s, _ in SCRIPTS])
def test_cost_script_runs(script: str, args: list[str]) -> None:
    got = subprocess.run(
        [sys.executable, str(EXAMPLES / script), *args],
        env=subprocess_env({"NUMBA_NUM_THREADS": "1"}), capture_output=True, text=True,
        timeout=600, check=False,
    )  # fmt: skip
    assert got.returncode == 0, got.stderr[-3000:]
    assert got.stdout.strip()
