"""The whole deck: the schema :class:`Deck` that holds every section."""

from __future__ import annotations

from pydantic import Field, field_validator

from peridynamics.deck.bodies import BodySpec, InterfaceSpec, RigidBodySpec
from peridynamics.deck.contact import Contact
from peridynamics.deck.cracks import NotchSpec, Precrack
from peridynamics.deck.damage import Damage
from peridynamics.deck.discretisation import Discretisation
from peridynamics.deck.geometry import Geometry, geometry_dim
from peridynamics.deck.loading import BoundaryCondition
from peridynamics.deck.materials import AnyMaterial
from peridynamics.deck.output import Output
from peridynamics.deck.regions import RegionSpec
from peridynamics.deck.solver import AnySolver
from peridynamics.deck.thermal import Thermal
from peridynamics.deck.types import Strict


class Deck(Strict):
    """A whole simulation."""

    name: str = Field(min_length=1, max_length=100, pattern=r"^[A-Za-z0-9_.-]+$")
    description: str = ""
    geometry: Geometry
    discretisation: Discretisation
    material: AnyMaterial
    damage: Damage = Damage(model="none")
    node_sets: dict[str, RegionSpec] = {}
    precracks: list[Precrack] = []
    notches: list[NotchSpec] = []
    contact: Contact | None = None
    bodies: list[BodySpec] = []
    interfaces: list[InterfaceSpec] = []
    rigid_bodies: list[RigidBodySpec] = []
    boundary_conditions: list[BoundaryCondition] = []
    thermal: Thermal | None = None
    solver: AnySolver
    output: Output = Output()

    @field_validator("name")
    @classmethod
    def _file_stem(cls, v: str) -> str:
        if v in (".", ".."):
            raise ValueError("the name becomes a file name: use letters, digits, _ . -")
        return v

    @field_validator("node_sets")
    @classmethod
    def _names(cls, v: dict[str, RegionSpec]) -> dict[str, RegionSpec]:
        for name in v:
            if not name:
                raise ValueError("node set names must not be empty")
            if name == "all":
                raise ValueError("[all] 'all' is built in (every point); choose another name")
        return v

    @property
    def dim(self) -> int:
        """Spatial dimension."""
        return geometry_dim(self.geometry)
