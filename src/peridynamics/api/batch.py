"""Sweeps and ensembles from Python: :func:`sweep`, :func:`ensemble`, :class:`SweepResult`.

Both run the command line's code (``peridynamics sweep`` and ``peridynamics ensemble``,
:mod:`peridynamics.app.sweep`, :mod:`peridynamics.app.ensemble`) with the same semantics:
the same folders, files, resumption of an interrupted sweep and exit conditions. An
invalid input raises :class:`~peridynamics.deck.errors.DeckError` with the message the
command prints.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import itertools
import tempfile
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from peridynamics.api.deck import Deck, _overrides
from peridynamics.api.result import Result
from peridynamics.app.exit_codes import EXIT_INVALID
from peridynamics.deck.errors import DeckError
from peridynamics.deck.schema import Deck as DeckSchema

if TYPE_CHECKING:
    import pandas

__all__ = ["SweepResult", "ensemble", "sweep"]


class SweepResult:
    """The outputs of a sweep or an ensemble: a table with one row per run, and each
    run's :class:`~peridynamics.api.result.Result`.

    Attributes
    ----------
    folder : Path
        The sweep's folder (``sweep.csv``, ``sweep.json``, one folder per case).
    exit_code : int
        The command's exit code: 0 every case completed, 4 some case failed or went
        unstable (see the table's ``status``), 3 an ensemble member went unstable.

    Examples
    --------
    >>> import peridynamics as pd
    >>> deck = pd.Deck.example("bar_wave_1d", {"solver.end_time": 2.0e-5})
    >>> swept = pd.sweep(deck, {"discretisation.spacing": [0.01, 0.005]}, jobs=2)
    >>> [round(r.results["spacing_m"], 6) for r in swept.results]
    [0.01, 0.005]
    """

    def __init__(self, folder: Path, table_file: str, exit_code: int, keep: Any = None) -> None:
        self.folder = folder
        self.exit_code = exit_code
        self._table_file = table_file
        self._keep = keep  # a temporary folder lives as long as the result

    @property
    def table(self) -> pandas.DataFrame:
        """One row per case (``sweep.csv``: the swept values, status, wall time and
        results) or per realisation (an ensemble's runs)."""
        import pandas as pd

        path = self.folder / self._table_file
        if path.suffix == ".csv":
            return pd.read_csv(path)
        import json

        data = json.loads(path.read_text(encoding="utf-8"))
        return pd.DataFrame(data.get("runs", []))

    @property
    def results(self) -> list[Result]:
        """The :class:`~peridynamics.api.result.Result` of every run that wrote a
        summary, in case order."""
        table = self.table
        if "folder" in table.columns:  # a sweep: its cases in order
            found = [self.folder / str(f) for f in table["folder"]]
        else:
            found = sorted(p.parent for p in self.folder.glob("*/summary.json"))
        return [Result(p) for p in found if (p / "summary.json").is_file()]

    def __repr__(self) -> str:
        return f"SweepResult(folder={str(self.folder)!r}, exit_code={self.exit_code})"


def _deck_file(deck: Deck | DeckSchema | str | Path, out: Path) -> Path:
    """A deck file for the command: the given file, or the deck written into ``out``."""
    if isinstance(deck, str | Path):
        return Path(deck)
    if isinstance(deck, DeckSchema):
        plain = Deck._of(deck)
        path = out / f"{plain.name}.yaml"
        out.mkdir(parents=True, exist_ok=True)
        plain.to_yaml(path)
        return path
    raise TypeError("deck: give a peridynamics.Deck or a deck file's path")


def _folder(out: str | Path | None, prefix: str) -> tuple[Path, Any]:
    if out is not None:
        return Path(out), None
    tmp = tempfile.TemporaryDirectory(prefix=f"peridynamics_{prefix}_")
    return Path(tmp.name), tmp


def _call(command: Any, args: argparse.Namespace) -> int:
    """Run a command; its problems (exit 2) as a DeckError with its message."""
    said = io.StringIO()
    with contextlib.redirect_stderr(said):
        code = int(command(args))
    if code == EXIT_INVALID:
        lines = [ln.removeprefix("invalid deck:").strip() for ln in said.getvalue().splitlines()]
        raise DeckError([("", "\n  ".join(ln for ln in lines if ln) or "invalid input")])
    return code


def sweep(
    deck: Deck | DeckSchema | str | Path,
    grid: Mapping[str, Sequence[Any]] | None = None,
    cases: Iterable[Mapping[str, Any]] | str | Path | None = None,
    overrides: Mapping[str, Any] | Iterable[str] | None = None,
    *,
    out: str | Path | None = None,
    jobs: int = 1,
    checkpoint_every: int | None = None,
    plot: Sequence[str] | None = None,
    allow_large: bool = False,
    quiet: bool = True,
) -> SweepResult:
    """Run a deck over a grid or a list of values (``peridynamics sweep``).

    Parameters
    ----------
    deck : Deck, str or Path
        The deck, or a deck file.
    grid : mapping of key path to values, optional
        The cases are the Cartesian product (``{"discretisation.spacing": [1e-3, 5e-4]}``).
    cases : list of mappings, or a file, optional
        Cases as ``[{key.path: value, ...}, ...]`` or a YAML / CSV file of them (crossed
        with ``grid`` when both are given).
    overrides : mapping or list of str, optional
        Values every case shares (``--set``).
    out : str or Path, optional
        The sweep's folder (default: a temporary folder that lives as long as the
        result); rerunning a sweep into the same folder skips the finished cases.
    jobs : int
        Cases run at a time (each a process with its share of the cores).
    checkpoint_every : int, optional
        Passed to each run: an interrupted case resumes from its checkpoint.
    plot : list of str, optional
        ``sweep.csv`` columns drawn in ``sweep.png``.
    allow_large : bool
        Run models the size checks would refuse.
    quiet : bool
        No progress lines or table (default ``True``).

    Examples
    --------
    >>> import peridynamics as pd
    >>> deck = pd.Deck.example("bar_wave_1d", {"solver.end_time": 2.0e-5})
    >>> swept = pd.sweep(deck, {"material.youngs_modulus": [10e9, 20e9]}, jobs=2)
    >>> swept.exit_code, len(swept.table), list(swept.table["status"])
    (0, 2, ['completed', 'completed'])
    """
    folder, keep = _folder(out, "sweep")
    folder.mkdir(parents=True, exist_ok=True)
    deck_path = _deck_file(deck, folder)
    rows: list[dict[str, Any]] = []
    if cases is not None and not isinstance(cases, str | Path):
        rows = [dict(c) for c in cases]
    if grid:
        keys = list(grid)
        product = [dict(zip(keys, vals, strict=True)) for vals in itertools.product(*grid.values())]
        rows = [{**r, **p} for r in (rows or [{}]) for p in product]
    cases_file = str(cases) if isinstance(cases, str | Path) else None
    if rows:
        if cases_file is not None:
            raise DeckError([("cases", "give cases as a file or as values with grid, not both")])
        path = folder / "sweep_cases.yaml"
        path.write_text(yaml.safe_dump(rows, sort_keys=False), encoding="utf-8")
        cases_file = str(path)
    from peridynamics.app.sweep import cmd_sweep

    args = argparse.Namespace(
        deck=str(deck_path),
        set=_overrides(overrides),
        grid=None,
        cases=cases_file,
        jobs=int(jobs),
        out=str(folder),
        plot=",".join(plot) if plot else None,
        checkpoint_every=checkpoint_every,
        dry_run=False,
        quiet=quiet,
        allow_large=allow_large,
    )
    return SweepResult(folder, "sweep.csv", _call(cmd_sweep, args), keep)


def ensemble(
    deck: Deck | DeckSchema | str | Path,
    n: int = 5,
    seed0: int = 0,
    overrides: Mapping[str, Any] | Iterable[str] | None = None,
    *,
    out: str | Path | None = None,
    allow_large: bool = False,
    quiet: bool = True,
) -> SweepResult:
    """Run ``n`` realisations of a deck's Weibull field, seeds ``seed0``, ``seed0 + 1``,
    ... (``peridynamics ensemble``); the table holds one row per realisation.

    Examples
    --------
    >>> import peridynamics as pd
    >>> pd.ensemble(pd.Deck.example("bar_wave_1d"), n=2)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    peridynamics.deck.errors.DeckError: invalid deck:
      ensemble: the deck has no damage.weibull section (nothing to vary)
    """
    folder, keep = _folder(out, "ensemble")
    folder.mkdir(parents=True, exist_ok=True)
    deck_path = _deck_file(deck, folder)
    from peridynamics.app.ensemble import cmd_ensemble

    args = argparse.Namespace(
        deck=str(deck_path),
        set=_overrides(overrides),
        n=int(n),
        seed0=int(seed0),
        out=str(folder),
        quiet=quiet,
        allow_large=allow_large,
    )
    return SweepResult(folder, "ensemble.json", _call(cmd_ensemble, args), keep)
