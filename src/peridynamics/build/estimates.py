"""Estimates of a model from its deck before anything is built: its size (points,
bonds, memory) and the steps of an explicit run (the continuum estimate of the stable
time step)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from peridynamics.deck import (
    BarGeometry,
    BoxGeometry,
    CylinderGeometry,
    Deck,
    DiscGeometry,
    RectangleGeometry,
    Solver,
)
from peridynamics.deck.geometry import ImageGeometry, SurfaceGeometry
from peridynamics.geometry.image_phases import grid_cells, image_shape
from peridynamics.geometry.surface_fill import estimate_fill_points


def file_points(g: object, spacing: float) -> float | None:
    """Points of a geometry read from a file, estimated before any is allocated: a
    surface fill's enclosed volume / dx^3 (the surface is read), an image's grid cells
    (its header is read); ``None`` for a mesh or a Gmsh model (known once built) or a
    file that cannot be read (the build says why)."""
    try:
        if isinstance(g, SurfaceGeometry):
            return estimate_fill_points(g.file, spacing, g.scale)
        if isinstance(g, ImageGeometry):
            nx, ny = grid_cells(image_shape(g.file), g.pixel_size, spacing)
            return float(nx) * float(ny)
    except ValueError:
        return None
    return None


@dataclass(frozen=True)
class SizeEstimate:
    """The size of a model estimated from its deck before anything is built: ``points``
    from the bounding volume / spacing^dim, ``bonds`` (directed) from points x the
    volume of the horizon ball / spacing^dim, ``bytes`` of peak memory from the
    measured cost of a run (about 150 bytes per bond and 500 per point, plus the
    interpreter and libraries). Floats: absurd decks give 1e30, not an overflow."""

    points: float
    bonds: float
    bytes: float

    BASE_BYTES = 0.3e9
    BYTES_PER_POINT = 500.0
    BYTES_PER_BOND = 150.0

    def describe(self) -> str:
        """One line: points, bonds, GB."""
        return (
            f"about {self.points:.3g} points, {self.bonds:.3g} bonds, "
            f"{self.bytes / 1e9:.3g} GB of memory"
        )


def estimate_size(deck: Deck, n_points: float | None = None) -> SizeEstimate | None:
    """Estimate points, bonds and memory from the deck alone (``None`` for a mesh or
    Gmsh geometry unless ``n_points`` is given: its points are only known once it is
    read; a surface or an image is estimated from its file, :func:`file_points`)."""
    g, d = deck.geometry, deck.discretisation
    dx, dim = d.spacing, deck.dim

    def cells(length: float) -> float:
        return length / dx

    if n_points is None:
        if isinstance(g, BarGeometry):
            n_points = cells(g.length) + 1.0
        elif isinstance(g, RectangleGeometry):
            n_points = cells(g.size[0]) * cells(g.size[1])
        elif isinstance(g, BoxGeometry):
            n_points = cells(g.size[0]) * cells(g.size[1]) * cells(g.size[2])
        elif isinstance(g, CylinderGeometry):
            n_points = math.pi * cells(g.radius) ** 2 * cells(g.length)
        elif isinstance(g, DiscGeometry):
            n_points = math.pi * cells(g.radius) ** 2
        else:
            n_points = file_points(g, dx)
            if n_points is None:
                return None
    reach = d.delta + (0.5 * dx if d.partial_volume == "extended" else 0.0)
    r = reach / dx
    family = {1: 2.0 * r, 2: math.pi * r * r, 3: 4.0 / 3.0 * math.pi * r**3}[dim]
    n = float(n_points)
    family = min(family, max(n - 1.0, 0.0))  # a family holds at most every other point
    bonds = n * family
    size = SizeEstimate.BASE_BYTES + SizeEstimate.BYTES_PER_POINT * n
    return SizeEstimate(n, bonds, size + SizeEstimate.BYTES_PER_BOND * bonds)


def estimate_steps(deck: Deck) -> float | None:
    """Steps of an explicit run estimated before the bonds exist (``None`` for a static
    solver): ``steps``, or ``end_time`` / dt with dt = ``time_step`` or ``safety_factor``
    x the continuum estimate of the stable step of the PMB model (delta / (3 c) in 2-D,
    delta / (sqrt(12) c) in 3-D, delta / (c sqrt(2 H_m)) in 1-D, c = sqrt(E / rho)),
    lengthened as the built model's Lanczos estimate lengthens it (1.5 times in 2-D,
    1.8 in 3-D, measured on a plate and a box: :mod:`peridynamics.evaluation.spectral`).
    An estimate for the size guards, not the step the solver takes."""
    s = deck.solver
    if not isinstance(s, Solver):
        return None
    if s.steps is not None:
        return float(s.steps)
    assert s.end_time is not None
    if s.time_step is not None:
        return math.ceil(s.end_time / s.time_step)
    m, d = deck.material, deck.discretisation
    speed = math.sqrt(m.youngs_modulus / m.density)
    m_ratio = max(d.delta / d.spacing, 1.0)
    harmonic = math.log(m_ratio) + 0.5772 + 0.5 / m_ratio
    factor = {1: math.sqrt(2.0 * harmonic), 2: 3.0, 3: math.sqrt(12.0)}[deck.dim]
    lanczos = {1: 1.0, 2: 1.5, 3: 1.8}[deck.dim]
    dt = s.safety_factor * lanczos * d.delta / (factor * speed)
    return s.end_time / dt if dt > 0 else math.inf
