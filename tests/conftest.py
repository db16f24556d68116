"""Fixtures shared by the test files.

- ``serial_numba``: one Numba thread for the test (small clouds, many kernel calls:
  a parallel launch costs more than the work; results do not depend on the count).
- ``example_run``: an example deck run once per session through the command line and
  shared by every test that asks for the same run (an example's test and its gallery
  test read one run).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from pathlib import Path

if "PYTEST_XDIST_WORKER" in os.environ:  # pytest -n N: N processes share the cores
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numba  # noqa: E402
import pytest

from tests.helpers import EXAMPLES, cli


@pytest.fixture
def serial_numba() -> Iterator[None]:
    """One Numba thread while the test runs (the previous count restored after)."""
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(before)


@pytest.fixture(scope="session")
def example_run(tmp_path_factory: pytest.TempPathFactory) -> Callable[..., Path]:
    """``example_run(folder, deck, *overrides)``: the output folder of
    ``peridynamics run examples/<folder>/<deck> --set <override>...  --quiet``, run the
    first time it is asked for and shared for the session. Read it, do not write in it
    (copy it to write: ``shutil.copytree``)."""
    runs: dict[tuple[str, ...], Path] = {}

    def run(folder: str, deck: str = "deck.yaml", *overrides: str) -> Path:
        key = (folder, deck, *overrides)
        if key not in runs:
            out = tmp_path_factory.mktemp(f"{folder}_{Path(deck).stem}") / "run"
            sets = [a for o in overrides for a in ("--set", o)]
            cli("run", EXAMPLES / folder / deck, "--out", out, "--quiet", *sets, check=True)
            runs[key] = out
        return runs[key]

    return run


#: the marker tiers (pyproject.toml): the default selection deselects them all; .ci/run
#: runs mpi, gpu, docs and long after it (slow: paper scale, by hand)
TIERS = ("mpi", "gpu", "docs", "long", "slow")


@pytest.hookimpl(tryfirst=True)  # before -m deselects: every collected test is checked
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Each test is in at most one tier, so the default run and the tiers of ``.ci/run``
    run every test exactly once."""
    both = [
        f"{item.nodeid}: {', '.join(names)}"
        for item in items
        if len(names := [t for t in TIERS if item.get_closest_marker(t) is not None]) > 1
    ]
    if both:
        raise pytest.UsageError("tests in more than one tier:\n" + "\n".join(both))
