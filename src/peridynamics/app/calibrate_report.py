"""The outputs of ``peridynamics calibrate`` (docs/calibration.md): ``report.json``,
``report.md``, ``fit.png`` (measured against fitted curves), ``fit_<target>.csv`` and
``fitted_deck.yaml`` (the deck with the fitted values)."""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

import numpy as np

from peridynamics.app.calibrate_data import TargetData, simulated_curve
from peridynamics.app.calibrate_spec import Parameter
from peridynamics.app.sweep_cases import yaml_text
from peridynamics.io.atomic import atomic_path


def write_json(path: Path, data: dict[str, Any]) -> None:
    """Write ``data`` as indented JSON, atomically."""
    with atomic_path(path) as tmp:
        Path(tmp).write_text(json.dumps(data, indent=1, default=float) + "\n", encoding="utf-8")


def fitted_deck(deck: Path, sets: list[str], params: list[Parameter], values: list[float],
                path: Path) -> None:  # fmt: skip
    """The deck with the fixed ``set`` values and the fitted parameters applied."""
    import yaml

    from peridynamics.deck import apply_overrides, yaml_load
    from peridynamics.deck.yaml_source import read_text

    raw = yaml_load(read_text(deck, f"deck {str(deck)!r}"))
    args = [*sets, *(f"{p.key}={yaml_text(v)}" for p, v in zip(params, values, strict=True))]
    data = apply_overrides(raw, args)
    head = f"# {deck.name} with the values fitted by peridynamics calibrate (report.md)\n"
    with atomic_path(path) as tmp:
        Path(tmp).write_text(head + yaml.safe_dump(data, sort_keys=False), encoding="utf-8")


def write_curves(out: Path, folder: Path, targets: list[TargetData],
                 fitted: dict[str, Any]) -> list[str]:  # fmt: skip
    """Per curve target ``fit_<name>.csv``: measured x, y and the fitted y there; the
    whole fitted curve as ``fit_<name>_simulated.csv``. Returns the files written."""
    files = []
    for n, td in enumerate(targets):
        t = td.spec
        if t.scalar is not None:
            continue
        name = out / f"fit_{t.name}.csv"
        with name.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(["x", "y_measured", "y_fitted", "sigma"])
            for row in zip(td.x, td.y, fitted[t.name]["fitted"], td.sigma, strict=True):
                w.writerow([repr(float(v)) for v in row])
        xs, ys = simulated_curve(folder, t, f"targets.{n} ({t.name})")
        sim = out / f"fit_{t.name}_simulated.csv"
        with sim.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(["x", "y"])
            w.writerows([[repr(float(a)), repr(float(b))] for a, b in zip(xs, ys, strict=True)])
        files += [name.name, sim.name]
    return files


def plot_fit(path: Path, folder: Path, targets: list[TargetData], fitted: dict[str, Any],
             title: str) -> bool:  # fmt: skip
    """Measured points and the fitted curve, one panel per curve target (scalars: one
    panel of measured against fitted). Returns whether a figure was written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves = [td for td in targets if td.spec.scalar is None]
    scalars = [td for td in targets if td.spec.scalar is not None]
    panels = len(curves) + (1 if scalars else 0)
    if panels == 0:
        return False
    fig, axes = plt.subplots(1, panels, figsize=(4.2 * panels, 3.6), squeeze=False)
    for ax, td in zip(axes[0], curves, strict=False):
        t = td.spec
        xs, ys = simulated_curve(folder, t, t.name)
        ax.plot(xs, ys, "-", color="C0", label="fitted")
        ax.plot(td.x, td.y, "o", ms=3, color="k", label="measured")
        assert t.simulated is not None
        ax.set_xlabel(t.simulated.x)
        ax.set_ylabel(t.simulated.y)
        ax.set_title(t.name)
        ax.legend()
    if scalars:
        ax = axes[0][-1]
        names = [td.spec.name for td in scalars]
        meas = [float(td.y[0]) for td in scalars]
        fit = [fitted[nm]["fitted"][0] for nm in names]
        pos = np.arange(len(names))
        ax.bar(pos - 0.2, meas, 0.4, label="measured", color="0.4")
        ax.bar(pos + 0.2, fit, 0.4, label="fitted", color="C0")
        ax.set_xticks(pos, names)
        ax.legend()
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return True


def markdown(report: dict[str, Any]) -> str:
    """``report.md``: the fitted parameters with intervals, the misfit, the runs."""
    u = report["uncertainty"]
    conf = round(100 * u["confidence"])
    lines = [
        f"# Calibration of {report['deck_name']}",
        "",
        f"Deck `{report['deck']}`, calibration file `{report['calibration_file']}`; "
        f"method `{report['optimiser']['method']}` ({report['optimiser']['stopped']}).",
        "",
        f"| parameter | key | fitted | std. error | {conf} % interval | correlation |",
        "|---|---|---|---|---|---|",
    ]
    for k, p in enumerate(u["parameters"]):
        corr = ", ".join(f"{c:+.3f}" for c in u["correlation"][k])
        lo, hi = p["interval"]
        bound = " (at a bound)" if p["at_bound"] else ""
        lines.append(
            f"| {p['name']} | `{p['key']}` | {p['value']:.6g}{bound} | {p['std_error']:.3g} | "
            f"[{lo:.6g}, {hi:.6g}] | {corr} |"
        )
    m = report["misfit"]
    lines += [
        "",
        f"Misfit: cost (half the sum of squared weighted residuals) {m['cost']:.6g} over "
        f"{u['residuals']} residuals, RMS {m['rms']:.4g}; s^2 = {u['s2']:.4g} with "
        f"{u['dof']} degrees of freedom; t quantile {u['t_quantile']:.4g}; condition "
        f"number of J in the unit variables {u['condition_number']:.3g}"
        + (
            ""
            if u["identifiable"]
            else " (the parameters are not identifiable: J is "
            "rank-deficient; fix a parameter or add a target)"
        )
        + ".",  # fmt: skip
        "",
        "| target | residuals | RMS weighted residual | measured points outside the "
        "simulated range |",
        "|---|---|---|---|",
    ]
    for name, t in report["targets"].items():
        lines.append(f"| {name} | {t['n']} | {t['rms']:.4g} | {t['outside']} |")
    r = report["runs"]
    lines += [
        "",
        f"Runs: {r['runs']} made ({r['runs_wall_s']:.1f} s of run wall time), "
        f"{r['runs_read_back']} read back from earlier calibrations, {r['failed']} did "
        f"not complete; calibration wall time {report['wall_s']:.1f} s.",
        "",
        f"The fitted run: `{report['fitted_run']}`; the deck with the fitted values: "
        "`fitted_deck.yaml`.",
    ]
    if report.get("figure"):
        lines += ["", f"![measured and fitted]({report['figure']})"]
    return "\n".join(lines) + "\n"
