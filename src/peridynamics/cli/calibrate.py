"""``peridynamics calibrate``: fit deck values to measured data (the application layer
does it: :mod:`peridynamics.app.calibrate`)."""

from __future__ import annotations

import argparse
from typing import Any

from peridynamics.app.exit_codes import EXIT_INVALID
from peridynamics.cli.common import deck_args, large_arg, out_folder_problem


def cmd_calibrate(args: argparse.Namespace) -> int:
    """Fit the parameters of a calibration file (``peridynamics.app.calibrate``)."""
    from peridynamics.app.calibrate import cmd_calibrate as run_calibrate

    if out_folder_problem(args.out, "--out"):
        return EXIT_INVALID
    return run_calibrate(args)


def cmd_band(args: argparse.Namespace) -> int:
    """Prediction band of a history curve over runs (``peridynamics.app.prediction_band``)."""
    from peridynamics.app.prediction_band import cmd_band as run_band

    return run_band(args)


def _levels(text: str) -> list[float]:
    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r}: comma-separated percentiles, e.g. 5,50,95"
        ) from None


def register(sub: Any) -> None:
    """The parsers of ``calibrate`` and ``band``."""
    cp = sub.add_parser(
        "calibrate",
        help="fit deck values to measured curves or scalars (docs/calibration.md)",
        description="Fit the deck values named in a calibration file (parameters with "
        "bounds and scale), or by --fit flags, to measured data (targets: a history "
        "curve or a summary scalar); every trial is a run in DIR/runs, run in parallel "
        "(--jobs processes; under mpiexec -n N on all ranks) and read back when the "
        "calibration is started again. Writes report.md, "
        "report.json, fit.png, fit_<target>.csv, runs.csv and fitted_deck.yaml.",
        epilog="exit codes:\n  0    done\n  2    bad arguments, calibration file, data or "
        "deck (nothing fitted)\n  130  interrupted (Ctrl-C or SIGTERM): run the same "
        "command again to continue",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    deck_args(cp)
    cp.add_argument(
        "calibration",
        nargs="?",
        help="calibration file (YAML; docs/calibration.md); or leave it out and give "
        "--data, --fit, --x, --y",
    )
    fl = cp.add_argument_group(
        "flag form (no calibration file; one measured curve)",
        "the same fit as a calibration file with one curve target; the file built is "
        "written to DIR/calibration.yml",
    )
    fl.add_argument("--data", metavar="CSV", help="the measured curve (a header row)")
    fl.add_argument(
        "--fit",
        action="append",
        metavar="KEY[=LO:HI[:log]]",
        help="a deck value to fit (dotted key as for --set), repeat or separate by commas; "
        "without bounds: [0.5, 2] x the deck value; starts from the deck value",
    )
    fl.add_argument(
        "--x",
        metavar="SIM=COLUMN",
        help="abscissa: history.csv columns (probes; a sum like 'a - b') = the CSV column; "
        "a unit [mm] in the CSV header or after COLUMN is converted to SI",
    )
    fl.add_argument(
        "--y", metavar="SIM=COLUMN", help="ordinate, as --x, e.g. '-1 * reaction=load [kN]'"
    )
    fl.add_argument("--sigma", metavar="COLUMN", help="CSV column of the standard deviation of y")
    fl.add_argument(
        "--monotone", action="store_true", help="cut both curves where x first decreases"
    )
    cp.add_argument("--jobs", type=int, metavar="N", help="runs at a time (options.jobs)")
    cp.add_argument(
        "--method", choices=("least_squares", "global"), help="the optimiser (options.method)"
    )
    cp.add_argument("--restarts", type=int, metavar="N", help="options.restarts")
    cp.add_argument("--max-runs", type=int, metavar="N", help="options.max_runs")
    cp.add_argument(
        "--sobol",
        type=int,
        metavar="N",
        help="instead of fitting: Sobol' indices of the misfit and of each target over the "
        "bounds from N (n + 2) runs (N a power of 2; needs SALib)",
    )
    cp.add_argument(
        "-o", "--out", metavar="DIR", help="output folder (default results/<name>_calibration)"
    )
    cp.add_argument("--quiet", action="store_true", help="no progress lines or report")
    large_arg(cp)
    cp.set_defaults(func=cmd_calibrate)

    bp = sub.add_parser(
        "band",
        help="prediction band of a history curve over the runs of an ensemble, sweep or "
        "calibration (docs/calibration.md)",
        description="Percentiles (default 5, 50, 95) of a history curve over every completed "
        "run below FOLDER, on a common x grid; writes band.csv, band.json, band.png there.",
    )
    bp.add_argument("folder", help="an ensemble, sweep or calibration folder")
    bp.add_argument("--x", required=True, help="history.csv column(s), e.g. strain")
    bp.add_argument("--y", required=True, help="history.csv column(s), e.g. stress")
    bp.add_argument("--levels", type=_levels, default=[5.0, 50.0, 95.0], metavar="P,P,...")
    bp.add_argument("--points", type=int, default=101, help="points of the x grid")
    bp.add_argument("--extend", action="store_true", help="grid up to the largest x of any run")
    bp.add_argument(
        "--monotone", action="store_true", help="cut each curve where x first decreases"
    )
    bp.add_argument("--quiet", action="store_true")
    bp.set_defaults(func=cmd_band)
