"""The runs of a calibration: each parameter vector is a case of the sweep machinery
(:mod:`peridynamics.app.sweep_run`), a ``peridynamics run`` process in its own folder
under ``DIR/runs``, a batch of them ``jobs`` at a time (under ``mpiexec -n N``, divided
among the ranks: :mod:`peridynamics.app.calibrate_mpi`).

The folder of a run is named from its parameter values and holds ``case.json`` with
the fingerprint of its validated deck; a calibration started again over the same folder
finds the runs it already has (same values, same fingerprint, status ``completed``) and
reads them back instead of running them (``skipped-done``): an interrupted calibration,
whose optimiser is deterministic, retraces its steps at no cost and continues.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.app.calibrate_mpi import Batch, Ranks, runs_plan
from peridynamics.app.calibrate_spec import CalibrationError, Parameter
from peridynamics.app.sweep_cases import Case, Override, validate, yaml_text
from peridynamics.app.sweep_run import run_cases


def run_folder(params: list[Parameter], values: list[float]) -> str:
    """``run_<12 hex digits>``: a hash of the keys and values (``repr``, exact)."""
    text = ";".join(f"{p.key}={v!r}" for p, v in zip(params, values, strict=True))
    return "run_" + hashlib.sha1(text.encode()).hexdigest()[:12]


@dataclass
class RunRecord:
    """One finished run: its values, folder, status, wall time and the MPI rank that ran
    (or read back) it."""

    values: list[float]
    folder: str
    status: str
    wall_s: float | None
    cached: bool
    rank: int = 0


@dataclass
class Runner:
    """Runs batches of parameter vectors through the sweep machinery.

    Attributes
    ----------
    deck : Path
        The deck.
    sets : list of str
        Fixed ``--set`` overrides of every run.
    params : list of Parameter
        The fitted parameters (their deck keys).
    out : Path
        The calibration folder; runs go to ``out/runs/<run folder>``.
    jobs : int
        Runs at a time.
    quiet : bool
        No progress lines.
    ranks : Ranks or None
        Under ``mpiexec -n N`` (rank 0): each batch is divided among the ranks.
    """

    deck: Path
    sets: list[str]
    params: list[Parameter]
    out: Path
    jobs: int = 1
    quiet: bool = False
    allow_large: bool = False
    log: list[RunRecord] = field(default_factory=list)
    ranks: Ranks | None = None
    on_batch: Callable[[list[RunRecord]], None] | None = None

    @property
    def runs(self) -> int:
        """Runs made so far (not counting those read back from an earlier calibration)."""
        return sum(1 for r in self.log if not r.cached)

    def cases(self, points: list[list[float]]) -> list[Case]:
        """The sweep cases of parameter vectors (validated, fingerprinted)."""
        cases = []
        for n, values in enumerate(points):
            ovs = tuple(
                Override(p.key, yaml_text(float(v)), float(v), "parameters")
                for p, v in zip(self.params, values, strict=True)
            )
            cases.append(Case(n, ovs, run_folder(self.params, values)))
        problem = validate(str(self.deck), self.sets, cases, self.allow_large)
        if problem:
            raise CalibrationError(problem.replace("sweep: ", "calibrate: ", 1))
        return cases

    def run(self, points: list[list[float]]) -> list[RunRecord]:
        """Run (or read back) every point; returns one record per point, in order."""
        unique: dict[str, list[float]] = {}
        for values in points:
            unique.setdefault(run_folder(self.params, values), values)
        cases = self.cases(list(unique.values()))
        runs = self.out / "runs"
        runs.mkdir(parents=True, exist_ok=True)
        if self.ranks is None:
            plan = runs_plan(self.deck, self.sets, runs, self.jobs, self.allow_large)
            records, interrupted = run_cases(cases, plan, self.jobs, lambda rec: None)
        else:
            job = Batch(self.deck, list(self.sets), runs, self.jobs, self.allow_large, cases)
            records, interrupted = self.ranks.run(job)
        if interrupted:
            raise KeyboardInterrupt
        by_folder = {}
        for rec in records:
            values = unique[rec["folder"]]
            by_folder[rec["folder"]] = RunRecord(
                [float(v) for v in values], rec["folder"], rec["status"], rec["wall_s"],
                rec["status"] == "skipped-done", rec.get("rank", 0),
            )  # fmt: skip
        batch = list(by_folder.values())
        self.log.extend(batch)
        if self.on_batch is not None:
            self.on_batch(batch)
        return [by_folder[run_folder(self.params, v)] for v in points]


def evaluate_batch(
    runner: Runner,
    points: list[list[float]],
    residual_of: Callable[[Path], NDArray[np.float64]],
    strict: bool,
) -> list[NDArray[np.float64] | None]:
    """Residual vectors of parameter vectors: ``None`` for a run that did not complete
    (``strict``: raise :class:`CalibrationError` naming its folder and run.log)."""
    out: list[NDArray[np.float64] | None] = []
    for rec in runner.run(points):
        folder = runner.out / "runs" / rec.folder
        if rec.status not in ("completed", "skipped-done"):
            if strict:
                raise CalibrationError(
                    f"calibrate: the run with {_values_text(runner.params, rec.values)} "
                    f"{rec.status}; see {folder / 'run.log'} (narrow the bounds, or use "
                    "options.method: global, which scores such runs as bad fits)"
                )
            out.append(None)
            continue
        out.append(residual_of(folder))
    return out


def _values_text(params: list[Parameter], values: list[float]) -> str:
    return ", ".join(f"{p.key}={v:.6g}" for p, v in zip(params, values, strict=True))


def summary_of(runner: Runner) -> dict[str, Any]:
    """Counts and wall time of the runs."""
    made = [r for r in runner.log if not r.cached]
    ranks = 1 if runner.ranks is None else runner.ranks.size
    return {
        "runs": len(made),
        "runs_read_back": len(runner.log) - len(made),
        "runs_wall_s": float(sum(r.wall_s or 0.0 for r in made)),
        "failed": sum(1 for r in runner.log if r.status not in ("completed", "skipped-done")),
        "mpi_ranks": ranks,
        "runs_by_rank": [sum(1 for r in made if r.rank == k) for k in range(ranks)],
    }
