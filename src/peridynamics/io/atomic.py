"""Files that appear whole: written under a temporary name in the same folder, then
renamed over the final name (``os.replace`` is atomic on POSIX and Windows), so that a
kill or a full disk never leaves a half-written result file under its real name."""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary path next to ``path``; renamed to ``path`` when the block ends
    without an exception, removed otherwise."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def save_npz(path: str | Path, **arrays: Any) -> None:
    """``np.savez(path, **arrays)``, appearing atomically."""
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **arrays)
