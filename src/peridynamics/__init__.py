"""peridynamics: peridynamic simulation of deformation, wave propagation and fracture."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("peridynamics")
except PackageNotFoundError:  # running from a source tree
    __version__ = "0.0.0+src"

from peridynamics.bonds import Bonds, build_bonds
from peridynamics.damage import CriticalStretch
from peridynamics.evaluation import Evaluator
from peridynamics.families.pmb import BondBasedMaterial
from peridynamics.geometry import PointCloud
from peridynamics.solvers import ExplicitSolver, State

__all__ = [
    "BondBasedMaterial",
    "Bonds",
    "CriticalStretch",
    "ExplicitSolver",
    "Evaluator",
    "PointCloud",
    "State",
    "__version__",
    "build_bonds",
]
