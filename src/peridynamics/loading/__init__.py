"""Loading: boundary/initial conditions on node sets and their time functions."""

from peridynamics.loading.blast import BlastPulse
from peridynamics.loading.blast_parameters import BlastRangeWarning, kingery_bulmash
from peridynamics.loading.conditions import (
    BodyForce,
    Fixed,
    InitialVelocity,
    PrescribedDisplacement,
    PrescribedVelocity,
    cavity_pressure_as_body_force,
    traction_as_body_force,
)
from peridynamics.loading.time_functions import (
    Constant,
    Ramp,
    SinePulse,
    SquarePulse,
    Table,
    TimeFunction,
    TriangularPulse,
)

__all__ = [
    "BlastPulse",
    "BlastRangeWarning",
    "BodyForce",
    "Constant",
    "Fixed",
    "InitialVelocity",
    "PrescribedDisplacement",
    "PrescribedVelocity",
    "Ramp",
    "SinePulse",
    "SquarePulse",
    "Table",
    "TimeFunction",
    "TriangularPulse",
    "cavity_pressure_as_body_force",
    "kingery_bulmash",
    "traction_as_body_force",
]
