"""The results of a run as Python objects: :class:`Result`.

A run folder (``peridynamics run`` or :meth:`peridynamics.api.simulation.Simulation.run`) read back:
``summary.json`` as a mapping, ``history.csv`` as a pandas DataFrame, the frames of the
``.pvd`` series as arrays or PyVista meshes, ``final_state.npz`` in float64, and the
figures as matplotlib objects. Nothing is read before it is asked for.
"""

from __future__ import annotations

import html
import json
import re
import shutil
import xml.etree.ElementTree as ET
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    import pandas
    from matplotlib.figure import Figure

__all__ = ["Result"]

_HEADER = re.compile(r"^(?P<name>.*?) \[(?P<unit>[^\]]*)\]$")


#: fields of three components in every dimension (not vectors of the model's dimension)
_THREE = ("principal_stress", "principal_direction")


class Result:
    """A finished (or interrupted) run's outputs, read from its folder.

    Parameters
    ----------
    folder : str or Path
        The run folder (it holds ``summary.json``).
    summary : dict, optional
        The summary mapping when already at hand (else read from the folder).

    Examples
    --------
    >>> import peridynamics as pd
    >>> result = pd.Simulation(pd.Deck.example("bar_wave_1d"), {"solver.end_time": 1e-4}).run()
    >>> result.status
    'completed'
    >>> list(result.history.columns[:3])
    ['time', 'kinetic_energy', 'strain_energy']
    >>> result.units["time"]
    's'
    >>> result.final["u"].shape
    (201, 1)
    >>> again = pd.Result.load(result.folder)
    >>> bool((again.final["u"] == result.final["u"]).all())
    True
    """

    def __init__(self, folder: str | Path, summary: dict[str, Any] | None = None) -> None:
        self.folder = Path(folder)
        if summary is None:
            path = self.folder / "summary.json"
            if not path.is_file():
                raise FileNotFoundError(
                    f"{str(self.folder)!r} is not a run folder: it has no summary.json "
                    "(give the folder of `peridynamics run --out` or Simulation(out=))"
                )
            summary = json.loads(path.read_text(encoding="utf-8"))
        self.summary: dict[str, Any] = summary
        #: what keeps a temporary run folder alive (the Simulation's, when out=None)
        self._keep: Any = None

    @classmethod
    def load(cls, folder: str | Path) -> Result:
        """Read a run folder (``summary.json``, and the rest when asked for)."""
        return cls(folder)

    # -- the summary ---------------------------------------------------------------
    @property
    def status(self) -> str:
        """``"completed"``, ``"interrupted"`` or ``"unstable"``."""
        return str(self.summary.get("status", "completed"))

    @property
    def results(self) -> dict[str, Any]:
        """The summary's ``results`` (SI units, named in the key: ``final_time_s``)."""
        return dict(self.summary.get("results", {}))

    @property
    def timing(self) -> dict[str, Any]:
        """The summary's ``timing`` (``wall_s``, ``steps``, ``bond_updates_per_s``, ...)."""
        return dict(self.summary.get("timing", {}))

    @property
    def crack(self) -> dict[str, Any]:
        """The crack and damage metrics of ``results``: every key that starts with
        ``crack``, ``fracture`` or ``damage``, ``max_damage`` and ``bonds_broken``."""
        keep = ("crack", "fracture", "damage")
        got = {k: v for k, v in self.results.items() if k.startswith(keep)}
        for key in ("max_damage", "bonds_broken"):
            if key in self.results:
                got[key] = self.results[key]
        return got

    # -- histories -------------------------------------------------------------------
    @cached_property
    def _history(self) -> tuple[pandas.DataFrame, dict[str, str]]:
        import pandas as pd

        path = self.folder / "history.csv"
        if not path.is_file():
            raise FileNotFoundError(
                f"no history.csv in {str(self.folder)!r} (output.history_csv: false?)"
            )
        table = pd.read_csv(path)
        names, units = [], {}
        for header in table.columns:
            m = _HEADER.match(str(header))
            name, unit = (m["name"], m["unit"]) if m else (str(header), "-")
            names.append(name)
            units[name] = unit
        table.columns = names
        table.attrs["units"] = units
        return table, units

    @property
    def history(self) -> pandas.DataFrame:
        """The histories (``history.csv``) as a DataFrame: one row per record, columns
        named without units (``time``, ``kinetic_energy``, probes by name, ...); the
        units are :attr:`units` (also ``history.attrs["units"]``)."""
        return self._history[0].copy()

    @property
    def units(self) -> dict[str, str]:
        """The unit of each :attr:`history` column (``{"time": "s", ...}``)."""
        return dict(self._history[1])

    # -- fields ----------------------------------------------------------------------
    @cached_property
    def _series(self) -> list[tuple[float, Path]]:
        name = self.summary.get("inputs", {}).get("name")
        pvd = self.folder / f"{name}.pvd"
        if not pvd.is_file():
            found = sorted(self.folder.glob("*.pvd"))
            if not found:
                return []
            pvd = found[0]
        root = ET.parse(pvd).getroot()
        return [(float(d.get("timestep", "nan")), self.folder / str(d.get("file")))
                for d in root.iter("DataSet")]  # fmt: skip

    @property
    def times(self) -> NDArray[np.float64]:
        """Time (s) of each recorded frame, shape (n_frames,)."""
        return np.array([t for t, _ in self._series], dtype=np.float64)

    def frame_path(self, index: int = -1) -> Path:
        """The file of frame ``index`` (``.vtu``, or ``.pvtu`` for a decomposed run)."""
        series = self._series
        if not series:
            raise FileNotFoundError(
                f"no frames in {str(self.folder)!r}: set output.vtk_every (steps between "
                "frames) or output.vtk_times"
            )
        try:
            return series[index][1]
        except IndexError:
            raise IndexError(
                f"frame {index} of {len(series)} (0 to {len(series) - 1}, or -1 the last)"
            ) from None

    def fields(self, index: int = -1) -> dict[str, NDArray]:
        """The point fields of frame ``index`` (default the last) as arrays.

        Returns a mapping with ``x`` (n, dim) reference positions (m) and each field the
        frame holds (``displacement`` (n, dim) m, ``velocity`` m/s, ``damage`` (n,),
        ``force_density`` N/m^3, the tensors ``stress`` (n, 3, 3) Pa and ``strain``,
        ... as ``output.fields`` chose), in the precision of
        ``output.frame_precision`` (float32 by default; :attr:`final` is float64).
        A decomposed run's frame joins its pieces in rank order.
        """
        import meshio

        path = self.frame_path(index)
        paths = _pieces(path) if path.suffix == ".pvtu" else [path]
        meshes = [meshio.read(p) for p in paths]
        dim = self._dim(meshes[0].points)
        out: dict[str, NDArray] = {"x": np.concatenate([m.points[:, :dim] for m in meshes])}
        for name in meshes[0].point_data:
            parts = [np.asarray(m.point_data[name]) for m in meshes]
            arr = np.concatenate(parts)
            if arr.ndim == 2 and arr.shape[1] == 3 and dim < 3 and name not in _THREE:
                arr = arr[:, :dim]
            elif arr.ndim == 2 and arr.shape[1] == 9:  # a tensor: stress, strain
                arr = arr.reshape(-1, 3, 3)
            out[name] = arr
        return out

    def _dim(self, points: NDArray) -> int:
        try:
            return int(np.asarray(self.final["x"]).shape[1])
        except (FileNotFoundError, KeyError):
            span = np.ptp(points, axis=0) if len(points) else np.zeros(3)
            return int(np.count_nonzero(span)) or 1

    def to_pyvista(self, index: int = -1) -> Any:
        """Frame ``index`` as a PyVista mesh (``pip install "peridynamics[viz]"``)."""
        try:
            import pyvista
        except ImportError:
            raise ImportError(
                'Result.to_pyvista needs PyVista: pip install "peridynamics[viz]"'
            ) from None
        return pyvista.read(self.frame_path(index))

    @cached_property
    def final(self) -> dict[str, NDArray]:
        """``final_state.npz`` (float64): ``u``, ``v`` (n, dim), ``damage`` (n,), ``x``,
        ``intact`` (n_bonds,), ``t``, ``step`` and what the model adds; the pieces of a
        decomposed run joined (:func:`peridynamics.io.final_state.read_final_state`)."""
        from peridynamics.io.final_state import read_final_state

        return read_final_state(self.folder)

    @property
    def damage(self) -> NDArray[np.float64]:
        """Point damage at the end, shape (n,)."""
        return self.final["damage"]

    # -- figures ---------------------------------------------------------------------
    @staticmethod
    def _inline() -> None:
        """In a notebook, have Jupyter show a returned Figure as an image: IPython's PNG
        formatter for Figures (what ``%matplotlib inline`` registers), added when absent;
        the figures themselves stay outside pyplot."""
        from peridynamics.app.run_progress import in_notebook

        if not in_notebook():
            return
        from IPython import get_ipython
        from IPython.core.pylabtools import select_figure_formats
        from matplotlib.figure import Figure

        shell = get_ipython()
        try:
            shell.display_formatter.formatters["image/png"].lookup_by_type(Figure)
        except KeyError:
            select_figure_formats(shell, {"png"})

    def plot_damage(self, title: str | None = None) -> Figure:
        """The final damage over the reference configuration (2-D; 3-D: largest along z)
        as a matplotlib Figure (nothing written)."""
        from peridynamics.io.plots import damage_figure

        self._inline()
        x = np.asarray(self.final["x"])
        if x.shape[1] < 2:
            raise ValueError("plot_damage draws 2-D and 3-D models; a bar: plot result.damage")
        spacing = float(self.results.get("spacing_m", 0.0)) or 1.0
        name = self.summary.get("inputs", {}).get("name", "")
        return damage_figure(x, self.damage, spacing, title or f"{name}: damage")

    def plot_history(self, *columns: str, title: str | None = None) -> Figure:
        """The named :attr:`history` columns (default: every column) against time, one
        panel each, as a matplotlib Figure (nothing written)."""
        from peridynamics.io.plots import histories_figure

        self._inline()
        table, units = self.history, self.units
        names = list(columns) or [c for c in table.columns if c != "time"]
        missing = [c for c in names if c not in table.columns]
        if missing:
            raise KeyError(f"no history column {missing}; the columns: {list(table.columns)}")
        series = {f"{c} [{units[c]}]": table[c].to_numpy() for c in names}
        name = self.summary.get("inputs", {}).get("name", "")
        return histories_figure(table["time"].to_numpy(), series, title or name)

    # -- files -----------------------------------------------------------------------
    def save(self, folder: str | Path) -> Result:
        """Copy the run folder to ``folder`` (which must not exist) and return the copy's
        result (a run into a temporary folder is kept this way)."""
        dest = Path(folder)
        if dest.exists():
            raise FileExistsError(f"{str(dest)!r} exists: give a new folder")
        shutil.copytree(self.folder, dest, ignore=shutil.ignore_patterns(".peridynamics.lock"))
        return Result(dest)

    def _repr_html_(self) -> str:
        r = self.results
        rows = "".join(
            f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
            f"<td style='text-align:left'>{html.escape(_short(r[k]))}</td></tr>"
            for k in ("n_points", "n_bonds", "steps", "final_time_s", "max_damage",
                      "bonds_broken", "max_displacement_m")
            if k in r
        )  # fmt: skip
        name = self.summary.get("inputs", {}).get("name", "")
        return (
            f"<div><b>Result {html.escape(name)}</b> ({html.escape(self.status)}, "
            f"{html.escape(str(self.folder))})<table>{rows}</table></div>"
        )

    def __repr__(self) -> str:
        name = self.summary.get("inputs", {}).get("name", "")
        return f"Result({name!r}, status={self.status!r}, folder={str(self.folder)!r})"


def _short(value: Any) -> str:
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def _pieces(pvtu: Path) -> list[Path]:
    """The piece files a ``.pvtu`` joins, in rank order."""
    root = ET.parse(pvtu).getroot()
    return [pvtu.parent / str(p.get("Source")) for p in root.iter("Piece") if p.get("Source")]
