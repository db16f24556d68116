"""The cases of a parameter sweep: ``--grid`` and ``--cases`` parsing, folder names,
validation of every case before anything runs (``peridynamics sweep``, docs/sweep.md).

A case is a list of deck overrides (``key.path=value``, applied after the sweep's own
``--set`` values exactly as ``peridynamics run --set`` applies them).
"""

from __future__ import annotations

import csv
import hashlib
import itertools
import json
import math
import re
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

#: longest folder name before it is shortened (with a hash of the full name appended)
MAX_NAME = 100


class SweepError(ValueError):
    """Bad sweep input: ``str(exc)`` names the option and the fix (exit 2)."""


@dataclass(frozen=True)
class Override:
    """One deck override of a case.

    Attributes
    ----------
    key
        Deck key path (``discretisation.spacing``, ``boundary_conditions.0.value``).
    text
        The value as YAML text, passed to ``peridynamics run --set key=text``.
    value
        The parsed value (numbers in scientific notation are floats, as in a deck).
    source
        Where it came from, for messages (``--grid``, ``--cases cases.csv row 3``).
    """

    key: str
    text: str
    value: Any
    source: str

    @property
    def arg(self) -> str:
        """The ``--set`` argument."""
        return f"{self.key}={self.text}"


@dataclass
class Case:
    """One run of the sweep: its overrides, folder, fingerprint and estimated cost."""

    index: int
    overrides: tuple[Override, ...]
    folder: str = ""
    fingerprint: str = ""
    cost: float = 1.0
    deck_name: str = ""

    @property
    def set_args(self) -> list[str]:
        """The case's ``--set`` arguments."""
        return [o.arg for o in self.overrides]

    @property
    def values(self) -> dict[str, Any]:
        """Key path -> value of this case."""
        return {o.key: o.value for o in self.overrides}


def parse_value(text: str, where: str) -> Any:
    """Parse a value as ``--set`` does (YAML; ``1e-3`` and ``0.8e6`` are floats)."""
    from peridynamics.deck import yaml_load
    from peridynamics.deck.yaml_source import short

    try:
        return yaml_load(text)
    except Exception as exc:  # noqa: BLE001 - any YAML error: name the value
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise SweepError(
            f"{where}: value {short(text)} is not valid YAML ({problem}); quote it in the shell "
            "and close brackets, e.g. --grid 'boundary_conditions.0.value=[1e6],[2e6]'"
        ) from None


def yaml_text(value: Any) -> str:
    """A value as one-line YAML that :func:`parse_value` reads back to the same value."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        return repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(yaml_text(v) for v in value) + "]"
    if isinstance(value, dict):
        inner = ", ".join(f"{json.dumps(str(k))}: {yaml_text(v)}" for k, v in value.items())
        return "{" + inner + "}"
    return json.dumps(str(value))  # a double-quoted YAML string


def split_values(text: str) -> list[str]:
    """Split ``v1,v2,...`` at the commas outside brackets, braces and quotes."""
    items: list[str] = []
    cur: list[str] = []
    depth, quote = 0, ""
    for ch in text:
        if quote:
            quote = "" if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == "," and depth == 0:
            items.append("".join(cur).strip())
            cur = []
            continue
        cur.append(ch)
    items.append("".join(cur).strip())
    return items


def _check_key(key: str, where: str) -> str:
    key = key.strip()
    if not key or any(not part for part in key.split(".")) or re.search(r"\s", key):
        raise SweepError(
            f"{where}: {key!r} is not a deck key path; write it as in --set, e.g. "
            "discretisation.spacing or boundary_conditions.0.value"
        )
    return key


def parse_grid(items: list[str]) -> list[list[Override]]:
    """``--grid KEY=V1,V2,...`` arguments -> per key, its overrides (one per value)."""
    out: list[list[Override]] = []
    seen: set[str] = set()
    for item in items:
        if "=" not in item:
            raise SweepError(
                f"--grid {item!r}: write KEY.PATH=V1,V2,..., e.g. "
                "--grid discretisation.spacing=0.001,0.0005"
            )
        raw_key, raw = item.split("=", 1)
        key = _check_key(raw_key, f"--grid {item!r}")
        if key in seen:
            raise SweepError(f"--grid {key}: given twice; put all its values in one --grid")
        seen.add(key)
        texts = split_values(raw)
        if any(not t for t in texts):
            raise SweepError(
                f"--grid {item!r}: an empty value (two commas, or a comma at an end); "
                "write KEY.PATH=V1,V2,..."
            )
        where = f"--grid {key}"
        ovs = [Override(key, t, parse_value(t, where), where) for t in texts]
        if len({yaml_text(o.value) for o in ovs}) < len(ovs):
            raise SweepError(f"--grid {key}: a value is given twice ({raw!r})")
        out.append(ovs)
    return out


def read_cases(path: str) -> list[list[Override]]:
    """A cases file -> one list of overrides per case.

    YAML: a list of mappings ``{key.path: value}``. CSV: a header of key paths, one row
    per case; an empty cell leaves that key as the deck has it.
    """
    from peridynamics.deck import yaml_load
    from peridynamics.deck.yaml_source import TextError, read_text

    p = Path(path)
    opt = f"--cases {path}"
    try:
        text = read_text(p, "the file")
    except OSError as exc:
        raise SweepError(f"{opt}: cannot read the file ({exc.strerror})") from None
    except TextError as exc:
        raise SweepError(f"{opt}: {exc}") from None
    rows: list[list[Override]] = []
    if p.suffix.lower() == ".csv":
        reader = csv.reader(text.splitlines())
        header = next(reader, None)
        if not header:
            raise SweepError(f"{opt}: empty; the first line names the key paths")
        keys = [_check_key(h, f"{opt} header") for h in header]
        if len(set(keys)) < len(keys):
            raise SweepError(f"{opt}: a key path is in the header twice")
        for n, cells in enumerate(reader, start=2):
            if not any(c.strip() for c in cells):
                continue
            if len(cells) > len(keys):
                raise SweepError(f"{opt} line {n}: more cells than the header has keys")
            where = f"{opt} line {n}"
            rows.append([Override(k, c.strip(), parse_value(c.strip(), f"{where}, {k}"), where)
                         for k, c in zip(keys, cells, strict=False) if c.strip()])  # fmt: skip
    elif p.suffix.lower() in (".yaml", ".yml"):
        try:
            data = yaml_load(text)
        except Exception as exc:  # noqa: BLE001 - any YAML error
            raise SweepError(f"{opt}: not valid YAML ({str(exc).splitlines()[0]})") from None
        if not isinstance(data, list):
            raise SweepError(f"{opt}: a YAML list of mappings, e.g. - {{horizon_factor: 3}}")
        for n, item in enumerate(data):
            where = f"{opt} item {n}"
            if not isinstance(item, dict):
                raise SweepError(f"{where}: not a mapping of key.path: value")
            rows.append([Override(_check_key(str(k), where), yaml_text(v), v, where)
                         for k, v in item.items()])  # fmt: skip
    else:
        raise SweepError(f"{opt}: give a .yaml, .yml or .csv file")
    for n, row in enumerate(rows):
        if not row:
            raise SweepError(f"{opt}: case {n} sets no key (a case needs at least one value)")
    if not rows:
        raise SweepError(f"{opt}: no cases in the file")
    return rows


def _short(value: Any) -> str:
    """A value as it appears in a folder name (3.0 -> 3, 0.001 -> 0.001, lists joined)."""
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    if isinstance(value, list | tuple):
        return ",".join(_short(v) for v in value)
    if isinstance(value, bool | float | int) or value is None:
        return yaml_text(value)
    if isinstance(value, dict):
        return ",".join(f"{k}={_short(v)}" for k, v in value.items())
    return str(value)


def folder_names(cases: list[list[Override]]) -> list[str]:
    """Stable, readable folder names from the values: ``case_horizon_factor=3_spacing=0.001``.

    Keys are sorted by path and named by their last part (two parts when the last is a
    list index; the whole path where two varied keys end alike). The name depends only on
    the case's values, so adding values to a grid keeps the folders of the others (a
    rerun skips them). Characters other than letters, digits and ``.,+-=`` become ``_``;
    a name longer than :data:`MAX_NAME`, or one that two cases share after that, gets a
    hash of the full overrides appended.
    """
    keys = sorted({o.key for case in cases for o in case})

    def tail(key: str) -> str:
        parts = key.split(".")
        return ".".join(parts[-2:]) if parts[-1].isdigit() and len(parts) > 1 else parts[-1]

    tails = Counter(tail(k) for k in keys)
    short = {k: (tail(k) if tails[tail(k)] == 1 else k) for k in keys}
    names, full = [], []
    for case in cases:
        parts = [f"{short[o.key]}={_short(o.value)}" for o in sorted(case, key=lambda o: o.key)]
        name = re.sub(r"_+", "_", re.sub(r"[^A-Za-z0-9.,+=\-]", "_", "case_" + "_".join(parts)))
        full.append(json.dumps(sorted((o.key, yaml_text(o.value)) for o in case)))
        names.append(name.rstrip("_."))
    uses = Counter(names)
    for n, name in enumerate(names):
        if len(name) > MAX_NAME or uses[name] > 1:
            digest = hashlib.sha1(full[n].encode()).hexdigest()[:8]
            names[n] = f"{name[:MAX_NAME].rstrip('_.')}_{digest}"
    return names


def build_cases(
    grid: list[str] | None, cases_file: str | None, sets: list[str]
) -> tuple[list[Case], list[str]]:
    """The cases of a sweep: the rows of ``cases_file`` (if any), each crossed with the
    Cartesian product of the ``--grid`` values. Returns the cases (folders named) and
    the varied key paths in order (grid keys in the order given, then the file's)."""
    if not grid and not cases_file:
        raise SweepError(
            "give the values to sweep: --grid KEY.PATH=V1,V2,... (repeatable) and/or "
            "--cases FILE.yaml|FILE.csv"
        )
    axes = parse_grid(grid or [])
    rows = read_cases(cases_file) if cases_file else [[]]
    grid_keys = [ax[0].key for ax in axes]
    file_keys = list(dict.fromkeys(o.key for row in rows for o in row))
    for key in grid_keys:
        if key in file_keys:
            raise SweepError(f"--grid {key}: the key is also in --cases {cases_file}; use one")
    set_keys = {s.split("=", 1)[0].strip() for s in sets if "=" in s}
    for key in grid_keys + file_keys:
        if key in set_keys:
            raise SweepError(
                f"--set {key}: the key is also swept (--grid / --cases); drop the --set"
            )
    combos = [row + list(point) for row in rows for point in itertools.product(*axes)]
    seen: dict[str, int] = {}
    for n, combo in enumerate(combos):
        ident = json.dumps(sorted((o.key, yaml_text(o.value)) for o in combo))
        if ident in seen:
            raise SweepError(
                f"cases {seen[ident]} and {n} are the same run "
                f"({', '.join(o.arg for o in combo)}); give each case once"
            )
        seen[ident] = n
    names = folder_names(combos)
    cases = [Case(n, tuple(c), names[n]) for n, c in enumerate(combos)]
    return cases, grid_keys + file_keys


def fingerprint(deck: Any) -> str:
    """Hash of the validated deck (every default filled in), the package version and the
    file of a geometry read from one: what ``Simulation.fingerprint`` hashes for a
    checkpoint."""
    from peridynamics import __version__

    text = json.dumps(deck.model_dump(mode="json", by_alias=True), sort_keys=True)
    h = hashlib.sha256(text.encode())
    h.update(__version__.encode())
    file = getattr(deck.geometry, "file", None)
    if file is not None:
        h.update(Path(file).read_bytes())
    return h.hexdigest()


def _deck_loader(deck_path: str) -> Any:
    """``load(overrides) -> Deck``: the deck file read and parsed once, each case's
    overrides applied to a copy (a sweep of many cases validates in seconds)."""
    import copy

    from peridynamics.deck import apply_overrides, load_deck, parse_deck, yaml_load
    from peridynamics.deck.yaml_source import read_text

    path = Path(deck_path)
    try:
        raw = yaml_load(read_text(path, f"deck {str(path)!r}"))
    except Exception:  # noqa: BLE001 - load_deck reports it, case by case
        return lambda overrides: load_deck(deck_path, overrides)
    if not isinstance(raw, dict):
        return lambda overrides: load_deck(deck_path, overrides)

    def load(overrides: list[str]) -> Any:
        return parse_deck(apply_overrides(copy.deepcopy(raw), overrides), base_dir=path.parent)

    return load


def validate(deck_path: str, sets: list[str], cases: list[Case], allow_large: bool) -> str | None:
    """Validate every case (deck + ``--set`` + its overrides) and its size, fill in each
    case's fingerprint, cost (estimated bond updates) and deck name. Returns ``None`` or
    the message that names the invalid cases and their keys (nothing has run)."""
    from peridynamics.app.checks import size_problem, work_problem
    from peridynamics.build.estimates import estimate_size, estimate_steps
    from peridynamics.deck import DeckError

    bad: dict[str, list[Case]] = {}
    load = _deck_loader(deck_path)
    for case in cases:
        try:
            deck = load([*sets, *case.set_args])
            problem = size_problem(deck, allow_large)
            est = estimate_size(deck)
            steps = estimate_steps(deck)
            if problem is None and est is not None:
                problem = work_problem(steps, est.bonds, allow_large, True)
            if problem is None:
                case.fingerprint = fingerprint(deck)
        except DeckError as exc:
            problem = "\n  ".join(f"{p}: {m}" if p else m for p, m in exc.errors)
        except OSError as exc:  # a mesh file that cannot be read
            problem = f"geometry.file: {exc}"
        if problem:
            bad.setdefault(problem, []).append(case)
            continue
        case.deck_name = deck.name
        work = (est.bonds if est is not None else 1.0) * (steps or 1.0)
        case.cost = min(work, 1e30) if math.isfinite(work) else 1e30
    if not bad:
        return None
    n_bad = sum(map(len, bad.values()))
    lines = [f"sweep: {n_bad} of {len(cases)} case(s) invalid; nothing was run:"]
    for problem, members in bad.items():
        first = members[0]
        sources = sorted({o.source for o in first.overrides})
        more = f" and {len(members) - 1} more case(s)" if len(members) > 1 else ""
        lines.append(
            f"  {first.folder} ({' '.join('--set ' + a for a in first.set_args)}; from "
            f"{', '.join(sources)}){more}:\n    {problem.replace(chr(10), chr(10) + '  ')}"
        )
    return "\n".join(lines)
