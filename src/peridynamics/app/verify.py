"""``peridynamics verify``: run the verification cases (:mod:`peridynamics.app.verify_cases`)
and write a report: ``verify.json``, ``verify.md`` and ``verify.html`` (a table of case,
quantity, measured, reference, tolerance, pass or fail, time; the figure each run drew).

Each case runs its example deck into ``<out>/<case>/`` (the files of ``peridynamics
run``); ``<case>/case.json`` records its fingerprint (the case, its overrides, the
validated deck and the package version) and outcome, so a rerun of the same command
skips the cases that finished and reruns the rest. ``--jobs N`` runs N cases at a time,
each in its own process with its share of the cores.
"""

from __future__ import annotations

import hashlib
import json
import os
import platform
import time
from concurrent.futures import ProcessPoolExecutor
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from peridynamics.app.examples import list_examples
from peridynamics.app.verify_cases import Case, select
from peridynamics.app.verify_report import write_reports
from peridynamics.io.atomic import atomic_path

__all__ = ["run_cases", "run_one"]


def _fingerprint(case: Case, tier: str, deck_dump: dict[str, Any]) -> str:
    from peridynamics import __version__

    text = json.dumps([case.name, tier, deck_dump, __version__], sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


def _load(case: Case, tier: str, extra: tuple[str, ...] = ()) -> Any:
    from peridynamics.deck import load_deck

    decks = list_examples()
    if case.deck not in decks:
        raise FileNotFoundError(f"case {case.name}: no example deck {case.deck!r}")
    return load_deck(decks[case.deck], [*(case.overrides(tier) or ()), *extra])


def _run_deck(
    deck: Any, folder: Path, fingerprint: str
) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """The summary of ``deck`` run into ``folder`` (or of a finished run there with the
    same fingerprint) and, when it was reused, the case record of the run that made it
    (``None``: run now)."""
    finished = _finished(folder, fingerprint)
    if finished is not None:
        return finished
    from peridynamics.app.run import Simulation

    folder.mkdir(parents=True, exist_ok=True)
    return Simulation.from_deck(deck).run(folder, quiet=True, progress=False), None


def run_one(case: Case, tier: str, out: Path) -> dict[str, Any]:
    """Run ``case`` at ``tier``'s size into ``out / case.name`` (or reuse a finished run
    with the same fingerprint) and judge its checks; returns the case's record."""
    folder = out / case.name
    record: dict[str, Any] = {"case": case.name, "title": case.title, "deck": case.deck,
                              "overrides": list(case.overrides(tier) or ())}  # fmt: skip
    t0 = time.perf_counter()
    earlier: dict[str, Any] | None = None  # the record of the run a reused case comes from
    ran_now = 0.0  # seconds of further runs (companion, series) run by this call
    try:
        deck = _load(case, tier)
        fingerprint = _fingerprint(case, tier, deck.model_dump(mode="json", by_alias=True))
        summary, earlier = _run_deck(deck, folder, fingerprint)
        record["reused"] = earlier is not None
        summary = {**summary, "folder": str(folder)}  # checks that read the final fields
        if case.companion is not None:  # the same problem by another scheme
            companion, took = _further_run(case, tier, case.companion, folder / "companion")
            ran_now += took
            summary = {**summary, "companion": companion}
            if companion.get("status", "completed") != "completed":
                summary["status"] = "companion " + str(companion.get("status"))
        if case.series:  # the refinements of a convergence study
            runs = []
            for k, extra in enumerate(case.series):
                run, took = _further_run(case, tier, extra, folder / f"series_{k}")
                runs.append(run)
                ran_now += took
                if runs[-1].get("status", "completed") != "completed":
                    summary["status"] = f"series_{k} " + str(runs[-1].get("status"))
            summary = {**summary, "series": runs}
        record["status"] = summary.get("status", "completed")
        record["checks"] = _judge(case, summary)
        record["figures"] = [f for f in summary.get("files", []) if f.endswith(".png")]
        record["fingerprint"] = fingerprint
    except Exception as exc:  # a case that cannot run is a failure of the report, not a crash
        record.update(status="error", error=f"{type(exc).__name__}: {exc}", checks=[])
    record["passed"] = record["status"] == "completed" and all(
        c["passed"] for c in record["checks"]
    )
    record["wall_s"] = time.perf_counter() - t0
    made = None if earlier is None else earlier.get("wall_s")
    if isinstance(made, (int, float)):  # reused: the time of the call that made it,
        record["wall_s"] = float(made) + ran_now  # plus further runs made only now
    _write_record(folder, record)
    return record


def _further_run(
    case: Case, tier: str, extra: tuple[str, ...], sub: Path
) -> tuple[dict[str, Any], float]:
    """The summary of the case's deck with ``extra`` overrides added, run into ``sub``
    (or reused from a finished run there with the same fingerprint), and the seconds
    this call spent running it (0 when reused)."""
    other = _load(case, tier, extra)
    fingerprint = _fingerprint(case, tier, other.model_dump(mode="json", by_alias=True))
    t0 = time.perf_counter()
    summary, earlier = _run_deck(other, sub, fingerprint)
    _write_record(sub, {"fingerprint": fingerprint})
    ran = 0.0 if earlier is not None else time.perf_counter() - t0
    return {**summary, "folder": str(sub)}, ran


def _write_record(folder: Path, record: dict[str, Any]) -> None:
    """``folder/case.json`` (the fingerprint a rerun compares), where the run wrote."""
    if folder.is_dir():
        with atomic_path(folder / "case.json") as tmp:
            tmp.write_text(json.dumps(record, indent=2) + "\n")


def _finished(folder: Path, fingerprint: str) -> tuple[dict[str, Any], dict[str, Any]] | None:
    """The summary of a finished run of this fingerprint in ``folder`` and the case's
    record (``case.json``) of it, else ``None``."""
    try:
        old = json.loads((folder / "case.json").read_text())
        summary = json.loads((folder / "summary.json").read_text())
    except (OSError, ValueError):
        return None
    if old.get("fingerprint") != fingerprint or summary.get("status") != "completed":
        return None
    return dict(summary), dict(old)


def _judge(case: Case, summary: dict[str, Any]) -> list[dict[str, Any]]:
    """Each check's measured and reference values and verdict."""
    out = []
    for check in case.checks:
        try:
            measured = float(check.measure(summary))
        except (KeyError, TypeError, ValueError, IndexError) as exc:
            measured, why = float("nan"), f"not measured: {type(exc).__name__}: {exc}"
        else:
            why = ""
        reference = float(check.reference(summary["inputs"]))
        tol = (f"<= reference (+{check.rel:g} rel)" if check.at_most
               else f"{check.rel:g} rel + {check.abs:g} {check.unit}")  # fmt: skip
        out.append({
            "quantity": check.quantity, "unit": check.unit, "measured": measured,
            "reference": reference, "tolerance": tol, "source": check.source,
            "passed": check.judge(measured, reference), **({"note": why} if why else {}),
        })  # fmt: skip
    return out


def _run_named(name: str, tier: str, out: Path) -> dict[str, Any]:
    """:func:`run_one` of the case ``name`` (a worker process: cases hold functions,
    which do not pickle)."""
    from peridynamics.app.verify_cases import CASES

    return run_one(next(c for c in CASES if c.name == name), tier, out)


def _worker_init(threads: int) -> None:
    os.environ["NUMBA_NUM_THREADS"] = str(threads)


def machine() -> dict[str, Any]:
    """The machine the report ran on: CPU model (``/proc/cpuinfo``), cores, Python."""
    model = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:
        cores = os.cpu_count() or 1
    return {"cpu": model, "cores": cores, "python": platform.python_version(),
            "system": platform.platform()}  # fmt: skip


def run_cases(
    tier: str, out: Path, pattern: str | None = None, jobs: int = 1, quiet: bool = False
) -> dict[str, Any]:
    """Run the cases of ``tier`` matching ``pattern`` into ``out`` and write the reports;
    returns ``verify.json``'s content (``passed``: every case passed)."""
    from peridynamics import __version__

    cases = select(tier, pattern)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    records: list[dict[str, Any]] = []
    if jobs <= 1:
        for case in cases:
            records.append(_said(run_one(case, tier, out), quiet, len(records) + 1, len(cases)))
    else:
        import multiprocessing

        from peridynamics.parallel.launch import threads_per_process

        threads = threads_per_process(jobs, 1)  # the cores shared among the jobs

        ctx = multiprocessing.get_context("spawn")  # no forked Numba threads
        with ProcessPoolExecutor(jobs, mp_context=ctx, initializer=_worker_init,
                                 initargs=(threads,)) as pool:  # fmt: skip
            futures = [pool.submit(_run_named, case.name, tier, out) for case in cases]
            for fut in futures:
                records.append(_said(fut.result(), quiet, len(records) + 1, len(cases)))
    report = {
        "tier": tier,
        "pattern": pattern,
        "version": __version__,
        "date": datetime.now(UTC).isoformat(timespec="seconds"),
        "machine": machine(),
        "jobs": jobs,
        "wall_s": time.perf_counter() - t0,
        # the cases' own run times: a resumed campaign's wall_s counts this call alone
        "case_wall_s": sum(float(r.get("wall_s", 0.0)) for r in records),
        "cases": records,
        "passed": all(r["passed"] for r in records),
    }
    write_reports(out, report)
    return report


def _said(record: dict[str, Any], quiet: bool, k: int, n: int) -> dict[str, Any]:
    if not quiet:
        verdict = "pass" if record["passed"] else "FAIL"
        reused = " (done before)" if record.get("reused") else ""
        print(f"[{k}/{n}] {record['case']}: {verdict} in {record['wall_s']:.1f} s{reused}",
              flush=True)  # fmt: skip
        if record.get("error"):
            print(f"    {record['error']}", flush=True)
    return record
