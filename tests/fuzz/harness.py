"""The fuzzer's oracle: a deck (text or bytes) run through ``peridynamics check --bonds``
(or a short ``run``) in this process, with the memory the size guard sees capped so a
mutation that makes the model large is refused instead of built, and a watchdog that
ends a hung example.

Every outcome must be an exit in {0, 2} (3 too for ``run``: unstable) without a Python
traceback on stderr and without an exception escaping ``main``; a ``run`` that exits 0
writes a ``summary.json`` whose ``results`` hold no NaN or infinity.
"""

from __future__ import annotations

import contextlib
import faulthandler
import json
import math
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from unittest import mock

from tests.helpers import cli

#: the memory the size guard sees (bytes): its base 0.3 GB plus room for about a
#: million bonds, so a mutation that makes the model large is refused in milliseconds
MEMORY_CAP = 0.45e9
#: an example that takes longer than this (s) dumps the stacks and ends the process
WATCHDOG_S = 300.0
#: exit codes a command may end with (0 valid, 2 invalid; 3 unstable for run)
ALLOWED = {"check": {0, 2}, "run": {0, 2, 3}}


@dataclass
class Tally:
    """Counts of a fuzz session: examples, exit codes, the slowest example."""

    examples: int = 0
    exits: dict[int, int] = field(default_factory=dict)
    slowest: float = 0.0
    seconds: float = 0.0
    started: float = field(default_factory=time.perf_counter)

    def add(self, rc: int, seconds: float) -> None:
        """Count one example."""
        self.examples += 1
        self.exits[rc] = self.exits.get(rc, 0) + 1
        self.slowest = max(self.slowest, seconds)
        self.seconds = time.perf_counter() - self.started

    def line(self, what: str) -> str:
        """One line for the test's output."""
        exits = ", ".join(f"exit {k}: {v}" for k, v in sorted(self.exits.items()))
        return (
            f"fuzz {what}: {self.examples} examples in {self.seconds:.1f} s ({exits}; "
            f"slowest {self.slowest:.2f} s)"
        )


@contextlib.contextmanager
def capped_memory() -> Iterator[None]:
    """The size guard sees :data:`MEMORY_CAP` bytes available."""
    with mock.patch(
        "peridynamics.app.checks.available_memory", return_value=(MEMORY_CAP, "the fuzz cap")
    ):
        yield


@contextlib.contextmanager
def watchdog(seconds: float = WATCHDOG_S) -> Iterator[None]:
    """Dump every thread's stack and end the process if the block takes ``seconds``."""
    faulthandler.dump_traceback_later(seconds, exit=True)
    try:
        yield
    finally:
        faulthandler.cancel_dump_traceback_later()


def non_finite(value: Any, path: str = "results") -> list[str]:
    """Key paths of the NaN and infinite numbers in a JSON value."""
    if isinstance(value, float) and not math.isfinite(value):
        return [path]
    if isinstance(value, dict):
        return [p for k, v in value.items() for p in non_finite(v, f"{path}.{k}")]
    if isinstance(value, list):
        return [p for n, v in enumerate(value) for p in non_finite(v, f"{path}.{n}")]
    return []


def _show(deck: bytes) -> str:
    text = deck.decode("utf-8", errors="backslashreplace")
    return text if len(text) < 4000 else text[:4000] + f"\n... ({len(text)} characters)"


def judge(command: str, rc: int, stderr: str, out: Path | None) -> str | None:
    """What is wrong with an outcome (``None``: acceptable)."""
    if rc not in ALLOWED[command]:
        return f"exit {rc} (allowed {sorted(ALLOWED[command])})"
    if "Traceback" in stderr:
        return "a traceback on stderr"
    if command == "run" and rc == 0 and out is not None:
        summary = out / "summary.json"
        if not summary.is_file():
            return "exit 0 without a summary.json"
        bad = non_finite(json.loads(summary.read_text()).get("results", {}))
        if bad:
            return f"non-finite results {bad[:5]}"
    return None


def exercise(deck: bytes, tally: Tally, command: str = "check", bonds: bool = True) -> None:
    """Run ``peridynamics COMMAND deck.yaml`` (``check``, with ``--bonds`` if ``bonds``;
    or ``run``) on ``deck`` in a temporary folder and assert the oracle (the module's
    docstring); the deck's text is in the message."""
    with tempfile.TemporaryDirectory(prefix="fuzz_") as tmp:
        folder = Path(tmp)
        (folder / "deck.yaml").write_bytes(deck)
        out = folder / "out" if command == "run" else None
        args = ["run", "deck.yaml", "--out", "out", "--quiet"]
        if command == "check":
            args = ["check", "deck.yaml", *(["--bonds"] if bonds else [])]
        start = time.perf_counter()
        try:
            with capped_memory(), watchdog():
                proc = cli(*args, cwd=folder, env={"COLUMNS": "200"})
        except Exception as exc:  # noqa: BLE001 - an exception escaping main
            raise AssertionError(
                f"{type(exc).__name__} escaped main: {exc}\ndeck:\n{_show(deck)}"
            ) from exc
        tally.add(proc.returncode, time.perf_counter() - start)
        problem = judge(command, proc.returncode, proc.stderr, out)
        assert problem is None, f"{problem}\nstderr:\n{proc.stderr[-3000:]}\ndeck:\n{_show(deck)}"
