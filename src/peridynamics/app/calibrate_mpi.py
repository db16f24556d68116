"""The runs of a calibration spread over MPI ranks (``mpiexec -n N peridynamics
calibrate``, docs/calibration.md "Running in parallel").

Rank 0 runs the optimiser. Each batch of runs (the columns of a finite-difference
Jacobian, a generation of the global search, the samples of ``--sobol``) is divided among
all ranks by the sweep's :func:`~peridynamics.app.sweep.assign` (largest estimated cost
first, equal costs round-robin); every rank runs its share with the sweep's
:func:`~peridynamics.app.sweep_run.run_cases` (``jobs`` serial ``peridynamics run``
processes at a time, in their folders under ``DIR/runs``), and the records are gathered
on rank 0. The other ranks only serve (:func:`serve`): wait for a batch, run their share,
send back the records, until rank 0 sends the exit code.

The messages are point to point, waited for by polling every 50 ms: a blocking MPI call
(``bcast``, ``gather``) spins at 100 % of a core in MPICH, which would take a core from
the runs, whose processes share the machine with the ranks.

Signals: ``mpiexec`` passes Ctrl-C and SIGTERM on to every rank. While a batch runs, a
signal stops that rank's runs as in a sweep (they write their outputs) and the batch is
reported interrupted; between batches it is remembered and reported with the next batch.
Either way every rank still sends its records, rank 0 stops the calibration (exit 130)
and tells the others, so no rank is left waiting.
"""

from __future__ import annotations

import contextlib
import signal
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from peridynamics.app.sweep import assign
from peridynamics.app.sweep_cases import Case
from peridynamics.app.sweep_run import Plan, child_env, death_signal, record, run_cases
from peridynamics.parallel.launch import node_ranks, threads_per_process

#: message tags: a batch or the exit code (rank 0 to the others), a rank's records
_ORDER, _RECORDS = 1, 2
_POLL_S = 0.05


def _receive(comm: Any, source: int, tag: int) -> Any:
    """A message, waited for without spinning (the module docstring)."""
    while not comm.Iprobe(source=source, tag=tag):
        time.sleep(_POLL_S)
    return comm.recv(source=source, tag=tag)


def runs_plan(deck: Path, sets: list[str], out: Path, jobs: int, allow_large: bool,
              ranks_here: int = 1, rank: int = 0) -> Plan:  # fmt: skip
    """The sweep's plan of a calibration's runs: folders under ``out`` (``DIR/runs``),
    ``jobs`` at a time, each with its share of the cores of this machine (shared by
    ``ranks_here`` ranks), no checkpoints, quiet; ``rank`` goes into the records."""
    threads = threads_per_process(jobs, ranks_here)
    return Plan(deck, list(sets), out, child_env(threads), None, allow_large, True,
                rank=rank, preexec=death_signal())  # fmt: skip


@dataclass
class Batch:
    """What rank 0 sends to every rank for one batch: the plan's inputs and the cases."""

    deck: Path
    sets: list[str]
    out: Path
    jobs: int
    allow_large: bool
    cases: list[Case]


class _Signals:
    """SIGINT and SIGTERM handled so that a rank never leaves the exchange of a batch: while
    ``live`` (its runs are running) a signal raises KeyboardInterrupt, which
    :func:`~peridynamics.app.sweep_run.run_cases` turns into stopping its runs; at any
    other time it is only remembered (``hit``)."""

    def __init__(self) -> None:
        self.live = False
        self.hit = False

    def handler(self, signum: int, frame: Any) -> None:
        self.hit = True
        if self.live:
            raise KeyboardInterrupt

    @contextlib.contextmanager
    def installed(self) -> Iterator[_Signals]:
        old: dict[signal.Signals, Any] = {}
        try:
            for num in (signal.SIGINT, signal.SIGTERM):
                old[num] = signal.signal(num, self.handler)
        except ValueError:  # not the main thread: leave the handlers alone
            pass
        try:
            yield self
        finally:
            for num, handler in old.items():
                signal.signal(num, handler)


def _run_share(cases: list[Case], plan: Plan, jobs: int, sig: _Signals) -> tuple[list, bool]:
    """This rank's cases of a batch: their records and whether it was interrupted (a
    signal now or since the last batch)."""
    records: list[dict[str, Any]] = []
    interrupted = True
    try:
        sig.live = True
        if not sig.hit:
            records, interrupted = run_cases(cases, plan, jobs, lambda rec: None)
        sig.live = False
    except KeyboardInterrupt:  # between run_cases' own handling and live = False
        sig.live = False
    return records, interrupted or sig.hit


@dataclass
class Ranks:
    """The MPI ranks of a calibration: ``comm`` (COMM_WORLD, more than one rank) and the
    number of ranks on this machine (they share its cores)."""

    comm: Any
    here: int = 1

    @classmethod
    def of(cls, comm: Any) -> Ranks:
        """Collective: every rank of ``comm`` calls it at the start."""
        return cls(comm, node_ranks(comm))

    @property
    def rank(self) -> int:
        """This rank."""
        return int(self.comm.Get_rank())

    @property
    def size(self) -> int:
        """The number of ranks."""
        return int(self.comm.Get_size())

    def run(self, batch: Batch) -> tuple[list[dict[str, Any]], bool]:
        """Rank 0: run a batch on all ranks; the records in case order (a case whose
        record was lost to an interruption is ``not-started``) and whether any rank was
        interrupted."""
        sig = _Signals()
        with sig.installed():
            for dest in range(1, self.size):
                self.comm.send(batch, dest=dest, tag=_ORDER)
            plan = runs_plan(batch.deck, batch.sets, batch.out, batch.jobs,
                             batch.allow_large, self.here)  # fmt: skip
            mine = assign(batch.cases, self.size)[0]
            parts = [_run_share(mine, plan, batch.jobs, sig)]
            parts += [_receive(self.comm, src, _RECORDS) for src in range(1, self.size)]
        by_case = {r["case"]: r for part, _ in parts for r in part}
        records = [by_case.get(c.index) or record(c, "not-started", None, None, False, {})
                   for c in sorted(batch.cases, key=lambda c: c.index)]  # fmt: skip
        return records, sig.hit or any(flag for _, flag in parts)

    def stop(self, code: int) -> None:
        """Rank 0: end the calibration on every rank with exit code ``code``."""
        with _Signals().installed():
            for dest in range(1, self.size):
                self.comm.send(code, dest=dest, tag=_ORDER)


def serve(ranks: Ranks) -> int:
    """A rank other than 0: run its share of each batch rank 0 sends until rank 0 sends
    the exit code, which is returned."""
    sig = _Signals()
    with sig.installed():
        while True:
            msg = _receive(ranks.comm, 0, _ORDER)
            if isinstance(msg, int):
                return msg
            plan = runs_plan(msg.deck, msg.sets, msg.out, msg.jobs, msg.allow_large,
                             ranks.here, ranks.rank)  # fmt: skip
            mine = assign(msg.cases, ranks.size)[ranks.rank]
            ranks.comm.send(_run_share(mine, plan, msg.jobs, sig), dest=0, tag=_RECORDS)
