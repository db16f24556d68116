"""Calibration from Python: :func:`calibrate`, the code of ``peridynamics calibrate``
(:mod:`peridynamics.app.calibrate`) with the same files, runs and resumption."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from peridynamics.api.deck import Deck
from peridynamics.app.calibrate import calibrate as _calibrate
from peridynamics.app.calibrate_spec import (
    CalibrationError,
    CalibrationSpec,
    load_spec,
    parse_spec,
)

__all__ = ["CalibrationError", "calibrate"]


def calibrate(
    deck: str | Path | Deck,
    calibration: str | Path | Mapping[str, Any],
    out: str | Path | None = None,
    jobs: int | None = None,
    sets: Sequence[str] = (),
    quiet: bool = True,
) -> dict[str, Any]:
    """Fit deck values to measured data (docs/calibration.md).

    Parameters
    ----------
    deck : path or Deck
        The deck file, or a :class:`~peridynamics.api.deck.Deck` (written to
        ``out/deck.yaml`` first; a Deck read from a file with a mesh keeps its path).
    calibration : path or mapping
        The calibration file, or its content as a mapping (relative data paths then
        start from the current folder).
    out : path, optional
        The calibration folder (default ``results/<deck name>_calibration``); started
        again over the same folder, the runs it has are read back.
    jobs : int, optional
        Runs at a time (overrides ``options.jobs``).
    sets : sequence of str
        ``key.path=value`` overrides of every run.

    Returns
    -------
    dict
        The report (``report.json``): ``parameters`` (key -> fitted value),
        ``uncertainty`` (standard errors, intervals, correlations), ``misfit``,
        ``targets``, ``runs``.

    Raises
    ------
    CalibrationError
        Naming the key of the calibration file, the data file or the run at fault.

    Examples
    --------
    >>> import peridynamics as pd
    >>> report = pd.calibrate(  # doctest: +SKIP
    ...     "examples/calibration/plate.yaml", "data/calibration.yml", jobs=2)
    >>> report["parameters"]["material.youngs_modulus"]  # doctest: +SKIP
    70100238956.56529
    """
    if isinstance(calibration, Mapping):
        spec: CalibrationSpec = parse_spec(dict(calibration))
        base, name = Path.cwd(), "(mapping)"
    else:
        spec = load_spec(calibration)
        base, name = Path(calibration).resolve().parent, str(Path(calibration).resolve())
    if jobs is not None:
        data = spec.model_dump()
        data["options"]["jobs"] = jobs
        spec = parse_spec(data, "jobs")
    if isinstance(deck, Deck):
        stem = deck.name
        folder = Path(out or Path("results") / f"{stem}_calibration").resolve()
        folder.mkdir(parents=True, exist_ok=True)
        deck_path = folder / "deck.yaml"
        deck.to_yaml(deck_path)
    else:
        deck_path = Path(deck).resolve()
        if not deck_path.is_file():
            raise CalibrationError(f"no deck file {str(deck)!r}")
        folder = Path(out or Path("results") / f"{deck_path.stem}_calibration").resolve()
    return _calibrate(spec, deck_path, folder, base, list(sets), quiet, spec_name=name)
