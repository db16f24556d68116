"""``peridynamics ensemble``: N Weibull realisations of a deck (seeds seed0 .. seed0 + N - 1)
and the spread of the peak stress and of the damaged area (``ensemble.json``,
docs/output.md), on one process or spread over the ranks of ``mpiexec -n R``.

Each realisation is an ordinary one-process run, ``Simulation.from_deck(member).run(
out / f"seed_{seed}", quiet=True)``; the seed, not the rank, determines it, so the runs and
their files are the same on any number of ranks.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from peridynamics.app.checks import (
    built_problem,
    err,
    load_from_args,
    out_of_memory,
    refuse,
    size_problem,
)
from peridynamics.app.exit_codes import EXIT_INTERRUPTED, EXIT_INVALID, EXIT_OK, EXIT_UNSTABLE
from peridynamics.parallel.launch import LaunchError, mpi_comm, share_cores


class Problem(NamedTuple):
    """Why a rank stopped: the exit code and the message for stderr."""

    seed: int
    code: int
    message: str
    #: an interruption: the message ends with the number of runs done (all ranks)
    interrupted: bool = False


def _said(report: Callable[..., int], *args: Any) -> tuple[int, str]:
    """The exit code of one of the CLI's reporting helpers and what it wrote to stderr."""
    buf = io.StringIO()
    with contextlib.redirect_stderr(buf):
        code = report(*args)
    return code, buf.getvalue()


def assign(n: int, ranks: int, rank: int) -> list[int]:
    """Realisations (0 .. n - 1) run by ``rank`` of ``ranks``: k goes to rank k % ranks.

    Round robin, not the cost-balanced assignment of ``peridynamics sweep``: every
    realisation is the same deck with another seed (same points, bonds and steps), so the
    costs are equal and round robin balances them; it is also fixed by n and the ranks
    alone, with no cost estimate or communication.
    """
    return list(range(rank, n, ranks))


def _check(args: argparse.Namespace) -> tuple[Any, int]:
    """The deck if the command can run (code 0), else ``None`` and the exit code; the
    reasons go to stderr."""
    if args.n < 1:
        err("--n must be >= 1")
        return None, EXIT_INVALID
    deck = load_from_args(args)
    if deck is None:
        return None, EXIT_INVALID
    if deck.damage.weibull is None:
        err("ensemble: the deck has no damage.weibull section (nothing to vary)")
        return None, EXIT_INVALID
    problem = size_problem(deck, args.allow_large)
    if problem:
        return None, refuse(problem)
    return deck, 0


def _run_members(
    args: argparse.Namespace, out: Path, seeds: list[int], prefix: str, catch_ctrl_c: bool
) -> tuple[list[dict[str, Any]], Problem | None]:
    """Run the realisations of ``seeds`` one after the other; stop at the first problem."""
    from peridynamics.app.run import RunInterrupted, Simulation
    from peridynamics.build.errors import SetupError
    from peridynamics.deck import DeckError, load_deck
    from peridynamics.solvers import SimulationUnstable

    runs: list[dict[str, Any]] = []
    for seed in seeds:
        try:
            member = load_deck(args.deck, [*(args.set or []), f"damage.weibull.seed={seed}"])
            sim = Simulation.from_deck(member)
            problem = built_problem(sim, args.allow_large)
            if problem:
                return runs, Problem(seed, *_said(refuse, problem))
            summary = sim.run(out / f"seed_{seed}", quiet=True)
        except (DeckError, SetupError) as exc:
            return runs, Problem(seed, *_said(refuse, str(exc)))
        except MemoryError as exc:
            return runs, Problem(seed, *_said(out_of_memory, exc))
        except SimulationUnstable as exc:
            return runs, Problem(seed, EXIT_UNSTABLE, f"error (seed {seed}): {exc}\n")
        except RunInterrupted as exc:
            text = f"interrupted in seed {seed} after step {exc.step}"
            return runs, Problem(seed, EXIT_INTERRUPTED, text, interrupted=True)
        except KeyboardInterrupt:  # Ctrl-C in a set-up, or a second one: stop this rank
            if not catch_ctrl_c:
                raise
            text = f"interrupted (Ctrl-C) in seed {seed}"
            return runs, Problem(seed, EXIT_INTERRUPTED, text, interrupted=True)
        r = summary["results"]
        runs.append(
            {
                "seed": seed,
                "peak_stress_Pa": r.get("peak_stress_Pa"),
                "damaged_area_fraction": r["damaged_area_fraction"],
                "wall_s": summary["timing"]["wall_s"],
            }
        )
        if not args.quiet:
            peak = r.get("peak_stress_Pa")
            print(
                f"{prefix}seed {seed}: peak stress "
                f"{'n/a (no output.stress_strain)' if peak is None else f'{peak:.4g} Pa'}, "
                f"damaged area fraction {r['damaged_area_fraction']:.4f}",
                flush=True,
            )
    return runs, None


def _spread(runs: list[dict[str, Any]], key: str) -> dict[str, float | None] | None:
    vals = np.array([r[key] for r in runs if r[key] is not None], dtype=float)
    if vals.size == 0:
        return None
    many = vals.size > 1  # a sample standard deviation needs two runs
    std = float(vals.std(ddof=1)) if many else None
    return {
        "mean": float(vals.mean()),
        "std": std,
        "min": float(vals.min()),
        "max": float(vals.max()),
        "cv": std / float(vals.mean()) if std is not None and vals.mean() else None,
    }


def _finish(
    args: argparse.Namespace, out: Path, runs: list[dict[str, Any]], problem: Problem | None,
    ranks: int,
) -> int:  # fmt: skip
    """Report the first problem, or write ensemble.json and print the spread."""
    if problem is not None:
        done = f"; {len(runs)} run(s) done\n" if problem.interrupted else ""
        sys.stderr.write(problem.message + done)
        sys.stderr.flush()
        return problem.code
    report: dict[str, Any] = {"deck": str(args.deck), "n": args.n}
    if ranks > 1:
        report["ranks"] = ranks
    report |= {
        "seeds": [r["seed"] for r in runs],
        "peak_stress_Pa": _spread(runs, "peak_stress_Pa"),
        "damaged_area_fraction": _spread(runs, "damaged_area_fraction"),
        "runs": runs,
    }
    out.mkdir(parents=True, exist_ok=True)
    (out / "ensemble.json").write_text(json.dumps(report, indent=2))
    if not args.quiet:
        for key, label, unit, fmt in (
            ("peak_stress_Pa", "peak stress", " Pa", ".4g"),
            ("damaged_area_fraction", "damaged area fraction", "", ".4f"),
        ):
            sp = report[key]
            if sp is None:
                continue
            std = "n/a (n = 1)" if sp["std"] is None else f"{sp['std']:{fmt}}{unit}"
            cv = "n/a" if sp["cv"] is None else f"{sp['cv']:.3g}"
            print(
                f"{label}: mean {sp['mean']:{fmt}}{unit}, std {std}, cv {cv}, "
                f"range {sp['min']:{fmt}} .. {sp['max']:{fmt}}{unit}"
            )
        print(f"wrote {out / 'ensemble.json'}", flush=True)
    return EXIT_OK


def cmd_ensemble(args: argparse.Namespace) -> int:
    """Run the realisations (see the module docstring); under ``mpiexec -n R`` realisation
    k runs on rank k % R (:func:`assign`) and rank 0 gathers the runs, sorted by seed,
    writes ensemble.json (with ``"ranks": R``) and reports. Every rank checks the deck
    before anything runs; a problem on any rank (invalid deck, unstable run, Ctrl-C) is
    gathered with the runs, rank 0 reports the first one (lowest seed) and every rank
    returns the same exit code: 0, 2 invalid, 3 unstable, 130 interrupted."""
    try:
        comm = mpi_comm()
    except LaunchError as exc:
        print(f"ensemble: {exc}", file=sys.stderr)
        return EXIT_INVALID
    rank, ranks = (0, 1) if comm is None else (comm.Get_rank(), comm.Get_size())

    # every rank checks (memory may differ by machine); rank 0 speaks
    buf = io.StringIO()
    with contextlib.redirect_stderr(buf):
        deck, code = _check(args)
    said = buf.getvalue()
    if comm is not None:
        checks = comm.allgather((code, said))
        code, said = next((c for c in checks if c[0]), checks[0])
    if rank == 0:
        sys.stderr.write(said)
        sys.stderr.flush()
    if code:
        return code
    out = Path(args.out or Path("results") / f"{deck.name}_ensemble")
    if comm is None:
        runs, problem = _run_members(args, out, [args.seed0 + k for k in range(args.n)], "",
                                     catch_ctrl_c=False)  # fmt: skip
        return _finish(args, out, runs, problem, 1)

    threads = share_cores(comm)  # ranks on one machine share its cores
    if rank == 0 and not args.quiet:
        print(
            f"{deck.name}: {args.n} realisation(s) over {ranks} MPI ranks "
            f"({threads} Numba thread(s) each) -> {out}",
            flush=True,
        )
    seeds = [args.seed0 + k for k in assign(args.n, ranks, rank)]
    runs, problem = _run_members(args, out, seeds, f"rank {rank}: ", catch_ctrl_c=True)
    gathered = comm.gather((runs, problem), root=0)
    if rank != 0:
        return int(comm.bcast(None, root=0))
    code = EXIT_INVALID  # if the report itself fails, the other ranks must not wait
    try:
        runs = sorted((r for part, _ in gathered for r in part), key=lambda r: r["seed"])
        problems = [p for _, p in gathered if p is not None]
        first = min(problems, key=lambda p: p.seed) if problems else None
        code = _finish(args, out, runs, first, ranks)
    finally:
        comm.bcast(code, root=0)
    return code
