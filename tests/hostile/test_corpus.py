"""The hostile corpus: decks and command lines a new user or an attacker tries, kept as
data (``tests/hostile/cases_*.yaml``) with the exit code and the message each must give.

Each case runs ``peridynamics ARGV`` in-process in a folder of its own. A case names

- ``id`` (unique) and ``origin``: ``issue`` (reported by users) or ``own`` (added by
  us or found by the fuzzer);
- ``deck`` (optional): an example whose ``deck.yaml`` and sibling files are copied into
  the folder, with ``set`` (dotted keys) changed in the copy;
- ``files`` (optional): files written into the folder, each ``{text: ...}``,
  ``{hex: ...}`` or ``{python: <expression giving bytes>}`` (``deck_text`` is the
  example deck's text);
- ``before`` (optional): command lines run first (any exit accepted);
- ``damage`` (optional): then files ``{path, truncate: fraction}``, ``{path, garbage:
  n_bytes}`` or ``{path, delete: true}``;
- ``tier`` (optional): ``long`` puts a case of more than a few seconds in the ``long``
  tier of ``.ci/run``;
- ``argv`` (or ``python_argv``: an expression giving the list, for long ones) and
  ``expect``: ``exit`` and ``outcome`` (``error``: a non-zero exit and the
  fragment on stderr; ``warning``: exit 0 and a ``warning:`` line with the fragment;
  ``run``: exit 0), ``stderr``: a fragment (or a list of them), case-insensitive.

Every case also must end without a Python traceback, and a run that exits 0 must write
a ``summary.json`` without NaN or infinity in its results.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import signal
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from tests.helpers import EXAMPLES, cli

HERE = Path(__file__).parent
OUTCOMES = ("error", "warning", "run")


def load_cases() -> list[dict[str, Any]]:
    """Every case of ``cases_*.yaml`` (ids checked unique)."""
    cases: list[dict[str, Any]] = []
    for path in sorted(HERE.glob("cases_*.yaml")):
        for case in yaml.safe_load(path.read_text(encoding="utf-8")) or []:
            case["_file"] = path.name
            cases.append(case)
    ids = [c["id"] for c in cases]
    dup = {i for i in ids if ids.count(i) > 1}
    if dup:
        raise ValueError(f"hostile corpus: ids given twice: {sorted(dup)}")
    return cases


def _set_key(data: dict[str, Any], dotted: str, value: Any) -> None:
    node: Any = data
    parts = dotted.split(".")
    for part in parts[:-1]:
        node = node[int(part)] if isinstance(node, list) else node.setdefault(part, {})
    if isinstance(node, list):
        node[int(parts[-1])] = value
    else:
        node[parts[-1]] = value


def prepare(case: dict[str, Any], folder: Path) -> None:
    """Write the case's deck and files into ``folder``, run ``before``, apply ``damage``."""
    deck_text = ""
    if "deck" in case:
        src = EXAMPLES / case["deck"]
        for f in src.iterdir():
            if f.is_file() and f.suffix not in {".png", ".json", ".md", ".py"}:
                shutil.copy(f, folder / f.name)
        deck_text = (src / "deck.yaml").read_text(encoding="utf-8")
        data = yaml.safe_load(deck_text)
        for key, value in (case.get("set") or {}).items():
            _set_key(data, key, value)
        deck_text = yaml.safe_dump(data, sort_keys=False)
        (folder / "deck.yaml").write_text(deck_text, encoding="utf-8")
    for name, spec in (case.get("files") or {}).items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if "text" in spec:
            path.write_text(spec["text"], encoding="utf-8")
        elif "hex" in spec:
            path.write_bytes(bytes.fromhex(spec["hex"]))
        else:
            path.write_bytes(eval(spec["python"], {"deck_text": deck_text}))  # noqa: S307
    for argv in case.get("before") or []:
        cli(*argv, cwd=folder)
    rng = np.random.default_rng(31)
    for spec in case.get("damage") or []:
        path = folder / spec["path"]
        if spec.get("delete"):
            path.unlink()
        elif "truncate" in spec:
            raw = path.read_bytes()
            path.write_bytes(raw[: int(len(raw) * float(spec["truncate"]))])
        else:
            path.write_bytes(rng.integers(0, 256, int(spec["garbage"]), dtype=np.uint8).tobytes())


def argv_of(case: dict[str, Any]) -> list[str]:
    """The command line of a case."""
    if "python_argv" in case:
        return list(eval(case["python_argv"], {}))  # noqa: S307
    return [str(a) for a in case["argv"]]


def judge(case: dict[str, Any], rc: int, stderr: str, folder: Path) -> str | None:
    """What is wrong with the outcome of a case (``None``: as expected)."""
    expect = case["expect"]
    if "Traceback" in stderr:
        return f"a traceback:\n{stderr}"
    if rc != expect["exit"]:
        return f"exit {rc}, expected {expect['exit']}:\n{stderr}"
    frags = expect.get("stderr") or []
    frags = [frags] if isinstance(frags, str) else frags
    low = stderr.lower()
    missing = [f for f in frags if f.lower() not in low]
    if missing:
        return f"stderr lacks {missing}:\n{stderr}"
    if expect["outcome"] == "warning" and "warning:" not in low:
        return f"no 'warning:' line:\n{stderr}"
    if rc == 0:
        for summary in folder.rglob("summary.json"):
            results = json.loads(summary.read_text()).get("results", {})
            bad = [k for k, v in results.items() if isinstance(v, float) and not math.isfinite(v)]
            if bad:
                return f"{summary}: non-finite results {bad}"
    return None


CASES = load_cases()
#: a case that takes longer is a hang (``timeout`` in a case changes it)
HANG_S = 120.0


@contextlib.contextmanager
def _time_limit(seconds: float, name: str) -> Iterator[None]:
    """Fail a case that runs longer than ``seconds`` (SIGALRM, main thread)."""

    def hang(signum: int, frame: Any) -> None:
        raise TimeoutError(f"{name}: a hang (no end after {seconds:.0f} s)")

    previous = signal.signal(signal.SIGALRM, hang)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@pytest.mark.parametrize(
    "case",
    [pytest.param(c, marks=[pytest.mark.long] if c.get("tier") == "long" else []) for c in CASES],
    ids=[c["id"] for c in CASES],
)
def test_hostile_case(case: dict[str, Any], tmp_path: Path) -> None:
    """The case ends with its documented exit code and message, and no traceback."""
    assert case["expect"]["outcome"] in OUTCOMES, case["id"]
    assert case.get("origin") in {"issue", "own"}, case["id"]
    prepare(case, tmp_path)
    with _time_limit(float(case.get("timeout", HANG_S)), case["id"]):
        proc = cli(*argv_of(case), cwd=tmp_path, env={"COLUMNS": "200"})
    problem = judge(case, proc.returncode, proc.stderr, tmp_path)
    assert problem is None, f"{case['id']} ({case['_file']}): {problem}"


def corpus_report(cases: list[dict[str, Any]], root: Path) -> dict[str, int]:
    """Outcome counts of the corpus (``python -m tests.hostile.test_corpus``): clean
    error, warning, correct run, traceback, hang, silent acceptance (exit 0 where an
    error or a warning was expected), other mismatch."""
    kinds = ("error", "warning", "run", "traceback", "hang", "silent", "mismatch")
    counts = dict.fromkeys(kinds, 0)
    for case in cases:
        folder = root / case["id"]
        folder.mkdir(parents=True)
        try:
            prepare(case, folder)
            with _time_limit(float(case.get("timeout", HANG_S)), case["id"]):
                proc = cli(*argv_of(case), cwd=folder)
            rc, stderr = proc.returncode, proc.stderr
        except TimeoutError as exc:
            counts["hang"] += 1
            print(exc)
            continue
        except BaseException as exc:  # noqa: BLE001 - an escaped exception is a traceback
            rc, stderr = 1, f"Traceback: {exc!r}"
        problem = judge(case, rc, stderr, folder)
        want = case["expect"]["outcome"]
        if problem is None:
            counts[want] += 1
        elif "Traceback" in stderr:
            counts["traceback"] += 1
        elif rc == 0 and ("warning:" not in stderr.lower() or want == "error"):
            counts["silent"] += 1
        else:
            counts["mismatch"] += 1
        if problem is not None:
            print(f"{case['id']}: {problem.splitlines()[0]}")
    return counts


def isolated_report(cases: list[dict[str, Any]], memory_gib: float = 6.0) -> dict[str, int]:
    """:func:`corpus_report` with every case in a process of its own (at most
    ``memory_gib`` of memory and :data:`HANG_S` seconds): a case that kills its process
    (out of memory, a crash) counts as a traceback, one that runs out of time as a hang.
    For measuring code that may not survive the corpus (``python -m
    tests.hostile.test_corpus --isolated``)."""
    import subprocess
    import sys

    kinds = ("error", "warning", "run", "traceback", "hang", "silent", "mismatch")
    counts = dict.fromkeys(kinds, 0)
    limit = (
        f"import resource; resource.setrlimit(resource.RLIMIT_AS, ({int(memory_gib * 2**30)},) * 2)"
    )
    for case in cases:
        one = "from tests.hostile.test_corpus import main_one; main_one(sys.argv[1])"
        code = f"{limit}; import sys; {one}"
        try:
            proc = subprocess.run(
                [sys.executable, "-c", code, case["id"]],
                capture_output=True,
                text=True,
                timeout=HANG_S + 60,
            )
            got = proc.stdout.strip().splitlines()
            kind = got[-1] if got and got[-1] in kinds else "traceback"
        except subprocess.TimeoutExpired:
            kind = "hang"
        counts[kind] += 1
        if kind not in ("error", "warning", "run") or (got and len(got) > 1):
            print(f"{case['id']}: {kind}", file=sys.stderr)
    return counts


def main_one(case_id: str) -> None:
    """Run one case (by id) and print its outcome kind on the last line."""
    import tempfile

    case = next(c for c in CASES if c["id"] == case_id)
    with tempfile.TemporaryDirectory() as tmp:
        counts = corpus_report([case], Path(tmp))
    print(next(k for k, v in counts.items() if v))
    os._exit(0)


if __name__ == "__main__":
    import sys
    import tempfile

    if "--isolated" in sys.argv:
        print(json.dumps(isolated_report(CASES), indent=1))
    else:
        with tempfile.TemporaryDirectory() as tmp:
            print(json.dumps(corpus_report(CASES, Path(tmp)), indent=1))
    os._exit(0)
