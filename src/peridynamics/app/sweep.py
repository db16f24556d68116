"""``peridynamics sweep``: run a deck over a grid or a list of parameter values, in
parallel local processes or spread over MPI ranks, resumable (docs/sweep.md).

Each case runs as its own process, ``python -m peridynamics run DECK --out DIR/<case>
--quiet --set ...``, so one crashing case cannot take the sweep down; its output goes
to ``<case>/run.log``. ``<case>/case.json`` records the case's fingerprint (the
validated deck, the package version and a mesh file) and its outcome; a rerun of the
same command skips the cases whose summary.json says ``completed`` under a matching
fingerprint, resumes interrupted ones that left a checkpoint, and reruns the rest.
"""

from __future__ import annotations

import argparse
import shlex
from pathlib import Path
from typing import Any

from peridynamics.app.checks import err
from peridynamics.app.exit_codes import EXIT_CASES_FAILED, EXIT_INTERRUPTED, EXIT_INVALID, EXIT_OK
from peridynamics.app.sweep_cases import Case, SweepError, build_cases, validate
from peridynamics.app.sweep_report import (
    counts,
    format_table,
    plot_columns,
    plot_sweep,
    write_csv,
    write_json,
)
from peridynamics.app.sweep_run import Plan, child_env, death_signal, record, run_cases
from peridynamics.parallel.launch import LaunchError
from peridynamics.parallel.launch import mpi_comm as _mpi_comm
from peridynamics.parallel.launch import node_ranks as _node_ranks
from peridynamics.parallel.launch import threads_per_process as _threads


def assign(cases: list[Case], n_ranks: int) -> list[list[Case]]:
    """Static assignment of cases to ranks, largest estimated cost first to the least
    loaded rank (LPT; with equal costs: round-robin).

    Not ``mpi4py.futures.MPICommExecutor``: its rank 0 only hands out work, so
    ``mpiexec -n 2`` would run one case at a time. Here every rank runs cases, so
    ``-n 2`` runs two at a time; the cost estimate (bonds x steps from the deck) keeps a
    grid over the spacing, whose cases differ by orders of magnitude, balanced.
    """
    loads = [0.0] * n_ranks
    out: list[list[Case]] = [[] for _ in range(n_ranks)]
    for case in sorted(cases, key=lambda c: (-c.cost, c.index)):
        r = min(range(n_ranks), key=lambda k: (loads[k], k))
        out[r].append(case)
        loads[r] += case.cost
    return out


# ----------------------------------------------------------------------- the command
def _report(
    args: argparse.Namespace, plan: Plan, cases: list[Case], keys: list[str],
    records: list[dict[str, Any]], ranks: int, final: bool,
) -> None:  # fmt: skip
    """Write sweep.json and sweep.csv (and, when ``final``, sweep.png)."""
    from peridynamics import __version__

    by_index = {r["case"]: r for r in records}
    rows = [by_index.get(c.index) or record(c, "not-started", None, None, False, {})
            for c in cases]  # fmt: skip
    write_csv(plan.out / "sweep.csv", rows, keys)
    info = {
        "deck": str(plan.deck),
        "command": _command(args),
        "set": plan.sets,
        "grid": args.grid or [],
        "cases_file": args.cases,
        "keys": keys,
        "jobs": args.jobs,
        "mpi_ranks": ranks,
        "version": __version__,
        "counts": counts(rows),
        "finished": final,
        "cases": rows,
    }
    write_json(plan.out / "sweep.json", info)
    if not final:
        return
    requested = [c.strip() for c in args.plot.split(",")] if args.plot else None
    cols, missing = plot_columns(rows, requested)
    if missing:
        err(f"--plot: no completed case has a value for {', '.join(missing)}; the columns "
             "are the header of sweep.csv")  # fmt: skip
    title = f"{cases[0].deck_name}: sweep of {len(cases)} cases"
    drawn = plot_sweep(plan.out / "sweep.png", rows, keys, cols, title)
    if not args.quiet:
        print(format_table(rows, cols))
        print(f"wrote {plan.out / 'sweep.csv'}, {plan.out / 'sweep.json'}"
              + (f", {plan.out / 'sweep.png'}" if drawn else ""))  # fmt: skip


def _exit_code(records: list[dict[str, Any]], interrupted: bool) -> int:
    n = counts(records)
    bad = n.get("failed", 0) + n.get("unstable", 0)
    if interrupted:
        err(f"sweep interrupted: {n.get('completed', 0) + n.get('skipped-done', 0)} of "
             f"{len(records)} case(s) done; run the same command again to continue")  # fmt: skip
        return EXIT_INTERRUPTED
    if bad:
        err(f"sweep: {bad} of {len(records)} case(s) did not complete ("
             + ", ".join(f"{n[s]} {s}" for s in ("failed", "unstable") if s in n)
             + "); see sweep.csv and each case's run.log")  # fmt: skip
        return EXIT_CASES_FAILED
    return EXIT_OK


def _command(args: argparse.Namespace) -> str:
    """The sweep's command line, rebuilt from its arguments (for sweep.json)."""
    parts = ["peridynamics", "sweep", str(args.deck)]
    for opt, values in (("--grid", args.grid), ("--set", args.set)):
        for v in values or []:
            parts += [opt, v]
    for opt, value in (
        ("--cases", args.cases),
        ("--jobs", args.jobs),
        ("--out", args.out),
        ("--plot", args.plot),
        ("--checkpoint-every", args.checkpoint_every),
    ):
        if value is not None:
            parts += [opt, str(value)]
    parts += [f for f, on in (("--quiet", args.quiet), ("--allow-large", args.allow_large)) if on]
    return " ".join(shlex.quote(p) for p in parts)


#: a sweep of more cases says that it validates them (about 1 ms each)
MANY_CASES = 1000


def _prepare(args: argparse.Namespace) -> tuple[list[Case], list[str]]:
    """Check the options, build and validate the cases (raises SweepError)."""
    if args.jobs < 1:
        raise SweepError("--jobs must be >= 1 (cases run at a time on each process)")
    if args.checkpoint_every is not None and args.checkpoint_every < 0:
        raise SweepError("--checkpoint-every must be >= 0 (0: no checkpoints)")
    if args.plot is not None and not all(c.strip() for c in args.plot.split(",")):
        raise SweepError("--plot: comma-separated column names of sweep.csv, e.g. "
                         "--plot max_damage,wall_s")  # fmt: skip
    if not Path(args.deck).is_file():
        raise SweepError(f"no deck file {args.deck!r}")
    cases, keys = build_cases(args.grid, args.cases, args.set or [])
    if len(cases) > MANY_CASES and not args.quiet:  # seconds of validation: say so
        print(f"sweep: validating {len(cases)} cases ...", flush=True)
    problem = validate(args.deck, args.set or [], cases, args.allow_large)
    if problem:
        raise SweepError(problem.removeprefix("sweep: "))
    return cases, keys


def cmd_sweep(args: argparse.Namespace) -> int:
    """Run a deck over the cases of ``--grid`` / ``--cases`` (see the module docstring);
    exit 0 all cases completed, 2 bad input (nothing run), 4 some case failed or went
    unstable, 130 interrupted."""
    comm, rank, ranks, problem = None, 0, 1, None
    cases: list[Case] = []
    keys: list[str] = []
    try:
        comm = _mpi_comm()
    except LaunchError as exc:
        problem = f"sweep: {exc}"
    if comm is not None:
        rank, ranks = comm.Get_rank(), comm.Get_size()
    if problem is None:
        try:
            cases, keys = _prepare(args)
        except SweepError as exc:
            problem = f"sweep: {exc}"
    if comm is not None:  # every rank checks; rank 0 speaks (memory may differ by node)
        problem = next((p for p in comm.allgather(problem) if p), None)
    if problem:
        if rank == 0:
            err(problem)
        return EXIT_INVALID
    out = Path(args.out or Path("results") / f"{cases[0].deck_name}_sweep").resolve()
    if out.exists() and not out.is_dir():
        err(f"--out: {str(out)!r} exists and is not a folder")
        return EXIT_INVALID
    threads = _threads(args.jobs, _node_ranks(comm))
    plan = Plan(
        Path(args.deck).resolve(),
        list(args.set or []),
        out,
        child_env(threads),
        args.checkpoint_every,
        args.allow_large,
        args.quiet,
        prefix=f"rank {rank}: " if comm is not None else "",
        rank=rank,
        preexec=death_signal(),
    )
    if rank == 0 and not args.quiet:
        where = f"{ranks} MPI ranks x {args.jobs}" if comm is not None else str(args.jobs)
        print(
            f"{cases[0].deck_name}: {len(cases)} case(s), {where} at a time "
            f"({plan.env['NUMBA_NUM_THREADS']} Numba thread(s) each) -> {out}",
            flush=True,
        )
        if args.dry_run:
            for c in cases:
                print(f"  {c.folder}: {' '.join('--set ' + shlex.quote(a) for a in c.set_args)}")
    if args.dry_run:
        return EXIT_OK
    out.mkdir(parents=True, exist_ok=True)
    mine = assign(cases, ranks)[rank]
    finished: list[dict[str, Any]] = []

    def on_done(rec: dict[str, Any]) -> None:
        finished.append(rec)
        if not args.quiet and rec["status"] != "not-started":
            wall = "" if rec["wall_s"] is None else f" in {rec['wall_s']:.1f} s"
            skipped = rec["status"] == "skipped-done"
            how = " (done before)" if skipped else wall
            resumed = " (resumed)" if rec["resumed"] and not skipped else ""
            print(
                f"{plan.prefix}[{len(finished)}/{len(mine)}] {rec['folder']}: "
                f"{rec['status']}{how}{resumed}",
                flush=True,
            )
        if comm is None:  # the tables follow the sweep as cases finish
            _report(args, plan, cases, keys, finished, ranks, final=False)

    records, interrupted = run_cases(mine, plan, args.jobs, on_done)
    if comm is not None:
        gathered = comm.gather((records, interrupted), root=0)
        if rank != 0:
            return int(comm.bcast(None, root=0))
        records = sorted((r for part, _ in gathered for r in part), key=lambda r: r["case"])
        interrupted = any(flag for _, flag in gathered)
    _report(args, plan, cases, keys, records, ranks, final=True)
    code = _exit_code(records, interrupted)
    if comm is not None:
        comm.bcast(code, root=0)
    return code
