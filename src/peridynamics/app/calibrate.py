"""``peridynamics calibrate``: fit deck values to measured curves or scalars
(docs/calibration.md).

A calibration file (:mod:`peridynamics.app.calibrate_spec`) names the parameters (deck
keys with bounds and a scale), the targets (a simulated history curve or a summary
scalar against measured data, :mod:`peridynamics.app.calibrate_data`) and the optimiser
(:mod:`peridynamics.app.calibrate_fit`). Each parameter vector is one ``peridynamics
run`` in ``DIR/runs/run_<hash>``, run by the sweep machinery in parallel processes
(:mod:`peridynamics.app.calibrate_runs`), under ``mpiexec -n N`` on all ranks while rank
0 runs the optimiser (:mod:`peridynamics.app.calibrate_mpi`); a calibration started
again over the same folder reads back the runs it has. The outputs
(:mod:`peridynamics.app.calibrate_report`) are ``report.json``, ``report.md``,
``fit.png``, ``fit_<target>.csv``, ``fitted_deck.yaml`` and ``runs.csv`` (every run:
values, cost, status).
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path
from typing import Any

import numpy as np

from peridynamics.app.calibrate_data import load_targets, residuals
from peridynamics.app.calibrate_fit import Objective, optimise, uncertainty
from peridynamics.app.calibrate_mpi import Ranks, serve
from peridynamics.app.calibrate_report import (
    fitted_deck,
    markdown,
    plot_fit,
    write_curves,
    write_json,
)
from peridynamics.app.calibrate_runs import Runner, evaluate_batch, run_folder, summary_of
from peridynamics.app.calibrate_spec import (
    CalibrationError,
    CalibrationSpec,
    load_spec,
    parse_spec,
)
from peridynamics.app.checks import err
from peridynamics.app.exit_codes import EXIT_INTERRUPTED, EXIT_INVALID, EXIT_OK
from peridynamics.app.sweep_run import sigterm_as_interrupt
from peridynamics.parallel.launch import LaunchError, mpi_comm


def _runs_csv(path: Path, obj: Objective, runner: Runner) -> None:
    """``runs.csv``: every point evaluated (physical values, cost, folder)."""
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow([p.key for p in obj.params] + ["cost", "folder"])
        for z, r in obj.memo.items():
            values = obj.physical(np.array(z))
            cost = "" if r is None else repr(0.5 * float(r @ r))
            w.writerow([repr(v) for v in values] + [cost, run_folder(obj.params, values)])


def calibrate(
    spec: CalibrationSpec,
    deck: Path,
    out: Path,
    base: Path,
    sets: list[str] | None = None,
    quiet: bool = False,
    allow_large: bool = False,
    spec_name: str = "",
    ranks: Ranks | None = None,
) -> dict[str, Any]:
    """Fit ``spec.parameters`` of ``deck`` to ``spec.targets``; write the outputs to
    ``out`` and return the report (``report.json``).

    Parameters
    ----------
    spec
        The validated calibration file.
    deck
        The deck file.
    out
        The calibration folder (runs in ``out/runs``; reused when it exists).
    base
        Folder that relative data paths of the targets start from.
    sets
        Extra ``--set`` overrides of every run (after ``spec.set``).
    ranks
        Under ``mpiexec -n N`` (on rank 0; the others
        :func:`~peridynamics.app.calibrate_mpi.serve`): every batch of runs is divided
        among the ranks.

    Raises
    ------
    CalibrationError
        Bad data or targets, an invalid deck with the parameters applied, a failed run
        in least squares, or no completed run.
    """
    t0 = time.perf_counter()
    targets = load_targets(spec.targets, base)
    params = spec.parameters
    all_sets = [*spec.set, *(sets or [])]
    out.mkdir(parents=True, exist_ok=True)
    runner = Runner(deck, all_sets, params, out, spec.options.jobs, quiet, allow_large,
                    ranks=ranks)  # fmt: skip

    def progress(batch: list[Any]) -> None:
        if not quiet:
            made = sum(1 for r in batch if not r.cached)
            print(f"calibrate: batch of {len(batch)} run(s) ({made} new, "
                  f"{len(batch) - made} read back); {runner.runs} run(s) so far",
                  flush=True)  # fmt: skip

    runner.on_batch = progress
    strict = spec.options.method == "least_squares"

    def batch(points: list[list[float]]) -> list[Any]:
        return evaluate_batch(runner, points, lambda f: residuals(f, targets)[0], strict)

    obj = Objective(params, batch, spec.options.max_runs)
    try:
        z_best, info = optimise(obj, spec.options)
    finally:
        if obj.memo:
            _runs_csv(out / "runs.csv", obj, runner)
    values = obj.physical(z_best)
    obj.max_runs += len(params)  # the Jacobian at the optimum is always computed
    jac = obj.jacobian(z_best, spec.options.fd_step)
    folder = out / "runs" / run_folder(params, values)
    res, fitted = residuals(folder, targets)
    unc = uncertainty(params, values, jac, res, spec.options.confidence)
    _runs_csv(out / "runs.csv", obj, runner)
    per_target: dict[str, Any] = {}
    start = 0
    for td in targets:
        r = res[start : start + td.size]
        start += td.size
        per_target[td.spec.name] = {
            "n": td.size, "rms": float(np.sqrt(np.mean(r**2))), **fitted[td.spec.name],
        }  # fmt: skip
    fitted_deck(deck, all_sets, params, values, out / "fitted_deck.yaml")
    files = write_curves(out, folder, targets, fitted)
    drawn = plot_fit(out / "fit.png", folder, targets, fitted, f"{deck.stem}: calibration")
    report: dict[str, Any] = {
        "deck": str(deck), "deck_name": deck.stem, "calibration_file": spec_name,
        "parameters": {p.key: v for p, v in zip(params, values, strict=True)},
        "uncertainty": unc, "optimiser": info,
        "misfit": {"cost": 0.5 * float(res @ res), "rms": float(np.sqrt(np.mean(res**2)))},
        "targets": per_target, "runs": summary_of(runner),
        "fitted_run": str(folder.relative_to(out)), "figure": "fit.png" if drawn else None,
        "files": ["report.json", "report.md", "runs.csv", "fitted_deck.yaml", *files]
        + (["fit.png"] if drawn else []),
        "wall_s": time.perf_counter() - t0,
    }  # fmt: skip
    write_json(out / "report.json", report)
    (out / "report.md").write_text(markdown(report), encoding="utf-8")
    return report


def _spec_of(args: argparse.Namespace) -> tuple[CalibrationSpec, Path, str, dict | None]:
    """The calibration of the command line: the file's (CAL.yml, with the option flags
    applied) or the flags' (:mod:`peridynamics.app.calibrate_flags`); its base folder
    of relative data paths, its name in the report, and the flags' mapping."""
    from peridynamics.app.calibrate_flags import flag_form, spec_from_flags

    flags = flag_form(args)
    if flags == (args.calibration is not None):
        raise CalibrationError(
            "give a calibration file (peridynamics calibrate DECK CAL.yml) or the flags "
            "--data, --fit, --x, --y (docs/calibration.md), not both"
            if flags else "give a calibration file CAL.yml, or --data CSV --fit KEY "
            "--x SIM=COLUMN --y SIM=COLUMN (docs/calibration.md)"
        )  # fmt: skip
    if flags:
        if not Path(args.deck).is_file():
            raise CalibrationError(f"no deck file {args.deck!r}")
        spec, data, notes = spec_from_flags(args, Path(args.deck))
        if not args.quiet:
            for note in notes:
                print(f"calibrate: {note}", flush=True)
        return spec, Path.cwd(), "flags", data
    spec = load_spec(args.calibration)
    updates: dict[str, Any] = {}
    for opt in ("jobs", "method", "restarts", "max_runs"):
        if getattr(args, opt, None) is not None:
            updates[opt] = getattr(args, opt)
    if updates:
        data = spec.model_dump()
        data["options"] = {**data["options"], **updates}
        spec = parse_spec(data, "options given on the command line")
    path = Path(args.calibration).resolve()
    return spec, path.parent, str(path), None


def cmd_calibrate(args: argparse.Namespace) -> int:
    """Run a calibration (module docstring); exit 0 done, 2 bad input, 130 interrupted.
    The flag form writes the calibration file it built to ``DIR/calibration.yml``.
    Under ``mpiexec -n N`` rank 0 does all of that and the other ranks run their share
    of each batch of runs; every rank exits with rank 0's code."""
    try:
        comm = mpi_comm()
    except LaunchError as exc:
        err(f"calibrate: {exc}")
        return EXIT_INVALID
    if comm is None:
        return _calibrate_command(args, None)
    ranks = Ranks.of(comm)
    if ranks.rank != 0:
        return serve(ranks)
    code = 1  # an unexpected error: the other ranks still stop
    try:
        with sigterm_as_interrupt():
            code = _calibrate_command(args, ranks)
    finally:
        ranks.stop(code)
    return code


def _calibrate_command(args: argparse.Namespace, ranks: Ranks | None) -> int:
    """:func:`cmd_calibrate` on one process, or on rank 0 with ``ranks``."""
    try:
        spec, base, spec_name, flag_data = _spec_of(args)
        if not Path(args.deck).is_file():
            raise CalibrationError(f"no deck file {args.deck!r}")
        deck = Path(args.deck).resolve()
        out = Path(args.out or Path("results") / f"{deck.stem}_calibration").resolve()
        if flag_data is not None:
            import yaml

            out.mkdir(parents=True, exist_ok=True)
            spec_name = str(out / "calibration.yml")
            text = yaml.safe_dump(flag_data, sort_keys=False, allow_unicode=True)
            Path(spec_name).write_text(
                "# built by peridynamics calibrate from its flags: run it again with\n"
                f"# peridynamics calibrate {args.deck} {spec_name}\n" + text,
                encoding="utf-8",
            )
        if getattr(args, "sobol", None) is not None:
            from peridynamics.app.calibrate_sobol import run_sobol

            result = run_sobol(spec, deck, out, base, args.sobol, args.set, args.quiet,
                               args.allow_large, ranks)  # fmt: skip
            if not args.quiet:
                print(f"Sobol' indices of {len(result['outputs'])} output(s) from "
                      f"{result['samples']} runs: wrote {out / 'sobol.json'}, "
                      f"{out / 'sobol.csv'}, {out / 'sobol.png'}")  # fmt: skip
            return EXIT_OK
        report = calibrate(spec, deck, out, base, args.set, args.quiet, args.allow_large,
                           spec_name, ranks)  # fmt: skip
    except CalibrationError as exc:
        err(str(exc))
        return EXIT_INVALID
    except KeyboardInterrupt:
        err("calibrate: interrupted; run the same command again: the finished runs are "
            "read back, not run again")  # fmt: skip
        return EXIT_INTERRUPTED
    if not args.quiet:
        print((out / "report.md").read_text(encoding="utf-8"))
        print(f"wrote {out / 'report.md'}, {out / 'report.json'}")
    return EXIT_OK if report else EXIT_INVALID
