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
