"""The flag form of ``peridynamics calibrate`` (docs/calibration.md): a calibration
without a calibration file, e.g.::

    peridynamics calibrate beam.yaml --data test.csv \\
        --fit material.youngs_modulus=20e9:50e9 --fit damage.fracture_energy \\
        --x "mouth_right_ux - mouth_left_ux=cmod [mm]" --y "-1 * reaction=load [N]"

:func:`spec_from_flags` turns the flags into the mapping a calibration file holds and
validates it with :func:`~peridynamics.app.calibrate_spec.parse_spec`: the fit itself
has one code path. ``--fit KEY`` without bounds takes [0.5, 2] x the deck's value (a
note says so); every fit starts from the deck's value when it lies inside the bounds.
A measured column's unit, ``[mm]`` in the CSV header or after the column's name in the
flag, is converted to SI (the deck's units) by :data:`UNITS`.
"""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path
from typing import Any

from peridynamics.app.calibrate_data import _column, read_table
from peridynamics.app.calibrate_spec import CalibrationError, CalibrationSpec, parse_spec

#: units a measured column may carry, and their factor to SI
UNITS: dict[str, float] = {
    "m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "nm": 1e-9,
    "N": 1.0, "kN": 1e3, "MN": 1e6, "Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9,
    "N/m": 1.0, "N/mm": 1e3, "kN/m": 1e3, "J": 1.0, "J/m^2": 1.0, "N/mm^2": 1e6,
    "s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "-": 1.0, "1": 1.0, "": 1.0,
    "%": 1e-2, "rad": 1.0, "kg": 1.0, "g": 1e-3,
}  # fmt: skip

_UNIT = re.compile(r"^(.*?)\s*\[([^\]]*)\]\s*$")
FLAG_ONLY = ("data", "fit", "x", "y", "sigma", "monotone")


def flag_form(args: argparse.Namespace) -> bool:
    """True when any flag of the flag form is given."""
    return any(getattr(args, f, None) not in (None, [], False) for f in FLAG_ONLY)


def unit_factor(unit: str, flag: str) -> float:
    """The factor from ``unit`` to SI; raise :class:`CalibrationError` naming ``flag``."""
    if unit.strip() not in UNITS:
        raise CalibrationError(
            f"{flag}: unknown unit [{unit}]; use one of {', '.join(u for u in UNITS if u)}, "
            "or convert the column to SI"
        )
    return UNITS[unit.strip()]


def _split_bounds(text: str, flag: str) -> tuple[str, tuple[float, float] | None, str]:
    """``KEY[=LO:HI[:log]]`` -> key, bounds or None, scale."""
    key, _, rest = text.partition("=")
    key = key.strip()
    if not key or " " in key:
        raise CalibrationError(f"{flag} {text!r}: write a deck key, e.g. material.youngs_modulus")
    if not rest:
        return key, None, "linear"
    parts = [p.strip() for p in rest.split(":")]
    scale = "linear"
    if len(parts) == 3 and parts[2] in ("log", "linear"):
        scale = parts.pop()
    if len(parts) != 2:
        raise CalibrationError(
            f"{flag} {text!r}: write bounds as {key}=LOWER:UPPER (optionally :log), "
            f"e.g. {key}=20e9:50e9"
        )
    try:
        lo, hi = float(parts[0]), float(parts[1])
    except ValueError:
        raise CalibrationError(f"{flag} {text!r}: the bounds are not numbers") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or not lo < hi:
        raise CalibrationError(
            f"{flag} {text!r}: bounds {lo:g}:{hi:g}; write {key}=LOWER:UPPER with "
            "finite LOWER < UPPER"
        )
    if scale == "log" and lo <= 0:
        raise CalibrationError(f"{flag} {text!r}: :log needs LOWER > 0; drop :log")
    return key, (lo, hi), scale


def deck_value(deck: Any, key: str, flag: str) -> Any:
    """The value at the dotted ``key`` of a validated deck (defaults filled in)."""
    node: Any = deck.model_dump(mode="json", by_alias=True)
    done: list[str] = []
    for part in key.split("."):
        if isinstance(node, list) and part.isdigit() and int(part) < len(node):
            node = node[int(part)]
        elif isinstance(node, dict) and part in node:
            node = node[part]
        else:
            here = ".".join(done) or "the deck"
            known = sorted(node) if isinstance(node, dict) else []
            hint = f"; the keys of {here}: {', '.join(map(str, known))}" if known else ""
            raise CalibrationError(f"{flag} {key}: unknown deck key (no {part!r} in {here}){hint}")
        done.append(part)
    return node


def _parameter(text: str, deck: Any, notes: list[str]) -> dict[str, Any]:
    """One ``--fit`` item -> a ``parameters`` entry."""
    key, bounds, scale = _split_bounds(text, "--fit")
    value = deck_value(deck, key, "--fit")
    if isinstance(value, dict):
        raise CalibrationError(
            f"--fit {key}: a section, not a number; name one of its keys: "
            f"{', '.join(f'{key}.{k}' for k in sorted(value))}"
        )
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise CalibrationError(f"--fit {key}: the deck value {value!r} is not a number")
    v = float(value)
    if bounds is None:
        if v == 0.0 or not math.isfinite(v):
            raise CalibrationError(
                f"--fit {key}: the deck value is {v:g}, so [0.5, 2] x it is no range; give "
                f"bounds: --fit {key}=LOWER:UPPER"
            )
        bounds = (min(0.5 * v, 2.0 * v), max(0.5 * v, 2.0 * v))
        notes.append(
            f"--fit {key}: no bounds given; fitting in [0.5, 2] x the deck value {v:g} = "
            f"[{bounds[0]:g}, {bounds[1]:g}] (give {key}=LOWER:UPPER to choose)"
        )
    entry: dict[str, Any] = {"key": key, "bounds": list(bounds), "scale": scale}
    if bounds[0] <= v <= bounds[1]:
        entry["initial"] = v
    return entry


def _axis(text: str, headers: list[str], flag: str) -> tuple[str, str, float]:
    """``SIM[=COLUMN [unit]]`` -> simulated expression, CSV column, factor to SI."""
    sim, _, col = text.partition("=")
    sim, col = sim.strip(), (col.strip() or sim.strip())
    if not sim:
        raise CalibrationError(
            f"{flag} {text!r}: write SIMULATED=COLUMN, e.g. {flag} 'mouth_right_ux - "
            "mouth_left_ux=cmod [mm]' (history.csv columns = the CSV's column)"
        )
    m = _UNIT.match(col)
    unit = None
    if m is not None:
        col, unit = m.group(1).strip(), m.group(2)
    try:
        header = headers[_column(headers, col, flag)]
    except CalibrationError:
        raise CalibrationError(
            f"{flag}: the data file has no column {col!r}; its columns: {headers}; write "
            f"{flag} SIMULATED=COLUMN"
        ) from None
    if unit is None:
        hm = _UNIT.match(header)
        unit = hm.group(2) if hm is not None else ""
    return sim, col, unit_factor(unit, f"{flag} {text!r}")


def spec_from_flags(
    args: argparse.Namespace, deck_path: Path
) -> tuple[CalibrationSpec, dict[str, Any], list[str]]:
    """The calibration of the flags ``--data``, ``--fit``, ``--x``, ``--y``,
    ``--sigma``, ``--monotone`` and the options ``--jobs``, ``--method``,
    ``--restarts``, ``--max-runs``.

    Returns
    -------
    spec, data, notes
        The validated calibration, the mapping it was built from (what a calibration
        file holds; the data path absolute) and notes to print (default bounds).

    Raises
    ------
    CalibrationError
        A missing or bad flag, an unknown deck key, a missing column, an unknown unit.
    """
    from peridynamics.deck import DeckError, load_deck

    missing = [f"--{f}" for f in ("data", "fit", "x", "y") if not getattr(args, f, None)]
    if missing:
        raise CalibrationError(
            f"calibrate without a calibration file needs {', '.join(missing)}: e.g. --data "
            "test.csv --fit material.youngs_modulus=20e9:50e9 --x 'time=load' --y "
            "'tip=displacement [mm]' (docs/calibration.md)"
        )
    try:
        deck = load_deck(deck_path, list(getattr(args, "set", None) or []))
    except DeckError as exc:
        text = "\n  ".join(f"{p}: {m}" if p else m for p, m in exc.errors)
        raise CalibrationError(f"{deck_path}: invalid deck:\n  {text}") from None
    notes: list[str] = []
    fixed = {s.split("=", 1)[0].strip() for s in getattr(args, "set", None) or []}
    items = [t for group in args.fit for t in group.split(",") if t.strip()]
    params = [_parameter(t, deck, notes) for t in items]
    both = sorted(fixed & {p["key"] for p in params})
    if both:
        raise CalibrationError(f"--fit {both[0]} is also fixed by --set; drop one of them")
    data_file = Path(args.data).resolve()
    if not data_file.is_file():
        raise CalibrationError(f"--data {args.data}: no such file; give the measured CSV")
    headers, _ = read_table(data_file, f"--data {args.data}")
    sx, cx, fx = _axis(args.x, headers, "--x")
    sy, cy, fy = _axis(args.y, headers, "--y")
    measured: dict[str, Any] = {"file": str(data_file), "x": cx, "y": cy}
    measured.update({"x_factor": fx, "y_factor": fy})
    if getattr(args, "sigma", None):
        measured["sigma"] = args.sigma
        _column(headers, args.sigma, "--sigma")
    name = re.sub(r"[^A-Za-z0-9_.\-]+", "_", f"{cy}").strip("_") or "curve"
    target: dict[str, Any] = {"name": name, "simulated": {"x": sx, "y": sy}, "measured": measured}
    if getattr(args, "monotone", False):
        target["monotone"] = True
    options = {
        o: getattr(args, o)
        for o in ("jobs", "method", "restarts", "max_runs")
        if getattr(args, o, None) is not None
    }
    data = {"parameters": params, "targets": [target], "options": options}
    return parse_spec(data, "the calibrate flags"), data, notes
