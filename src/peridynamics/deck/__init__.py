"""YAML input decks with a strict schema (pydantic v2).

Every section forbids unknown keys; every number is checked for range; errors name the
key path (``material.youngs_modulus``) and say what is allowed. The schema is documented
with one example per section in ``docs/deck.md``.

One module per section (:mod:`~peridynamics.deck.geometry`,
:mod:`~peridynamics.deck.discretisation`, :mod:`~peridynamics.deck.materials`,
:mod:`~peridynamics.deck.damage`, :mod:`~peridynamics.deck.loading`,
:mod:`~peridynamics.deck.solver`, :mod:`~peridynamics.deck.output`,
:mod:`~peridynamics.deck.bodies`, ...), each with its own cross-section checks;
:mod:`~peridynamics.deck.checks` runs them in order; :mod:`~peridynamics.deck.reader`
reads YAML and applies ``--set`` overrides; :mod:`~peridynamics.deck.help` serves
``peridynamics help``.
"""

from peridynamics.deck.bodies import BodySpec, InterfaceSpec, RigidBodySpec, RigidShapeSpec
from peridynamics.deck.checks import cross_check
from peridynamics.deck.contact import Contact
from peridynamics.deck.cracks import NotchSpec, Precrack
from peridynamics.deck.damage import Damage, SEDSofteningSpec, WeibullSpec
from peridynamics.deck.derived import SPEED_OF_LIGHT, derived_errors
from peridynamics.deck.discretisation import Discretisation
from peridynamics.deck.errors import DeckError, named_key, validation_errors
from peridynamics.deck.geometry import (
    BarGeometry,
    BoxGeometry,
    CylinderGeometry,
    DiscGeometry,
    Geometry,
    GmshGeometry,
    ImageGeometry,
    MeshGeometry,
    PhaseSpec,
    RectangleGeometry,
    SurfaceGeometry,
    cross_section,
    geometry_dim,
    geometry_set_names,
)
from peridynamics.deck.loading import (
    BodyForceBC,
    BoundaryCondition,
    DisplacementBC,
    FixedBC,
    InitialVelocityBC,
    PressureBC,
    TractionBC,
    VelocityBC,
)
from peridynamics.deck.materials import (
    MATERIAL_SCHEMAS,
    AnyMaterial,
    CorrespondenceMaterialSpec,
    FamilySpec,
    LPSMaterialSpec,
    Material,
    MicropolarMaterialSpec,
    Viscosity,
)
from peridynamics.deck.output import (
    CrackPathSpec,
    CrackTip,
    Fracture,
    Output,
    Period,
    Probe,
    Quantity,
    Slice,
    StressStrain,
    WaveComparison,
)
from peridynamics.deck.reader import apply_overrides, load_deck, parse_deck, yaml_load
from peridynamics.deck.regions import RegionSpec
from peridynamics.deck.schema import Deck
from peridynamics.deck.solver import (
    SOLVER_SCHEMAS,
    ADRSolverSpec,
    AnySolver,
    HeatSolverSpec,
    Hybrid,
    Solver,
    StaticSolverSpec,
    SteadyHeatSolverSpec,
)
from peridynamics.deck.thermal import ConvectionBC, HeatFluxBC, TemperatureBC, Thermal
from peridynamics.deck.time_functions import (
    BlastTF,
    ConstantTF,
    RampTF,
    SinePulseTF,
    SquarePulseTF,
    TableTF,
    TimeFunctionSpec,
    TriangularPulseTF,
)

__all__ = [
    "ConvectionBC",
    "HeatFluxBC",
    "HeatSolverSpec",
    "SteadyHeatSolverSpec",
    "TemperatureBC",
    "Thermal",
    "MATERIAL_SCHEMAS",
    "SOLVER_SCHEMAS",
    "SPEED_OF_LIGHT",
    "ADRSolverSpec",
    "AnyMaterial",
    "AnySolver",
    "BarGeometry",
    "BlastTF",
    "BodyForceBC",
    "BodySpec",
    "BoundaryCondition",
    "BoxGeometry",
    "ConstantTF",
    "Contact",
    "CorrespondenceMaterialSpec",
    "CrackPathSpec",
    "CrackTip",
    "CylinderGeometry",
    "Damage",
    "Deck",
    "DeckError",
    "DiscGeometry",
    "Discretisation",
    "DisplacementBC",
    "FamilySpec",
    "FixedBC",
    "Fracture",
    "Geometry",
    "Hybrid",
    "InitialVelocityBC",
    "InterfaceSpec",
    "LPSMaterialSpec",
    "Material",
    "MeshGeometry",
    "MicropolarMaterialSpec",
    "NotchSpec",
    "Output",
    "Period",
    "Precrack",
    "PressureBC",
    "Probe",
    "Quantity",
    "RampTF",
    "RectangleGeometry",
    "RegionSpec",
    "RigidBodySpec",
    "RigidShapeSpec",
    "SEDSofteningSpec",
    "SinePulseTF",
    "Slice",
    "Solver",
    "SquarePulseTF",
    "StaticSolverSpec",
    "StressStrain",
    "TableTF",
    "TimeFunctionSpec",
    "TractionBC",
    "TriangularPulseTF",
    "VelocityBC",
    "Viscosity",
    "WaveComparison",
    "WeibullSpec",
    "apply_overrides",
    "cross_check",
    "cross_section",
    "derived_errors",
    "geometry_dim",
    "geometry_set_names",
    "GmshGeometry",
    "ImageGeometry",
    "PhaseSpec",
    "SurfaceGeometry",
    "load_deck",
    "named_key",
    "parse_deck",
    "validation_errors",
    "yaml_load",
]
