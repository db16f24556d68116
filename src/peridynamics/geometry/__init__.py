"""Geometry: point clouds, grid generators, regions (node-set predicates), notches, mesh
import."""

from peridynamics.geometry.cloud import GeometryFitWarning, GridFit, PointCloud
from peridynamics.geometry.generators import bar, box, cylinder, disc, rectangle
from peridynamics.geometry.mesh import from_mesh
from peridynamics.geometry.notches import Notch
from peridynamics.geometry.regions import (
    Ball,
    Box,
    Circle,
    CylinderRegion,
    Everywhere,
    HalfSpace,
    Layer,
    NearestPoint,
    Polygon,
    Region,
    Sphere,
)

__all__ = [
    "Ball",
    "Box",
    "Circle",
    "CylinderRegion",
    "Everywhere",
    "GeometryFitWarning",
    "GridFit",
    "HalfSpace",
    "Layer",
    "NearestPoint",
    "Notch",
    "PointCloud",
    "Polygon",
    "Region",
    "Sphere",
    "bar",
    "box",
    "cylinder",
    "disc",
    "from_mesh",
    "rectangle",
]
