"""peridynamics: peridynamic simulation of deformation, wave propagation and fracture.

The names below are imported when first used (PEP 562), so that ``import
peridynamics.cli`` (the command line) starts without loading NumPy, Numba and the
models before it can handle Ctrl-C.

Importing the package first points Numba's cache of compiled kernels at a user cache
directory that survives reinstalls (:mod:`peridynamics.kernels.cache`; standard library
only), before any module of the package imports Numba.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

from peridynamics.kernels.cache import configure as _configure_numba_cache

_configure_numba_cache()  # before any kernel module imports Numba: sets NUMBA_CACHE_DIR

if TYPE_CHECKING:
    from peridynamics.api.batch import SweepResult, ensemble, sweep
    from peridynamics.api.calibrate import CalibrationError, calibrate
    from peridynamics.api.deck import Deck
    from peridynamics.api.result import Result
    from peridynamics.api.simulation import Callback, Simulation
    from peridynamics.app.run import RunInterrupted
    from peridynamics.bonds import Bonds, build_bonds
    from peridynamics.build.errors import SetupError
    from peridynamics.damage import CriticalStretch
    from peridynamics.deck.errors import DeckError
    from peridynamics.evaluation import Evaluator
    from peridynamics.families.pmb import BondBasedMaterial
    from peridynamics.geometry import PointCloud
    from peridynamics.solvers import ExplicitSolver, State
    from peridynamics.solvers.explicit import SimulationUnstable

#: public name -> the module it lives in
_LAZY = {
    "BondBasedMaterial": "peridynamics.families.pmb",
    "Bonds": "peridynamics.bonds",
    "CalibrationError": "peridynamics.api.calibrate",
    "Callback": "peridynamics.api.simulation",
    "CriticalStretch": "peridynamics.damage",
    "Deck": "peridynamics.api.deck",
    "DeckError": "peridynamics.deck.errors",
    "ExplicitSolver": "peridynamics.solvers",
    "Evaluator": "peridynamics.evaluation",
    "PointCloud": "peridynamics.geometry",
    "Result": "peridynamics.api.result",
    "RunInterrupted": "peridynamics.app.run",
    "SetupError": "peridynamics.build.errors",
    "Simulation": "peridynamics.api.simulation",
    "SimulationUnstable": "peridynamics.solvers.explicit",
    "State": "peridynamics.solvers",
    "SweepResult": "peridynamics.api.batch",
    "build_bonds": "peridynamics.bonds",
    "calibrate": "peridynamics.api.calibrate",
    "ensemble": "peridynamics.api.batch",
    "sweep": "peridynamics.api.batch",
}


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("peridynamics")
    except PackageNotFoundError:  # running from a source tree
        return "0.0.0+src"


def __getattr__(name: str) -> Any:
    if name == "__version__":
        globals()[name] = value = _version()
        return value
    if name in _LAZY:
        value = getattr(import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'peridynamics' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_LAZY, "__version__"])


__all__ = [
    "BondBasedMaterial",
    "Bonds",
    "CalibrationError",
    "Callback",
    "CriticalStretch",
    "Deck",
    "DeckError",
    "Evaluator",
    "ExplicitSolver",
    "PointCloud",
    "Result",
    "RunInterrupted",
    "SetupError",
    "Simulation",
    "SimulationUnstable",
    "State",
    "SweepResult",
    "__version__",
    "build_bonds",
    "calibrate",
    "ensemble",
    "sweep",
]
