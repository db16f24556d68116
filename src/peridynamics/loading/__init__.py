"""Loading: boundary/initial conditions on node sets and their time functions."""

from peridynamics.loading.conditions import (
    BodyForce,
    Fixed,
    InitialVelocity,
    PrescribedDisplacement,
    PrescribedVelocity,
    traction_as_body_force,
)
from peridynamics.loading.time_functions import (
    TIME_FUNCTIONS,
    Constant,
    Ramp,
    Table,
    TimeFunction,
    TriangularPulse,
)

__all__ = [
    "TIME_FUNCTIONS",
    "BodyForce",
    "Constant",
    "Fixed",
    "InitialVelocity",
    "PrescribedDisplacement",
    "PrescribedVelocity",
    "Ramp",
    "Table",
    "TimeFunction",
    "TriangularPulse",
    "traction_as_body_force",
]
