"""Deck sections ``bodies``, ``interfaces`` and ``rigid_bodies`` -> model objects.

:func:`build_body_points` gives the deformable points (each body contiguous) and
:func:`build_bodies_model` the evaluator: one force model and damage law per body
(:class:`~peridynamics.bodies.composite.CompositeForceModel`) when there are several
deformable bodies, the plain single-body model otherwise, and the rigid bodies
(:class:`~peridynamics.bodies.rigid.RigidSystem`) in either case.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics import deck as dk
from peridynamics.bodies.build import BodyLayout, assemble_points, build_interfaces, split_bonds
from peridynamics.bodies.composite import (
    BodiesMaterial,
    BodyPart,
    sub_bonds,
    sub_cloud,
)
from peridynamics.bodies.composite_damage import BodiesDamage
from peridynamics.bodies.rigid import RigidBody, RigidSystem
from peridynamics.bonds.bonds import Bonds
from peridynamics.build.errors import SetupError
from peridynamics.build.geometry import geometry_cloud
from peridynamics.build.loads import time_function
from peridynamics.build.materials import (
    build_contact,
    build_damage,
    build_material,
    build_model,
    calibrate_fracture_energy,
)
from peridynamics.build.regions import to_region
from peridynamics.communicator import SERIAL, active_comm, using
from peridynamics.evaluation import Evaluator
from peridynamics.geometry.cloud import PointCloud


def has_bodies(deck: dk.Deck) -> bool:
    """True for a deck with further deformable bodies or interfaces."""
    return bool(deck.bodies or deck.interfaces)


def build_body_points(deck: dk.Deck, main: PointCloud) -> tuple[PointCloud, BodyLayout]:
    """The deformable points of every body (``main`` first) and where each body is."""

    def geometry(g: Any) -> PointCloud:
        return geometry_cloud(g, deck.discretisation)

    def select(cloud: PointCloud, region: dk.RegionSpec) -> NDArray[np.intp]:
        # a region may name the node sets the geometry brings (an image's phases)
        return cloud.select(to_region(region, cloud.node_sets, cloud.spacing))

    try:
        return assemble_points(main, deck.bodies, geometry, select)
    except (ValueError, KeyError) as exc:
        raise SetupError("bodies", str(exc).strip("'\"")) from None


def body_layout(deck: dk.Deck, cloud: PointCloud) -> BodyLayout:
    """Where each body's points are, from the body node sets of a built cloud: the
    bodies in point order (deck order in one process; on a rank of a decomposed run
    the owned body first, and only the bodies it holds points of)."""
    ranges = []
    for name in ("main", *(b.name for b in deck.bodies)):
        idx = cloud.node_set(name)
        if len(idx) == 0:
            continue  # a rank holds no point of this body
        if int(idx[-1]) - int(idx[0]) != len(idx) - 1:
            raise ValueError(f"the points of body {name!r} are not contiguous")
        ranges.append((int(idx[0]), len(idx), name))
    ranges.sort()
    starts = [0]
    for start, n, name in ranges:
        if start != starts[-1]:
            raise ValueError(f"the points of body {name!r} do not follow the previous body's")
        starts.append(start + n)
    if starts[-1] != cloud.n_points:
        raise ValueError("the bodies do not cover every point")
    return BodyLayout(tuple(r[2] for r in ranges), tuple(starts))


def _body_cloud(cloud: PointCloud, start: int, stop: int) -> PointCloud:
    """The body's own points as a cloud, with the deck's node sets restricted to it."""
    sub = sub_cloud(cloud, start, stop)
    sets = {}
    for name, idx in cloud.node_sets.items():
        keep = idx[(idx >= start) & (idx < stop)] - start
        sets[name] = keep
    return sub.with_node_sets(**sets)


def build_bodies_model(
    deck: dk.Deck,
    cloud: PointCloud,
    bonds_all: Bonds,
    layout: BodyLayout,
    body_forces: list,
    contact: Any,
) -> Evaluator:
    """The evaluator of a deck with several deformable bodies (see module docstring)."""
    if deck.damage.sed_softening is not None or any(
        b.damage is not None and b.damage.sed_softening is not None for b in deck.bodies
    ):
        raise SetupError(
            "damage.sed_softening",
            "SED softening is built for single-body decks; use a softening bond law "
            "(damage.bond_law) with several bodies",
        )
    comm = active_comm()
    try:
        bonds, body = split_bonds(cloud, bonds_all, layout, n_checked=comm.n_owned)
    except ValueError as exc:
        raise SetupError("bodies", str(exc)) from None
    materials, specs = {}, {}
    for k, spec in enumerate((None, *deck.bodies)):
        m_spec = deck.material if spec is None or spec.material is None else spec.material
        d_spec = deck.damage if spec is None or spec.damage is None else spec.damage
        key = "material" if spec is None or spec.material is None else f"bodies.{k - 1}.material"
        if getattr(m_spec, "viscosity", None) is not None:
            raise SetupError(f"{key}.viscosity", "viscosity is built for single-body decks")
        if m_spec.model == "micropolar":
            raise SetupError(f"{key}.model", "micropolar bodies cannot be combined with others")
        try:
            material = build_material(m_spec, deck.discretisation)
        except SetupError as exc:
            raise SetupError(key, str(exc).split(": ", 1)[-1]) from None
        name = "main" if spec is None else spec.name
        materials[name], specs[name] = material, (m_spec, d_spec, key)
    parts = []
    for k, name in enumerate(layout.names):
        m_spec, d_spec, key = specs[name]
        start, stop = layout.range_of(k)
        local = _body_cloud(cloud, start, stop)
        own = sub_bonds(bonds, start, stop)
        materials[name] = calibrate_fracture_energy(
            materials[name], deck.discretisation, local, own, key
        )
        damage = build_damage(d_spec, m_spec, materials[name], local, own)
        parts.append(BodyPart(name, start, stop, materials[name], damage))
    try:
        interfaces = build_interfaces(
            deck.interfaces, cloud, bonds_all, body, layout, materials,
            any_rank=comm.any,
        )  # fmt: skip
    except ValueError as exc:
        raise SetupError("interfaces", str(exc)) from None
    try:
        # each body's model is made from the points held here alone: on a rank of a
        # decomposed run the ghosts it reads have their families (parallel/bodies.py), so
        # no body's set-up exchanges anything (the bodies held differ between ranks)
        with using(SERIAL):
            return Evaluator(
                cloud,
                bonds,
                BodiesMaterial(tuple(parts), tuple(interfaces), materials["main"]),
                BodiesDamage(tuple(parts)),
                body_forces,
                surface_correction=deck.discretisation.surface_correction,
                contact=contact,
                damping=getattr(deck.solver, "damping", 0.0),
                comm=comm,
            )
    except ValueError as exc:
        raise SetupError("bodies", str(exc)) from None


def build_deck_model(
    deck: dk.Deck, cloud: PointCloud, bonds: Bonds, body_forces: list
) -> Evaluator:
    """The evaluator of a deck: :func:`build_bodies_model` (with the deck's contact) for
    several deformable bodies, else :func:`~peridynamics.build.materials.build_model`;
    the same in one process and on a rank of a decomposed run."""
    if not has_bodies(deck):
        return build_model(deck, cloud, bonds, body_forces)
    contact = build_contact(deck, cloud, bonds, build_material(deck.material, deck.discretisation))
    return build_bodies_model(deck, cloud, bonds, body_layout(deck, cloud), body_forces, contact)


def rigid_mass_properties(
    shape: Any, density: float, thickness: float, dim: int
) -> tuple[NDArray[np.float64], float, NDArray[np.float64]]:
    """(centroid (dim,), mass (kg), inertia about the centroid (3, 3), kg m^2) of an
    analytic rigid shape; a 2-D shape is a prism of the model's ``thickness``."""
    kind = type(shape).__name__
    c = np.asarray(shape.center, dtype=float)
    if kind == "Box":
        h = 2.0 * np.asarray(shape.half_extents, dtype=float)
        if dim == 2:
            mass = density * h[0] * h[1] * thickness
            izz = mass * (h[0] ** 2 + h[1] ** 2) / 12.0
            return c, mass, np.diag([izz, izz, izz])
        mass = density * float(np.prod(h))
        a, b, cc = h
        return c, mass, mass / 12.0 * np.diag([b * b + cc * cc, a * a + cc * cc, a * a + b * b])
    r = float(shape.radius)
    if dim == 2:  # sphere and cylinder are discs
        mass = density * math.pi * r * r * thickness
        izz = 0.5 * mass * r * r
        return c, mass, np.diag([izz, izz, izz])
    if kind == "Sphere":
        mass = density * 4.0 / 3.0 * math.pi * r**3
        return c, mass, np.eye(3) * 0.4 * mass * r * r
    length = 2.0 * float(shape.half_length)
    mass = density * math.pi * r * r * length
    perp = mass * (3.0 * r * r + length * length) / 12.0
    inertia = np.full(3, perp)
    inertia[int(shape.axis)] = 0.5 * mass * r * r
    return c, mass, np.diag(inertia)


def point_mass_properties(
    x: NDArray[np.float64], volume: NDArray[np.float64], density: float
) -> tuple[NDArray[np.float64], float, NDArray[np.float64]]:
    """(centroid, mass, inertia about the centroid (3, 3)) of a rigid point set."""
    m = density * volume
    mass = float(m.sum())
    c = (m[:, None] * x).sum(axis=0) / mass
    r = np.zeros((len(x), 3))
    r[:, : x.shape[1]] = x - c
    inertia = np.einsum("k,kab->ab", m, np.einsum("ka,ka->k", r, r)[:, None, None] * np.eye(3))
    inertia -= np.einsum("k,ka,kb->ab", m, r, r)
    if x.shape[1] == 2:  # a plate in its plane: only Izz matters; keep the others positive
        inertia[0, 0] = inertia[1, 1] = inertia[2, 2]
        inertia[0, 1] = inertia[1, 0] = 0.0
    return c, mass, inertia


def attach_rigid_bodies(deck: dk.Deck, cloud: PointCloud, model: Any, bonds: Any) -> None:
    """Give ``model`` the deck's rigid bodies (``model.rigid``), if it has any; they move
    in explicit dynamics only (SetupError naming ``rigid_bodies`` otherwise)."""
    if not deck.rigid_bodies:
        return
    s = deck.solver
    if not isinstance(s, dk.Solver) or s.hybrid is not None or s.method == "fdm":
        raise SetupError(
            "rigid_bodies",
            "rigid bodies move in explicit dynamics (solver.type explicit, no "
            "hybrid or fdm method); for a quasi-static test load slowly with "
            "solver.damping",
        )
    c0 = model.material.micromodulus_constant(
        cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane
    )
    model.rigid = build_rigid_system(deck, cloud, model.density, c0, bonds.horizon)


def build_rigid_system(
    deck: dk.Deck, cloud: PointCloud, density: NDArray[np.float64], c0: float, horizon: float
) -> RigidSystem | None:
    """The deck's ``rigid_bodies`` (``None`` without any)."""
    if not deck.rigid_bodies:
        return None
    from peridynamics.bodies.rigid_contact import contact_for_shape, shape_of
    from peridynamics.evaluation.short_range_contact import ShortRangeContact

    con = deck.contact or dk.Contact()
    d_c = con.distance_factor * cloud.spacing
    c_s = ShortRangeContact.parks_stiffness(c0, d_c, horizon, con.stiffness_factor)
    bodies = []
    seating: dict[str, list[float]] = {}
    for k, spec in enumerate(deck.rigid_bodies):
        path = f"rigid_bodies.{k}"
        mu_s = con.friction_static if spec.friction_static is None else spec.friction_static
        mu_k = con.friction_kinetic if spec.friction_kinetic is None else spec.friction_kinetic
        try:
            if spec.shape.points is not None:
                pts = geometry_cloud(spec.shape.points, deck.discretisation)
                if pts.dim != cloud.dim:
                    raise ValueError(f"a {pts.dim}-D rigid body in a {cloud.dim}-D model")
                rho = 1.0 if spec.density is None else spec.density
                center, mass, inertia = point_mass_properties(pts.x, pts.volume, rho)
                shape: Any = pts
            else:
                shape = shape_of(spec.shape, cloud.dim, cloud.cross_section)
                if spec.shape.plane is not None:
                    center, mass, inertia = np.asarray(shape.point), math.inf, np.eye(3)
                else:
                    rho = 1.0 if spec.density is None else spec.density
                    center, mass, inertia = rigid_mass_properties(
                        shape, rho, cloud.cross_section, cloud.dim
                    )
            vel = np.zeros(cloud.dim) if spec.velocity is None else np.asarray(spec.velocity)
            if vel.shape != (cloud.dim,):
                raise ValueError(f"velocity needs {cloud.dim} components, got {len(vel)}")
            if spec.touch is not False:
                way = vel if spec.touch is True else np.asarray(spec.touch, dtype=float)
                if way.shape != (cloud.dim,):
                    raise ValueError(f"touch needs {cloud.dim} components, got {len(way)}")
                shift = touching_shift(shape, cloud.x, way / np.linalg.norm(way), 0.5 * d_c)
                shape = moved_shape(shape, shift)
                center = center + shift
                seating[spec.name] = shift.tolist()
            contact = contact_for_shape(shape, center, 0.5 * d_c, c_s, mu_s, mu_k)
            omega = np.zeros(3)
            if spec.angular_velocity is not None:
                w = np.asarray(spec.angular_velocity, dtype=float)
                if cloud.dim == 2 and w.size == 1:
                    omega[2] = w[0]
                elif w.size == 3:
                    omega = w
                else:
                    raise ValueError("angular_velocity: one number (2-D, about z) or three (3-D)")
            bodies.append(
                RigidBody(
                    spec.name,
                    cloud.dim,
                    contact,
                    center,
                    spec.motion,
                    vel,
                    None if spec.time_function is None else time_function(spec.time_function),
                    mass if spec.motion == "free" else math.inf,
                    inertia,
                    omega,
                )
            )
        except ValueError as exc:
            raise SetupError(path, str(exc)) from None
    try:
        system = RigidSystem(bodies, cloud.volume, density)
    except ValueError as exc:
        raise SetupError("rigid_bodies", str(exc)) from None
    system.seating = seating
    return system


def moved_shape(shape: Any, shift: NDArray[np.float64]) -> Any:
    """The analytic shape translated by ``shift`` (m)."""
    from dataclasses import replace

    if hasattr(shape, "center"):
        return replace(shape, center=tuple(np.asarray(shape.center) + shift))
    return replace(shape, point=tuple(np.asarray(shape.point) + shift))


def touching_shift(
    shape: Any, x: NDArray[np.float64], direction: NDArray[np.float64], radius: float
) -> NDArray[np.float64]:
    """The translation s d of ``shape`` along the unit ``direction`` after which its
    nearest point of ``x`` is exactly at the contact radius (bisection on s to 1e-12 of
    the model size). Raises when the body never meets the points along that line."""

    comm = active_comm()  # under MPI: x are a rank's points, the minimum the body's

    def gap(s: float) -> float:
        phi, _ = shape.evaluate(x - s * direction)
        return comm.min(float(phi.min()) if phi.size else np.inf) - radius

    span = max(comm.max(float(hi)) + comm.max(-float(lo)) for lo, hi in zip(
        x.min(axis=0), x.max(axis=0), strict=True))  # fmt: skip
    lo = 0.0
    if gap(0.0) <= 0:  # already overlapping: back off first
        while gap(lo) <= 0 and lo > -4.0 * span:
            lo -= radius
    hi = lo + radius
    while gap(hi) > 0:  # march in steps of the contact radius: no thin wall is skipped
        lo, hi = hi, hi + radius
        if hi > 4.0 * span:
            raise ValueError(
                "touch: the body does not meet the deformable points when moved along its "
                "velocity; check its position and velocity"
            )
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if gap(mid) > 0:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-12 * span:
            break
    return lo * direction
