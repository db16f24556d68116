"""``peridynamics ensemble`` and ``peridynamics sweep``: many runs of one deck (the
application layer runs them: :mod:`peridynamics.app.ensemble`,
:mod:`peridynamics.app.sweep`)."""

from __future__ import annotations

import argparse
from typing import Any

from peridynamics.app.exit_codes import EXIT_INVALID
from peridynamics.cli.common import deck_args, large_arg, out_folder_problem


def cmd_ensemble(args: argparse.Namespace) -> int:
    """Run N Weibull realisations of a deck (seeds seed0 .. seed0 + N - 1) and report the
    spread of the peak stress and of the damaged area (``ensemble.json``); under
    ``mpiexec -n R`` the realisations are spread over the R ranks
    (``peridynamics.app.ensemble``)."""
    from peridynamics.app.ensemble import cmd_ensemble as run_ensemble

    if out_folder_problem(args.out, "--out"):
        return EXIT_INVALID
    return run_ensemble(args)


def cmd_sweep(args: argparse.Namespace) -> int:
    """Run a deck over a grid or a list of parameter values (``peridynamics.app.sweep``)."""
    from peridynamics.app.sweep import cmd_sweep as run_sweep

    if out_folder_problem(args.out, "--out"):
        return EXIT_INVALID
    return run_sweep(args)


def register(sub: Any) -> None:
    """The parsers of ``ensemble`` and ``sweep``."""
    en = sub.add_parser(
        "ensemble",
        help="run N Weibull realisations of a deck",
        description="Run N Weibull realisations of a deck; under mpiexec -n R they are "
        "spread over the R ranks (realisation k on rank k % R).",
    )
    deck_args(en)
    en.add_argument("--n", type=int, default=5, help="number of realisations")
    en.add_argument("--seed0", type=int, default=0, help="first seed (then +1, +2, ...)")
    en.add_argument("-o", "--out", help="output folder (default results/<name>_ensemble)")
    en.add_argument("--quiet", action="store_true")
    large_arg(en)
    en.set_defaults(func=cmd_ensemble)

    sw = sub.add_parser(
        "sweep",
        help="run a deck over a grid or a list of parameter values (docs/sweep.md)",
        epilog="exit codes:\n  0    every case completed (or was done before)\n  2    bad "
        "arguments or an invalid case (nothing was run)\n  4    some case failed or went "
        "unstable (the others ran; see sweep.csv)\n  130  interrupted (Ctrl-C or SIGTERM): "
        "run the same command again to continue",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    deck_args(sw)
    sw.add_argument(
        "--grid",
        action="append",
        metavar="KEY.PATH=V1,V2,...",
        help="values of a deck key (repeatable: the cases are the Cartesian product), "
        "e.g. discretisation.spacing=1e-3,5e-4",
    )
    sw.add_argument(
        "--cases", metavar="FILE", help="cases from a file: YAML list of {key.path: value}, or CSV"
    )
    sw.add_argument("--jobs", type=int, default=1, metavar="N", help="cases run at a time")
    sw.add_argument(
        "-o", "--out", metavar="DIR", help="output folder (default results/<name>_sweep)"
    )
    sw.add_argument("--plot", metavar="COL,COL", help="sweep.csv columns drawn in sweep.png")
    sw.add_argument(
        "--checkpoint-every",
        type=int,
        metavar="N",
        help="passed to each run: an interrupted case resumes from its checkpoint",
    )
    sw.add_argument("--dry-run", action="store_true", help="validate and list the cases only")
    sw.add_argument("--quiet", action="store_true", help="no progress lines or table")
    large_arg(sw)
    sw.set_defaults(func=cmd_sweep)
