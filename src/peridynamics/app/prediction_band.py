"""``peridynamics band``: prediction bands of a history curve over the runs of an
ensemble (Weibull realisations), a sweep or a calibration (docs/calibration.md).

Every completed run below a folder (``seed_<k>/`` of an ensemble, ``case_*/`` of a sweep,
``runs/run_*/`` of a calibration: any folder holding a ``history.csv`` and a
``summary.json`` with status ``completed``) gives one curve (x, y), two expressions over
its ``history.csv`` columns as in a calibration target. The curves are interpolated
linearly on a common grid of x (their common range, or up to the largest x with
``--extend``, where the runs that end earlier drop out) and the percentiles of y over
the runs (5, 50 and 95 % by default; ``numpy.percentile``, linear) are the band.
Outputs: ``band.csv`` (x, the count of runs, the percentiles, the mean), ``band.json``
(the runs used, levels) and ``band.png`` (every curve thin, the band shaded).
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.app.calibrate_data import cut_monotone, evaluate_expression, read_table
from peridynamics.app.calibrate_spec import CalibrationError
from peridynamics.app.checks import err
from peridynamics.app.exit_codes import EXIT_INVALID, EXIT_OK


def run_folders(root: Path) -> list[Path]:
    """The completed runs below ``root`` (up to two levels deep), sorted by path."""
    found = []
    for summary in sorted([*root.glob("*/summary.json"), *root.glob("*/*/summary.json")]):
        try:
            status = json.loads(summary.read_text(encoding="utf-8")).get("status")
        except (OSError, ValueError):
            continue
        if status == "completed" and (summary.parent / "history.csv").is_file():
            found.append(summary.parent)
    return found


def curve(folder: Path, x: str, y: str, monotone: bool) -> tuple[NDArray, NDArray]:
    """(x, y) of one run from its history.csv (cut at the first decrease of x if
    ``monotone``)."""
    headers, table = read_table(folder / "history.csv", f"{folder.name}/history.csv")
    xs = evaluate_expression(table, headers, x, "--x")
    ys = evaluate_expression(table, headers, y, "--y")
    return cut_monotone(xs, ys) if monotone else (xs, ys)


def band(
    curves: list[tuple[NDArray, NDArray]], levels: tuple[float, ...] = (5.0, 50.0, 95.0),
    points: int = 101, extend: bool = False,
) -> dict[str, NDArray[np.float64]]:  # fmt: skip
    """Percentiles of y over the curves on a common x grid.

    Parameters
    ----------
    curves
        (x, y) per run, x increasing (a curve is sorted by x first).
    levels
        Percentiles (0-100).
    points
        Grid points.
    extend
        Grid up to the largest x of any run (a run counts where it reaches), instead of
        the range every run covers.

    Returns
    -------
    dict
        ``x`` (points,), ``count`` (points,), ``mean`` (points,) and ``p<level>`` per
        level (points,).
    """
    if not curves:
        raise CalibrationError("no completed run with a history.csv below the folder")
    lo = max(float(c[0].min()) for c in curves)
    hi = (max if extend else min)(float(c[0].max()) for c in curves)
    if not hi > lo:
        raise CalibrationError(
            f"the runs share no range of x ([{lo:g}, {hi:g}]); use --extend or another --x"
        )
    grid = np.linspace(lo, hi, points)
    ys = np.full((len(curves), points), np.nan)
    for k, (cx, cy) in enumerate(curves):
        order = np.argsort(cx, kind="stable")
        inside = grid <= cx.max() + 1e-12 * max(abs(hi), 1e-300)
        ys[k, inside] = np.interp(grid[inside], cx[order], cy[order])
    out: dict[str, NDArray[np.float64]] = {"x": grid, "count": np.sum(~np.isnan(ys), axis=0)}
    out["mean"] = np.nanmean(ys, axis=0)
    for q in levels:
        out[f"p{q:g}"] = np.nanpercentile(ys, q, axis=0)
    out["curves"] = ys
    return out


def write_band(root: Path, result: dict[str, NDArray], runs: list[Path], args: Any) -> list[Path]:
    """``band.csv``, ``band.json`` and ``band.png`` in ``root``."""
    keys = ["x", "count", *[k for k in result if k.startswith("p")], "mean"]
    with (root / "band.csv").open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow([f"x ({args.x})", "count", *keys[2:]])
        for row in zip(*(result[k] for k in keys), strict=True):
            w.writerow([repr(float(v)) for v in row])
    info = {
        "x": args.x, "y": args.y, "levels": list(args.levels), "points": args.points,
        "extend": args.extend, "runs": [str(r.relative_to(root)) for r in runs],
        "n_runs": len(runs),
    }  # fmt: skip
    (root / "band.json").write_text(json.dumps(info, indent=1) + "\n", encoding="utf-8")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4.0))
    for ys in result["curves"]:
        ax.plot(result["x"], ys, color="0.6", lw=0.6)
    lo, hi = f"p{min(args.levels):g}", f"p{max(args.levels):g}"
    ax.fill_between(result["x"], result[lo], result[hi], color="C0", alpha=0.3,
                    label=f"{min(args.levels):g}-{max(args.levels):g} %")  # fmt: skip
    if "p50" in result:
        ax.plot(result["x"], result["p50"], color="C0", label="median")
    ax.set_xlabel(args.x)
    ax.set_ylabel(args.y)
    ax.set_title(f"{root.name}: {len(runs)} runs")
    ax.legend()
    fig.tight_layout()
    fig.savefig(root / "band.png", dpi=120)
    plt.close(fig)
    return [root / "band.csv", root / "band.json", root / "band.png"]


def cmd_band(args: argparse.Namespace) -> int:
    """Prediction band over the runs below ``args.folder``; exit 0, or 2 (bad input)."""
    root = Path(args.folder)
    try:
        if not root.is_dir():
            raise CalibrationError(f"no folder {args.folder!r}: give an ensemble, sweep or "
                                   "calibration folder")  # fmt: skip
        if not all(0 <= q <= 100 for q in args.levels) or len(args.levels) < 2:
            raise CalibrationError("--levels: two or more percentiles in 0..100, e.g. 5,50,95")
        if args.points < 2:
            raise CalibrationError("--points must be >= 2")
        runs = run_folders(root)
        curves = [curve(r, args.x, args.y, args.monotone) for r in runs]
        result = band(curves, tuple(args.levels), args.points, args.extend)
    except CalibrationError as exc:
        err(f"band: {exc}")
        return EXIT_INVALID
    files = write_band(root, result, runs, args)
    if not args.quiet:
        print(f"band of {len(runs)} runs: wrote {', '.join(str(f) for f in files)}")
    return EXIT_OK
