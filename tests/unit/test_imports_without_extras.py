"""Every module of the package imports without the optional extras (warp-lang of
``[gpu]``, mpi4py of ``[mpi]``): the documentation site imports them all, and a run
that does not ask for a backend must not need it."""

from __future__ import annotations

import subprocess
import sys

from tests.helpers import PACKAGE_PARENT

SCRIPT = """
import sys
sys.modules["warp"] = None      # import warp -> ImportError
sys.modules["mpi4py"] = None
import importlib, pkgutil
import peridynamics
failed = []
for m in pkgutil.walk_packages(peridynamics.__path__, "peridynamics."):
    if m.name.endswith("__main__"):
        continue  # runs the command line
    try:
        importlib.import_module(m.name)
    except Exception as exc:
        failed.append(f"{m.name}: {type(exc).__name__}: {exc}")
print("\\n".join(failed) or "ok")
"""


def test_every_module_imports_without_warp_and_mpi4py() -> None:
    proc = subprocess.run(
        [sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=300,
        env={"PYTHONPATH": str(PACKAGE_PARENT), "PATH": "/usr/bin:/bin"},
    )  # fmt: skip
    assert proc.stdout.strip() == "ok", proc.stdout + proc.stderr[-2000:]
