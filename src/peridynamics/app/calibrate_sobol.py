"""Global sensitivity of a calibration's outputs to its parameters: Sobol' indices with
SALib (the ``--sobol N`` option of ``peridynamics calibrate``, docs/calibration.md;
optional extra ``pip install 'peridynamics[calibration]'``).

The parameters vary independently and uniformly over their bounds in their scale (a
``log`` parameter log-uniformly): Saltelli's sampling of the unit variables (SALib's
``sample.sobol``, N (n + 2) points for n parameters, first and total order), one run
per point in parallel batches through the calibration's runner, and SALib's
``analyze.sobol`` (Saltelli et al. (2010); bootstrap confidence intervals) of each
output: the misfit ``cost`` and each target's RMS weighted residual.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.app.calibrate_spec import CalibrationError, Parameter


def salib() -> tuple[Any, Any]:
    """SALib's ``sample.sobol`` and ``analyze.sobol`` modules, or a CalibrationError that
    says how to install it."""
    try:
        from SALib.analyze import sobol as analyze
        from SALib.sample import sobol as sample
    except ImportError:
        raise CalibrationError(
            "--sobol needs SALib: pip install 'peridynamics[calibration]' (or pip install SALib)"
        ) from None
    return sample, analyze


def sobol_from(
    params: list[Parameter], outputs: Callable[[list[list[float]]], NDArray[np.float64]],
    names: list[str], n: int, seed: int = 0,
) -> dict[str, Any]:  # fmt: skip
    """Sobol' indices of each output.

    Parameters
    ----------
    params
        The parameters (bounds and scales).
    outputs
        Physical parameter vectors (m of them) -> an (m, k) array of outputs (one batch).
    names
        The k output names.
    n
        Base sample size N (a power of 2; N (n_params + 2) evaluations).

    Returns
    -------
    dict
        ``samples`` (evaluations), and per output name per parameter label ``S1``,
        ``S1_conf``, ``ST``, ``ST_conf``.
    """
    if n < 2 or n & (n - 1):
        raise CalibrationError(f"--sobol {n}: give a power of 2 (e.g. 16, 64, 256)")
    sample, analyze = salib()
    labels = [p.label for p in params]
    problem = {"num_vars": len(params), "names": labels, "bounds": [[0.0, 1.0]] * len(params)}
    unit = sample.sample(problem, n, calc_second_order=False, seed=seed)
    points = [[p.from_unit(z) for p, z in zip(params, row, strict=True)] for row in unit]
    ys = np.asarray(outputs(points), dtype=np.float64)
    if not np.all(np.isfinite(ys)):
        raise CalibrationError("a Sobol' run gave no finite output; see runs.csv and run.log")
    out: dict[str, Any] = {"samples": len(points), "base_samples": n, "outputs": {}}
    for k, name in enumerate(names):
        # SALib's analyze reads seed 0 as no seed (bootstrap intervals then differ
        # from run to run): its bootstrap gets seed + 1
        si = analyze.analyze(problem, ys[:, k], calc_second_order=False, seed=seed + 1)
        out["outputs"][name] = {
            lab: {key: float(si[key][j]) for key in ("S1", "S1_conf", "ST", "ST_conf")}
            for j, lab in enumerate(labels)
        }
    return out


def write_sobol(out: Path, result: dict[str, Any]) -> list[str]:
    """``sobol.csv`` (output, parameter, S1, S1_conf, ST, ST_conf) and ``sobol.png``."""
    import csv

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with (out / "sobol.csv").open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["output", "parameter", "S1", "S1_conf", "ST", "ST_conf"])
        for name, per in result["outputs"].items():
            for lab, s in per.items():
                w.writerow([name, lab, *(repr(s[k]) for k in ("S1", "S1_conf", "ST", "ST_conf"))])
    names = list(result["outputs"])
    fig, axes = plt.subplots(1, len(names), figsize=(4.0 * len(names), 3.4), squeeze=False)
    for ax, name in zip(axes[0], names, strict=True):
        per = result["outputs"][name]
        pos = np.arange(len(per))
        for off, key, color in ((-0.2, "S1", "C0"), (0.2, "ST", "C1")):
            ax.bar(pos + off, [s[key] for s in per.values()], 0.4, color=color, label=key,
                   yerr=[s[key + "_conf"] for s in per.values()])  # fmt: skip
        ax.set_xticks(pos, list(per))
        ax.set_title(name)
        ax.legend()
    fig.suptitle(f"Sobol' indices ({result['samples']} runs)")
    fig.tight_layout()
    fig.savefig(out / "sobol.png", dpi=120)
    plt.close(fig)
    return ["sobol.csv", "sobol.png"]


def run_sobol(
    spec: Any, deck: Path, out: Path, base: Path, n: int, sets: list[str] | None = None,
    quiet: bool = False, allow_large: bool = False, ranks: Any = None,
) -> dict[str, Any]:  # fmt: skip
    """Sobol' indices of a calibration's outputs (module docstring): runs in
    ``out/runs`` (read back when there), ``sobol.json``, ``sobol.csv``, ``sobol.png``;
    ``ranks`` (:class:`~peridynamics.app.calibrate_mpi.Ranks`, on rank 0 under
    ``mpiexec -n N``): each batch of runs divided among the ranks."""
    import json

    from peridynamics.app.calibrate_data import load_targets, residuals
    from peridynamics.app.calibrate_runs import Runner, evaluate_batch, summary_of

    salib()  # before any run: the message if it is missing
    targets = load_targets(spec.targets, base)
    out.mkdir(parents=True, exist_ok=True)
    runner = Runner(deck, [*spec.set, *(sets or [])], spec.parameters, out, spec.options.jobs,
                    quiet, allow_large, ranks=ranks)  # fmt: skip
    names = ["cost", *(f"rms.{td.spec.name}" for td in targets)]

    def values(folder: Path) -> NDArray[np.float64]:
        res, _ = residuals(folder, targets)
        parts, start = [0.5 * float(res @ res)], 0
        for td in targets:
            r = res[start : start + td.size]
            start += td.size
            parts.append(float(np.sqrt(np.mean(r**2))))
        return np.array(parts)

    def outputs(points: list[list[float]]) -> NDArray[np.float64]:
        rows = evaluate_batch(runner, points, values, strict=True)
        return np.array([r for r in rows if r is not None])

    result = sobol_from(spec.parameters, outputs, names, n, spec.options.seed)
    result["runs"] = summary_of(runner)
    files = write_sobol(out, result)
    result["files"] = ["sobol.json", *files]
    (out / "sobol.json").write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    return result
