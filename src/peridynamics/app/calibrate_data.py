"""Targets of a calibration (docs/calibration.md): the measured curves read from CSV,
the simulated ones taken from a run's ``history.csv`` and ``summary.json``, and the
weighted residuals between them.

A curve's residuals are ``weight * (y_sim(x_i) - y_i) / sigma_i`` at the measured
abscissae ``x_i``, with ``y_sim`` interpolated linearly (``numpy.interp``) on the
simulated curve; measured points outside the simulated x range are counted and get the
value at its nearer end (a run that stops early is penalised, not dropped).
"""

from __future__ import annotations

import csv
import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.app.calibrate_spec import CalibrationError, Target

#: one term of a column expression: sign, optional factor ``number *``, column name
_TERM = re.compile(
    r"\s*([+-]?)\s*(?:([0-9.]+(?:[eE][+-]?[0-9]+)?)\s*\*\s*)?([^+\-*]+?)\s*(?=[+-]|$)"
)


def cut_monotone(x: NDArray[np.float64], y: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
    """The curve up to (excluding) the first point where x decreases."""
    drops = np.flatnonzero(np.diff(x) < 0)
    end = int(drops[0]) + 1 if drops.size else len(x)
    return x[:end], y[:end]


def _column(headers: list[str], name: str, where: str) -> int:
    """Index of a column named ``name`` with or without its ``[unit]``."""
    bare = [re.sub(r"\s*\[[^\]]*\]\s*$", "", h).strip() for h in headers]
    for n, (h, b) in enumerate(zip(headers, bare, strict=True)):
        if name.strip() in (h.strip(), b):
            return n
    raise CalibrationError(f"{where}: no column {name!r}; the columns: {headers}")


def expression_terms(text: str, where: str) -> list[tuple[float, str]]:
    """``a - 2 * b + c`` -> ``[(1, a), (-2, b), (1, c)]`` (column names hold no ``+``,
    ``-`` or ``*``)."""
    terms: list[tuple[float, str]] = []
    pos = 0
    text = text.strip()
    while pos < len(text):
        m = _TERM.match(text, pos)
        if m is None or m.end() == pos:
            raise CalibrationError(
                f"{where}: cannot read {text!r}; write columns joined by + and -, each with "
                "an optional factor, e.g. 'mouth_right_ux - mouth_left_ux' or '-1e-3 * load'"
            )
        sign = -1.0 if m.group(1) == "-" else 1.0
        terms.append((sign * float(m.group(2) or 1.0), m.group(3).strip()))
        pos = m.end()
    return terms


def evaluate_expression(
    table: dict[str, NDArray], headers: list[str], text: str, where: str
) -> NDArray:
    """The value of a column expression (:func:`expression_terms`) over a table."""
    out = np.zeros(len(next(iter(table.values()))))
    for factor, name in expression_terms(text, where):
        out = out + factor * table[headers[_column(headers, name, where)]]
    return out


def read_table(path: Path, where: str) -> tuple[list[str], dict[str, NDArray]]:
    """A CSV file with a header row -> its headers and columns as float arrays."""
    try:
        with path.open(newline="", encoding="utf-8") as fh:
            rows = [r for r in csv.reader(fh) if r and not r[0].lstrip().startswith("#")]
    except OSError as exc:
        raise CalibrationError(f"{where}: cannot read {str(path)!r} ({exc.strerror})") from None
    if len(rows) < 2:
        raise CalibrationError(f"{where}: {str(path)!r} needs a header row and data rows")
    headers = [h.strip() for h in rows[0]]
    try:
        data = np.array([[float(c) for c in r] for r in rows[1:]], dtype=np.float64)
    except ValueError as exc:
        raise CalibrationError(f"{where}: {str(path)!r}: a cell is not a number ({exc})") from None
    if data.ndim != 2 or data.shape[1] != len(headers):
        raise CalibrationError(f"{where}: {str(path)!r}: every row needs {len(headers)} cells")
    return headers, {h: data[:, n] for n, h in enumerate(headers)}


@dataclass
class TargetData:
    """A target with its measured data in simulation units."""

    spec: Target
    x: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    y: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    sigma: NDArray[np.float64] = field(default_factory=lambda: np.ones(0))

    @property
    def size(self) -> int:
        """Number of residuals."""
        return 1 if self.spec.scalar is not None else len(self.x)


def load_targets(targets: list[Target], base: Path) -> list[TargetData]:
    """Read every target's measured data (relative paths from ``base``)."""
    out = []
    for n, t in enumerate(targets):
        where = f"targets.{n} ({t.name})"
        if t.scalar is not None:
            assert t.value is not None
            one = t.sigma or max(abs(t.value), 1e-300)
            out.append(TargetData(t, np.zeros(1), np.array([t.value]), np.array([one])))
            continue
        m = t.measured
        assert m is not None
        path = Path(m.file) if Path(m.file).is_absolute() else base / m.file
        headers, table = read_table(path, f"{where}.measured.file")
        x = table[headers[_column(headers, m.x, f"{where}.measured.x")]] * m.x_factor
        y = table[headers[_column(headers, m.y, f"{where}.measured.y")]] * m.y_factor
        sig: NDArray[np.float64]
        if m.sigma is not None:
            sig = table[headers[_column(headers, m.sigma, f"{where}.measured.sigma")]]
            sig = np.abs(sig * m.y_factor)
            if not np.all(sig > 0):
                raise CalibrationError(f"{where}.measured.sigma: every sigma must be > 0")
        else:
            sig = np.full(len(y), t.sigma or max(float(np.abs(y).max()), 1e-300))
        if t.monotone:
            x, y = cut_monotone(x, y)
            sig = sig[: len(x)]
        if len(x) < 1 or not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            raise CalibrationError(f"{where}.measured: no finite data points")
        out.append(TargetData(t, x, y, sig))
    return out


def flatten(results: dict[str, Any], prefix: str = "") -> dict[str, float]:
    """Numeric scalars of a mapping, nested keys joined by dots (as in sweep.csv)."""
    flat: dict[str, float] = {}
    for k, v in results.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            flat.update(flatten(v, key + "."))
        elif isinstance(v, bool):
            flat[key] = float(v)
        elif isinstance(v, int | float):
            flat[key] = float(v)
    return flat


def simulated_curve(folder: Path, t: Target, where: str) -> tuple[NDArray, NDArray]:
    """The simulated (x, y) of a curve target from ``folder/history.csv``."""
    s = t.simulated
    assert s is not None
    headers, table = read_table(folder / "history.csv", f"{where}.simulated")
    x = evaluate_expression(table, headers, s.x, f"{where}.simulated.x") * s.x_factor
    y = evaluate_expression(table, headers, s.y, f"{where}.simulated.y") * s.y_factor
    return cut_monotone(x, y) if t.monotone else (x, y)


def residuals(folder: Path, targets: list[TargetData]) -> tuple[NDArray, dict[str, Any]]:
    """The stacked weighted residuals of a finished run, and per target its simulated
    values at the measured abscissae (``fitted``) and the points outside the simulated
    range (``outside``)."""
    parts: list[NDArray] = []
    info: dict[str, Any] = {}
    summary: dict[str, Any] | None = None
    for n, td in enumerate(targets):
        t = td.spec
        where = f"targets.{n} ({t.name})"
        if t.scalar is not None:
            if summary is None:
                summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
            flat = flatten(summary.get("results") or {})
            if t.scalar not in flat:
                near = [k for k in flat if t.scalar.split(".")[-1] in k][:5]
                raise CalibrationError(
                    f"{where}.scalar: the run has no result {t.scalar!r}"
                    + (f"; close ones: {near}" if near else "")
                )
            sim = np.array([flat[t.scalar]])
            outside = 0
        else:
            xs, ys = simulated_curve(folder, t, where)
            order = np.argsort(xs, kind="stable")
            sim = np.interp(td.x, xs[order], ys[order])
            slack = 1e-9 * max(float(np.ptp(xs)), 1e-300)  # round-off of unit factors
            outside = int(np.sum((td.x < xs.min() - slack) | (td.x > xs.max() + slack)))
        parts.append(t.weight * (sim - td.y) / td.sigma)
        info[t.name] = {"fitted": sim.tolist(), "outside": outside}
    return np.concatenate(parts), info
