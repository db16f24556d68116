"""Shared helpers for tests: run the CLI in a subprocess against the source tree."""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


def load_script(path: Path, name: str) -> ModuleType:
    """An example's script (``examples/<folder>/<script>.py``) imported as module ``name``."""
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def mpiexec() -> tuple[str | None, str]:
    """The mpiexec to use (beside this Python first, then on PATH) and, when there is
    none, why (for a skip reason)."""
    try:
        import mpi4py  # noqa: F401
    except ImportError:
        return None, "mpi4py cannot be imported (pip install '.[mpi]')"
    here = Path(sys.executable).parent / "mpiexec"
    found = str(here) if here.is_file() else shutil.which("mpiexec")
    return found, "no mpiexec beside sys.executable or on PATH (pip install '.[mpi]')"


def cli(
    *args: str,
    env: dict[str, str] | None = None,
    timeout: float = 600,
    check: bool = False,
    ranks: int = 1,
) -> subprocess.CompletedProcess:
    """Run ``python -m peridynamics ARGS`` with the source tree importable; under
    ``mpiexec -n RANKS`` when ``ranks`` > 1."""
    full_env = dict(os.environ)
    src = str(ROOT / "src")
    full_env["PYTHONPATH"] = src + os.pathsep + full_env.get("PYTHONPATH", "")
    if env:
        full_env.update(env)
    launch = [str(mpiexec()[0]), "-n", str(ranks)] if ranks > 1 else []
    proc = subprocess.run(
        [*launch, sys.executable, "-m", "peridynamics", *args],
        capture_output=True,
        text=True,
        env=full_env,
        timeout=timeout,
    )
    if check and proc.returncode != 0:
        raise AssertionError(
            f"exit {proc.returncode}\nstdout:\n{proc.stdout}\nstderr:\n{proc.stderr}"
        )
    return proc


def popen(*args: str) -> subprocess.Popen:
    """Start ``python -m peridynamics ARGS`` in the background."""
    full_env = dict(os.environ)
    full_env["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + full_env.get("PYTHONPATH", "")
    return subprocess.Popen(
        [sys.executable, "-m", "peridynamics", *args],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        env=full_env,
    )
