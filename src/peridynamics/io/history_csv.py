"""``history.csv``: the histories of a run as one table, one row per history record.

Columns, each headed ``name [unit]``: time, the cycle count (fatigue runs), kinetic and
strain energy, largest damage, specimen damage factor, every probe (in deck order), the
stress-strain pair, the crack-tip position, the broken-bond crack length, and per rigid
body its reaction force and displacement components. Only columns recorded at every
history record appear (so the rows line up with ``time [s]``).
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

import numpy as np

from peridynamics.io.atomic import atomic_path
from peridynamics.io.options import Output

BASE = (
    ("time_s", "time [s]"),
    ("cycles", "cycles [-]"),  # fatigue runs: the cycle count N
    ("kinetic_energy_J", "kinetic_energy [J]"),
    ("strain_energy_J", "strain_energy [J]"),
    ("max_damage", "max_damage [-]"),
    ("damage_factor", "damage_factor [-]"),
)


def history_columns(output: Output, records: dict[str, Any]) -> dict[str, list[float]]:
    """The columns of ``history.csv`` by header, each as long as ``time_s``."""
    from peridynamics.io.figures import probe_units

    n = len(records["time_s"])
    cols: dict[str, list[float]] = {}

    def add(header: str, values: Any) -> None:
        if values is not None and len(values) == n:
            cols[header] = [float(v) for v in values]

    for key, header in BASE:
        add(header, records.get(key))
    units = probe_units(output)
    for name, values in records["probes"].items():
        add(f"{name} [{units.get(name, '-')}]", values)
    add("stress [Pa]", records.get("stress_Pa"))
    add("strain [-]", records.get("strain"))
    tip = records.get("crack_tip_m")
    if tip and np.ndim(tip[0]) == 0:
        add("crack_tip [m]", tip)
    add("crack_length [m]", records.get("crack_length_history_m"))  # broken bonds, 2-D
    add("crack_area [m^2]", records.get("crack_area_history_m2"))  # 3-D
    rigid = records.get("rigid_bodies")
    if isinstance(rigid, dict):
        for body, rec in rigid.items():
            if not isinstance(rec, dict):
                continue
            for key, label, unit in (
                ("force_N", "force", "N"),
                ("displacement_m", "displacement", "m"),
            ):
                arr = np.asarray(rec.get(key, []), dtype=float)
                if arr.ndim == 2 and len(arr) == n:
                    for c in range(arr.shape[1]):
                        add(f"{body}.{label}_{'xyz'[c]} [{unit}]", arr[:, c])
    return cols


def write_history_csv(path: Path, output: Output, records: dict[str, Any]) -> str:
    """Write the table atomically; returns the file name."""
    cols = history_columns(output, records)
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(list(cols))
        rows = zip(*cols.values(), strict=True)
        w.writerows([[repr(v) for v in row] for row in rows])
    return path.name
