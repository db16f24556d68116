"""Geometry: point clouds, grid generators, regions (node-set predicates), mesh import."""

from peridynamics.geometry.cloud import PointCloud
from peridynamics.geometry.generators import bar, box, cylinder, rectangle
from peridynamics.geometry.mesh import from_mesh
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
    "HalfSpace",
    "Layer",
    "NearestPoint",
    "PointCloud",
    "Polygon",
    "Region",
    "Sphere",
    "bar",
    "box",
    "cylinder",
    "from_mesh",
    "rectangle",
]
