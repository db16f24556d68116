"""Solvers: explicit dynamics, adaptive dynamic relaxation, static (Newton), FDM and hybrids."""

from peridynamics.solvers.explicit import (
    INTEGRATORS,
    ExplicitSolver,
    SimulationUnstable,
    UnstableTimeStep,
)
from peridynamics.state import State

__all__ = ["INTEGRATORS", "ExplicitSolver", "SimulationUnstable", "State", "UnstableTimeStep"]
