"""summary.json: inputs, results, timing and versions of a run (the machine-readable contract)."""

from __future__ import annotations

import json
import math
import platform
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import numpy as np

from peridynamics.io.atomic import atomic_path

DEPENDENCIES = ("numpy", "scipy", "numba", "meshio", "pyyaml", "pydantic", "matplotlib", "rich")


def versions() -> dict[str, str]:
    """Versions of the package, its dependencies and Python."""
    out = {"python": platform.python_version()}
    for name in ("peridynamics", *DEPENDENCIES):
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            out[name] = "not installed"
    return out


def _clean(v: Any) -> Any:
    if isinstance(v, dict):
        return {str(k): _clean(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_clean(x) for x in v]
    if isinstance(v, np.ndarray):
        return _clean(v.tolist())
    if isinstance(v, np.generic):
        return _clean(v.item())
    if isinstance(v, float) and not math.isfinite(v):
        return None  # JSON has no inf/NaN
    return v


def write_summary(
    path: Path, inputs: dict, results: dict, timing: dict, extra: dict | None = None
) -> dict:
    """Write summary.json atomically; returns the written mapping."""
    data = {"inputs": inputs, "results": results, "timing": timing, "versions": versions()}
    if extra:
        data.update(extra)
    data = _clean(data)
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(data, indent=2, allow_nan=False) + "\n")
    return data
