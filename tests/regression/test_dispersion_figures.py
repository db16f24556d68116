"""The one-command dispersion figures (examples/dispersion/make_figures.py) run at low
resolution and write every PNG."""

from __future__ import annotations

import importlib.util
import time
from pathlib import Path

import pytest

from tests.helpers import EXAMPLES

pytestmark = pytest.mark.long  # the figure script (CI: pytest -m long)

SCRIPT = EXAMPLES / "dispersion" / "make_figures.py"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _load_script():
    spec = importlib.util.spec_from_file_location("dispersion_make_figures", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_make_figures_writes_every_png(tmp_path: Path) -> None:
    mod = _load_script()
    t0 = time.perf_counter()
    paths = mod.make_figures(tmp_path, n_points=201)
    elapsed = time.perf_counter() - t0
    assert elapsed < 30.0
    assert [p.name for p in paths] == list(mod.FIGURES)
    assert len(paths) == 9
    for p in paths:
        assert p.parent == tmp_path
        assert p.is_file()
        assert p.stat().st_size > 5_000, p.name  # a real picture, not an empty canvas
        assert p.read_bytes()[:8] == PNG_SIGNATURE, p.name
