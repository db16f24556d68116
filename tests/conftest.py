"""Fixtures shared by the test files.

- ``serial_numba``: one Numba thread for the test (small clouds, many kernel calls:
  a parallel launch costs more than the work; results do not depend on the count).
"""

from __future__ import annotations

from collections.abc import Iterator

import numba
import pytest


@pytest.fixture
def serial_numba() -> Iterator[None]:
    """One Numba thread while the test runs (the previous count restored after)."""
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(before)


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
