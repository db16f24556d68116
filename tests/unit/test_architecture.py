"""The house rules of docs/architecture.md, checked on the source tree.

- the import-linter contracts of ``pyproject.toml`` (the layers, families independent of
  each other, Warp and MPI independent, outputs without decks) are all kept;
- no import cycle between modules (a lazy import inside a function counts);
- no source file over 500 lines (a kernel module may reach 800 if its first five lines
  say it "cannot be split" and why); no function over 100 lines outside the kernels.
"""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers import ROOT

SRC = ROOT / "src" / "peridynamics"


def _is_kernel(rel: Path) -> bool:
    """Numba kernels (``kernels/``) and Warp kernels (``backends/_warp_*_dsl.py``): a long
    loop body there is one idea and stays whole."""
    return rel.parts[0] == "kernels" or (
        rel.parts[0] == "backends" and rel.name.startswith("_warp_")
    )


def _modules() -> dict[str, Path]:
    out = {}
    for path in sorted(SRC.rglob("*.py")):
        parts = path.relative_to(SRC.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _imports(name: str, path: Path, known: set[str]) -> set[str]:
    """The package modules ``name`` imports anywhere in its file (top level, inside
    functions or under TYPE_CHECKING), resolved to the longest known module."""
    found = set()
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    for node in ast.walk(ast.parse(path.read_text())):
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            targets = [f"{base}.{a.name}" for a in node.names] + [base]
        for t in targets:
            while t and t not in known:
                t = t.rpartition(".")[0]
            if t and t != name and t.startswith("peridynamics."):
                found.add(t)
    return found


def test_import_linter_contracts_are_kept() -> None:
    pytest.importorskip("importlinter", reason="pip install import-linter (the test extra)")
    exe = Path(sys.executable).parent / "lint-imports"
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "importlinter.cli"]
    proc = subprocess.run(
        [*cmd, "--no-cache"], cwd=ROOT, capture_output=True, text=True, timeout=300
    )
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, out
    kept = re.search(r"Contracts: (\d+) kept, (\d+) broken", out)
    assert kept is not None, out
    assert int(kept.group(1)) >= 4 and int(kept.group(2)) == 0, out


def test_no_import_cycle() -> None:
    mods = _modules()
    known = set(mods)
    graph = {m: {t for t in _imports(m, p, known) if t in known} for m, p in mods.items()}
    # a package's __init__ importing its own submodules is not a cycle of the house
    for m in graph:
        graph[m] = {t for t in graph[m] if not t.startswith(m + ".")}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    cycles: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in graph:
        if v not in index:
            visit(v)
    assert cycles == [], f"import cycles: {cycles}"


def test_modules_fit_on_a_screen() -> None:
    too_long = []
    for path in sorted(SRC.rglob("*.py")):
        text = path.read_text()
        n = text.count("\n")
        head = "\n".join(text.splitlines()[:5])
        limit = 800 if "cannot be split" in head else 500
        if n > limit:
            too_long.append(f"{path.relative_to(SRC)}: {n} lines")
    assert too_long == []


def test_functions_fit_on_a_screen() -> None:
    too_long = []
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC)
        if _is_kernel(rel):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                lines = node.end_lineno - node.lineno + 1  # type: ignore[operator]
                if lines > 100:
                    too_long.append(f"{rel}:{node.name}: {lines} lines")
    assert too_long == []
