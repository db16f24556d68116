"""``peridynamics run`` and ``peridynamics check``: run a deck (serial or under
``mpiexec``), or validate it and build its geometry (and bonds) without running."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path
from typing import Any

from peridynamics.app.checks import (
    build_checked,
    built_problem,
    err,
    invalid_deck,
    load_from_args,
    out_of_memory,
    refuse,
    size_problem,
    work_problem,
)
from peridynamics.app.exit_codes import EXIT_INVALID, EXIT_OK, EXIT_UNSTABLE, exit_for_signal
from peridynamics.app.run_progress import signal_name
from peridynamics.build.estimates import estimate_size, estimate_steps
from peridynamics.cli.common import (
    EXIT_CODES,
    HELP_TOPICS,
    deck_args,
    large_arg,
    out_folder_problem,
)
from peridynamics.deck import GmshGeometry, MeshGeometry


def cmd_check(args: argparse.Namespace) -> int:
    """Validate a deck and build its geometry and node sets, without running.

    With ``--bonds`` also build the bonds, the model and the solver: the time step is
    then checked against the stable limit as ``run`` would. The size of the model is
    estimated first and a model that cannot fit in memory is refused (exit 2) unless
    ``--allow-large``.
    """
    from peridynamics.app.run import Simulation
    from peridynamics.build.cloud import build_cloud
    from peridynamics.build.errors import SetupError

    deck = load_from_args(args)
    if deck is None:
        return EXIT_INVALID
    try:
        problem = size_problem(deck, args.allow_large)
        if problem:
            return refuse(problem)
        if args.bonds:
            if isinstance(deck.geometry, MeshGeometry | GmshGeometry):  # known once read
                problem = size_problem(deck, args.allow_large, build_cloud(deck).n_points)
                if problem:
                    return refuse(problem)
            sim = Simulation.from_deck(deck)
            problem = built_problem(sim, args.allow_large)
            extra = f", {sim.model.bonds.n_bonds} bonds, {sim.solver.describe()}"
            n_points = sim.cloud.n_points
        else:
            n_points, extra = build_cloud(deck).n_points, ""
            est = estimate_size(deck, n_points)
            problem = size_problem(deck, args.allow_large, n_points)
            if problem is None and est is not None:
                problem = work_problem(estimate_steps(deck), est.bonds, args.allow_large, True)
        if problem:
            return refuse(problem)
    except SetupError as exc:
        err(invalid_deck(exc))
        return EXIT_INVALID
    except MemoryError as exc:
        return out_of_memory(exc)
    print(f"{args.deck}: valid ({deck.dim}-D, {n_points} points{extra})")
    _notes(deck)
    return EXIT_OK


def _notes(deck: Any) -> None:
    """``note:`` lines for the changed defaults the deck relies on."""
    from peridynamics.deck.changed_defaults import notices

    for line in notices(deck):
        err(f"note: {line}")


def _resume_hint(args: argparse.Namespace, out: Path) -> str:
    sets = "".join(f" --set {shlex.quote(s)}" for s in args.set or [])
    return f"peridynamics run {shlex.quote(str(args.deck))} --resume {shlex.quote(str(out))}{sets}"


def _bad_run_args(args: argparse.Namespace) -> bool:
    """Print what is wrong with the options of ``run`` (``True`` when something is)."""
    if args.resume and args.out:
        err("give either --out DIR (a new run) or --resume DIR (continue the run in DIR)")
        return True
    if args.checkpoint_every is not None and args.checkpoint_every < 0:
        err("--checkpoint-every must be >= 0 (0: no checkpoints)")
        return True
    if args.resume and not Path(args.resume).is_dir():
        err(f"--resume: no run folder {args.resume!r}")
        return True
    return out_folder_problem(args.out, "--out")


def _announce(deck: Any, sim: Any, out: Path) -> None:
    """The line printed before a run: points, bonds, solver, ranks, output folder."""
    where = ""
    n_points, n_bonds = sim.cloud.n_points, sim.model.bonds.n_bonds
    if sim.session is not None:
        where = f" on {sim.session.comm.size} MPI ranks"
        n_points = sim.session.global_cloud.n_points
        n_bonds = sim.global_bonds()
    print(
        f"{deck.name}: {n_points} points, {n_bonds} bonds, {sim.solver.describe()}{where} -> {out}"
    )


def _interrupted(exc: Any, args: argparse.Namespace, out: Path, rank: int) -> int:
    """Report a run stopped by Ctrl-C or a stop signal (rank 0) and how to resume it;
    the exit code is 128 + the signal's number (130 for Ctrl-C, 143 for SIGTERM)."""
    code = exit_for_signal(exc.signum)
    if rank != 0:
        return code
    err(
        f"interrupted after step {exc.step} of {exc.total} (t = {exc.t:.6g} s, "
        f'{signal_name(exc.signum)}); wrote {out / "summary.json"} (status "interrupted")'
    )
    if exc.checkpoint is not None:
        err(f"checkpoint: {exc.checkpoint}\nresume with: {_resume_hint(args, out)}")
    else:
        err(
            "no checkpoint (checkpointing is off): run with --checkpoint-every N "
            "to be able to resume an interrupted run"
        )
    return code


def _done(args: argparse.Namespace, out: Path, summary: dict[str, Any]) -> None:
    """The closing line of a run, and a warning when a static solve did not converge."""
    if not args.quiet:
        r, t = summary["results"], summary["timing"]
        print(
            f"done: {t['steps']} steps in {t['wall_s']:.2f} s "
            f"({t['bond_updates_per_s']:.3g} bond updates/s); max damage "
            f"{r['max_damage']:.3f}; wrote {out / 'summary.json'}"
        )
    if summary["results"].get("converged") is False:  # adr / static: reported, not an error
        r = summary["results"]
        steps = r.get("not_converged_load_steps")
        err(
            "warning: the static solve did not converge"
            + (f" in load steps {steps}" if steps else "")
            + f": {r.get('message') or 'see summary.json'} (results.converged is false)"
        )


def cmd_run(args: argparse.Namespace) -> int:
    """Run a deck."""
    from peridynamics.app.run import RunInterrupted
    from peridynamics.build.errors import SetupError
    from peridynamics.solvers import SimulationUnstable
    from peridynamics.solvers.linear import UnconstrainedModel

    if _bad_run_args(args):
        return EXIT_INVALID
    if getattr(args, "backend", None):
        args.set = [*(args.set or []), f"solver.backend={args.backend}"]
    deck = load_from_args(args)
    if deck is None:
        return EXIT_INVALID
    out = Path(args.resume or args.out or Path("results") / deck.name)
    if out_folder_problem(str(out), "--resume" if args.resume else "--out", create=True):
        return EXIT_INVALID
    every = args.checkpoint_every if args.resume else (args.checkpoint_every or 0)
    comm = _run_comm()
    if comm is False:
        return EXIT_INVALID
    rank = 0 if comm is None else int(comm.Get_rank())
    quiet = args.quiet or rank != 0  # under mpiexec rank 0 speaks
    try:
        sim, problem = build_checked(deck, comm, args.allow_large)
        if problem:  # before the build rank 0 speaks; after it, every rank as before
            return refuse(problem) if sim is not None or rank == 0 else EXIT_INVALID
        if not quiet:
            _notes(deck)
            _announce(deck, sim, out)
        elif sim.session is not None:
            sim.global_bonds()  # collective: every rank takes part
        summary = sim.run(out, quiet=quiet, checkpoint_every=every, resume=bool(args.resume))
        if rank != 0:
            return EXIT_OK
    except (SetupError, UnconstrainedModel) as exc:
        if rank == 0:
            err(f"error: {exc}" if exc.path.startswith("--") else invalid_deck(exc))
        return EXIT_INVALID
    except OSError as exc:  # no checkpoint, unwritable output folder, ...
        err(f"error: {exc}")
        return EXIT_INVALID
    except MemoryError as exc:
        return out_of_memory(exc)
    except SimulationUnstable as exc:
        if rank == 0:
            err(f"error: {exc}\nwrote {out / 'last_good.vtu'} and {out / 'summary.json'}")
        return EXIT_UNSTABLE
    except RunInterrupted as exc:
        return _interrupted(exc, args, out, rank)
    _done(args, out, summary)
    return EXIT_OK


def _run_comm() -> Any:
    """The MPI communicator of ``mpiexec -n N peridynamics run`` (N > 1), ``None`` for a
    plain run, ``False`` after printing why an MPI launch cannot work. Each rank gets
    its share of the machine's cores as Numba threads (unless NUMBA_NUM_THREADS is set)."""
    from peridynamics.parallel.launch import LaunchError, mpi_comm, share_cores

    try:
        comm = mpi_comm()
    except LaunchError as exc:
        err(f"error: {exc}")
        return False
    share_cores(comm)
    if comm is not None:  # an error on one rank must not leave the others waiting

        def abort(kind: Any, value: Any, tb: Any) -> None:
            sys.__excepthook__(kind, value, tb)
            comm.Abort(1)

        sys.excepthook = abort
    return comm


def register(sub: Any) -> None:
    """The parser of ``run``."""
    r = sub.add_parser(
        "run",
        help="run a deck",
        epilog=EXIT_CODES + "\n\nCtrl-C stops after the current step and writes the outputs "
        "and summary.json;\nwith --checkpoint-every N, resume with --resume DIR.\n\n" + HELP_TOPICS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    deck_args(r)
    r.add_argument("-o", "--out", help="output folder (default results/<name>)")
    r.add_argument("--quiet", action="store_true", help="no progress bar or messages")
    r.add_argument(
        "--checkpoint-every",
        type=int,
        default=None,
        metavar="N",
        help="write an atomic checkpoint every N steps, and one of the final state "
        "(default 0: none; with --resume: the interval of the original run)",
    )
    r.add_argument("--resume", metavar="DIR", help="continue from the checkpoint in DIR")
    r.add_argument(
        "--backend",
        choices=["numba", "warp"],
        help="compute backend of the explicit step (sets solver.backend; warp: pip install "
        "'peridynamics[gpu]', its CUDA device when there is one, else its CPU device)",
    )
    large_arg(r)
    r.set_defaults(func=cmd_run)


def register_check(sub: Any) -> None:
    """The parser of ``check``."""
    c = sub.add_parser("check", help="validate a deck without running (exit 0 valid, 2 not)")
    deck_args(c)
    c.add_argument(
        "--bonds",
        action="store_true",
        help="also build bonds, model and solver (checks the time step)",
    )
    large_arg(c)
    c.set_defaults(func=cmd_check)
