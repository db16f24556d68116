"""Reports of a parameter sweep: ``sweep.json``, ``sweep.csv``, ``sweep.png`` and the
table printed at the end (``peridynamics sweep``, see docs/sweep.md).

A *record* is the mapping the sweep keeps for each case: ``case`` (index), ``folder``,
``status``, ``exit_code``, ``wall_s``, ``resumed``, ``values`` (key path -> value used),
``set`` (the ``--set`` arguments of the case), ``fingerprint``, ``results`` and
``timing`` (flattened scalars of the case's summary.json, see :func:`flatten_scalars`)
and, for a case that did not complete, ``stderr_tail`` (the last lines of its run.log).
"""

from __future__ import annotations

import csv
import json
import math
import re
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from peridynamics.io.atomic import atomic_path

#: every status a case can have in sweep.csv / sweep.json
STATUSES = ("completed", "skipped-done", "failed", "unstable", "interrupted", "not-started")
#: results drawn by default when present (then wall_s); a crack length is added when found
DEFAULT_PLOT = (
    "peak_stress_Pa",
    "events.peak_load.load",
    "crack_length_m",
    "crack_area_m2",
    "events.fracture.time_s",
    "fracture_time_s",
    "<crack length>",
    "max_crack_tip_speed_m_per_s",
    "max_damage",
    "max_displacement_m",
)
MAX_PANELS = 6
#: rows of the table printed at the end (all of them are in sweep.csv)
MAX_ROWS = 40
_CRACK_LENGTH = re.compile(r"^crack_paths\.[^.]+\.length_m$")


def flatten_scalars(data: dict[str, Any], prefix: str = "", depth: int = 3) -> dict[str, Any]:
    """The numeric scalars of a results mapping, nested mappings flattened as ``a.b``.

    Parameters
    ----------
    data
        A ``results`` (or ``timing``) mapping of summary.json.
    prefix
        Put before every name (``"timing."``).
    depth
        Levels of nested mappings to descend (``probes.<name>.peak`` is two levels).

    Returns
    -------
    dict
        Name -> int, float or ``None`` (a null in summary.json: no fracture, ...);
        true/false become 1/0; lists and strings are left out.
    """
    out: dict[str, Any] = {}
    for key, value in data.items():
        name = f"{prefix}{key}"
        if isinstance(value, bool):
            out[name] = int(value)
        elif value is None or isinstance(value, int | float):
            out[name] = value
        elif isinstance(value, dict) and depth > 0:
            out.update(flatten_scalars(value, name + ".", depth - 1))
    return out


def _cell(value: Any) -> Any:
    """A csv cell: numbers as they are (full precision), lists and mappings as JSON."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, list | dict):
        return json.dumps(value)
    return value


def table_columns(records: Sequence[dict[str, Any]], keys: Sequence[str]) -> list[str]:
    """Columns of sweep.csv: case, folder, status, wall_s, the varied keys, then every
    result scalar and timing scalar met in any record (in order of first appearance)."""
    cols = ["case", "folder", "status", "exit_code", "wall_s", *keys]
    extra: dict[str, None] = {}
    for rec in records:
        for name in (*rec.get("results", {}), *rec.get("timing", {})):
            if name not in cols:
                extra[name] = None
    return cols + list(extra)


def row_of(rec: dict[str, Any]) -> dict[str, Any]:
    """One record as a flat mapping column -> value (the row of sweep.csv)."""
    row = {k: rec.get(k) for k in ("case", "folder", "status", "exit_code", "wall_s")}
    row.update(rec.get("values", {}))
    row.update(rec.get("results", {}))
    row.update(rec.get("timing", {}))
    return row


def write_csv(path: Path, records: Sequence[dict[str, Any]], keys: Sequence[str]) -> None:
    """Write sweep.csv atomically (one row per case, in case order)."""
    cols = table_columns(records, keys)
    with atomic_path(path) as tmp, tmp.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for rec in records:
            row = row_of(rec)
            w.writerow([_cell(row.get(c)) for c in cols])


def write_json(path: Path, data: dict[str, Any]) -> None:
    """Write a JSON file atomically (temporary file, then rename)."""
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(data, indent=2, default=str) + "\n")


def counts(records: Iterable[dict[str, Any]]) -> dict[str, int]:
    """Number of cases per status (only the statuses that occur)."""
    out: dict[str, int] = {}
    for rec in records:
        out[rec["status"]] = out.get(rec["status"], 0) + 1
    return out


def _finite(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


def plot_columns(
    records: Sequence[dict[str, Any]], requested: Sequence[str] | None
) -> tuple[list[str], list[str]]:
    """The result columns to draw, and the requested ones that no case has.

    Default: those of :data:`DEFAULT_PLOT` that hold a finite value in some completed
    case (at most five), then ``wall_s``.
    """
    done = [row_of(r) for r in records if r["status"] in ("completed", "skipped-done")]
    present = {c for row in done for c, v in row.items() if _finite(v)}
    if requested:
        return [c for c in requested if c in present], [c for c in requested if c not in present]
    chosen: list[str] = []
    for name in DEFAULT_PLOT:
        if name == "<crack length>":
            name = next((c for c in sorted(present) if _CRACK_LENGTH.match(c)), "")
        if name in present and name not in chosen and len(chosen) < MAX_PANELS - 1:
            chosen.append(name)
    if "wall_s" in present:
        chosen.append("wall_s")
    return chosen, []


def _label(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:g}"
    return "(deck)" if v is None else str(v)


def plot_sweep(
    path: Path,
    records: Sequence[dict[str, Any]],
    keys: Sequence[str],
    columns: Sequence[str],
    title: str,
) -> bool:
    """``sweep.png``: each column (rows of panels) against each varied key (columns of
    panels), one line per combination of the other keys' values; completed cases only.

    A key is drawn on a numeric axis when all its values are numbers (logarithmic when
    positive and spanning a factor of 20 or more), else as categories. Keys with a single
    value are not drawn against. Returns ``False`` (nothing written) when there is no
    key with two or more values or no column to draw.
    """
    rows = [row_of(r) for r in records if r["status"] in ("completed", "skipped-done")]
    varied = [k for k in keys if len({_label(r.get(k)) for r in rows}) > 1]
    if not rows or not varied or not columns:
        return False
    from peridynamics.io.plots import plt

    n_r, n_c = len(columns), len(varied)
    fig, axes = plt.subplots(
        n_r, n_c, figsize=(max(8.0, 4.0 * n_c), 2.4 * n_r + 0.8), squeeze=False
    )
    for j, key in enumerate(varied):
        xs = [r.get(key) for r in rows]
        numeric = all(_finite(x) for x in xs)
        nums = [float(x) for x in xs if x is not None] if numeric else []
        cats = sorted({_label(x) for x in xs})
        others = [k for k in keys if k != key]
        groups: dict[str, list[dict[str, Any]]] = {}
        for r in rows:
            name = ", ".join(f"{k.rsplit('.', 1)[-1]}={_label(r.get(k))}" for k in others)
            groups.setdefault(name, []).append(r)
        for i, col in enumerate(columns):
            ax = axes[i, j]
            for name, members in groups.items():
                pts = [
                    (m[key] if numeric else cats.index(_label(m.get(key))), m.get(col))
                    for m in members
                    if _finite(m.get(col))
                ]
                if not pts:
                    continue
                pts.sort()
                ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", lw=1.2, ms=4,
                        label=name or None)  # fmt: skip
            if numeric:
                lo, hi = min(nums), max(nums)
                if lo > 0 and hi / lo >= 20.0:
                    ax.set_xscale("log")
            else:
                ax.set_xticks(range(len(cats)), cats)
            ax.set_ylabel(col)
            ax.grid(alpha=0.3)
            if i == n_r - 1:
                ax.set_xlabel(key)
            if i == 0 and len(groups) > 1:
                handles, labels = ax.get_legend_handles_labels()
                if labels:
                    ax.legend(handles[:10], labels[:10], fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return True


def format_table(records: Sequence[dict[str, Any]], columns: Sequence[str]) -> str:
    """The table printed at the end: folder, status, wall time, up to three results."""
    shown = [c for c in columns if c != "wall_s"][:3]
    head = ["folder", "status", "wall_s", *shown]
    body = []
    for rec in records[:MAX_ROWS]:
        row = row_of(rec)
        cells = [str(rec["folder"]), str(rec["status"])]
        for c in ("wall_s", *shown):
            v = row.get(c)
            cells.append(f"{v:.4g}" if _finite(v) else ("-" if v is None else str(v)))
        body.append(cells)
    widths = [max(len(r[k]) for r in [head, *body]) for k in range(len(head))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)).rstrip()
             for r in [head, *body]]  # fmt: skip
    if len(records) > MAX_ROWS:
        lines.append(f"... and {len(records) - MAX_ROWS} more case(s): see sweep.csv")
    return "\n".join(lines)
