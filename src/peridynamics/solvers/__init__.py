"""Solvers: explicit dynamics now; ADR, implicit, FDM and hybrids in later issues."""

from peridynamics.solvers.explicit import (
    INTEGRATORS,
    ExplicitSolver,
    SimulationUnstable,
    UnstableTimeStep,
)
from peridynamics.solvers.state import State

__all__ = ["INTEGRATORS", "ExplicitSolver", "SimulationUnstable", "State", "UnstableTimeStep"]
