"""Build a simulation from a deck and run it with observers, checkpoints and output.

``Simulation.from_deck(deck)`` builds geometry -> bonds -> model -> solver;
``Simulation.run(out_dir)`` (:class:`peridynamics.run_loop.RunLoop`) steps it, records
histories, writes VTK frames, the figure, ``final_state.npz`` and ``summary.json``.
"""

from __future__ import annotations

import hashlib
import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bodies.from_deck import (
    body_layout,
    build_bodies_model,
    build_body_points,
    build_rigid_system,
    has_bodies,
)
from peridynamics.bonds import build_bonds, make_crack
from peridynamics.bonds.bonds import Bonds
from peridynamics.damage import NO_DAMAGE, CriticalStretch, SEDSoftening, WeibullField
from peridynamics.geometry import (
    Notch,
    PointCloud,
    bar,
    box,
    cylinder,
    disc,
    from_mesh,
    rectangle,
)
from peridynamics.io import deck as dk
from peridynamics.io.regions import to_region
from peridynamics.loading import conditions as bc
from peridynamics.loading import initial_fields
from peridynamics.loading import time_functions as tf
from peridynamics.materials import MATERIALS
from peridynamics.materials.viscosity import BondViscosity
from peridynamics.model import Model
from peridynamics.run_loop import RunInterrupted as RunInterrupted  # re-exported
from peridynamics.run_loop import RunLoop
from peridynamics.run_loop import _RateColumn as _RateColumn  # noqa: F401  (tests)
from peridynamics.solvers.base import Solver
from peridynamics.solvers.explicit import ExplicitSolver
from peridynamics.solvers.fdm import FDMModel1D
from peridynamics.solvers.hybrid import HybridSolver, SwitchAtStretch

COMP = {"x": 0, "y": 1, "z": 2}


class SetupError(ValueError):
    """The deck is valid but the model it describes is not (empty node set, ...)."""

    def __init__(self, path: str, message: str) -> None:
        self.path = path
        super().__init__(f"{path}: {message}")


# ------------------------------------------------------------------------ building
def geometry_cloud(g: Any, d: dk.Discretisation) -> PointCloud:
    """A geometry section (the deck's, a body's or a rigid body's) -> PointCloud without
    node sets, on the deck's discretisation."""
    dx = d.spacing
    try:
        if d.jitter > 0 and isinstance(g, dk.BarGeometry | dk.MeshGeometry):
            kind = "bar" if isinstance(g, dk.BarGeometry) else "mesh"
            raise ValueError(
                f"discretisation.jitter = {d.jitter} needs a rectangle, disc, box or cylinder "
                f"geometry, not a {kind} (a mesh's points are its cell centroids); set "
                "discretisation.jitter: 0"
            )
        if isinstance(g, dk.BarGeometry):
            cloud = bar(
                g.length, dx, area=g.area, origin=g.origin, nodes_on_boundary=g.nodes_on_boundary
            )
        elif isinstance(g, dk.RectangleGeometry):
            cloud = rectangle(
                g.size,
                dx,
                thickness=g.thickness,
                origin=g.origin,
                plane=g.plane,
                holes=[to_region(h) for h in g.holes],
                jitter=d.jitter,
                seed=d.seed,
            )
        elif isinstance(g, dk.DiscGeometry):
            cloud = disc(
                g.radius,
                dx,
                center=g.center,
                thickness=g.thickness,
                plane=g.plane,
                holes=[to_region(h) for h in g.holes],
                jitter=d.jitter,
                seed=d.seed,
            )
        elif isinstance(g, dk.BoxGeometry):
            cloud = box(
                g.size,
                dx,
                origin=g.origin,
                holes=[to_region(h) for h in g.holes],
                jitter=d.jitter,
                seed=d.seed,
            )
        elif isinstance(g, dk.CylinderGeometry):
            cloud = cylinder(
                g.radius,
                g.length,
                dx,
                origin=g.origin,
                holes=[to_region(h) for h in g.holes],
                jitter=d.jitter,
                seed=d.seed,
            )
        else:
            cloud = from_mesh(g.file, dim=g.dim, thickness=g.thickness, plane=g.plane, spacing=dx)
    except ValueError as exc:
        raise SetupError("geometry", str(exc)) from None
    return cloud


def deck_notches(deck: dk.Deck) -> list[Notch]:
    """The deck's ``notches`` as :class:`~peridynamics.geometry.notches.Notch` objects."""
    out = []
    for n, spec in enumerate(deck.notches):
        try:
            out.append(Notch(spec.start, spec.end, spec.width, spec.tip, spec.z))
        except ValueError as exc:
            raise SetupError(f"notches.{n}", str(exc)) from None
    return out


def _cut_notches(
    deck: dk.Deck, cloud: PointCloud, body_sets: dict[str, NDArray[np.intp]]
) -> tuple[PointCloud, dict[str, NDArray[np.intp]]]:
    """Remove the points inside the deck's notches (every body's); the body node sets
    are re-indexed (each body stays contiguous)."""
    notches = deck_notches(deck)
    if not notches:
        return cloud, body_sets
    cut = cloud.with_node_sets(**body_sets)
    for n, notch in enumerate(notches):
        try:
            cut = cut.remove(notch.region())
        except ValueError as exc:
            raise SetupError(f"notches.{n}", str(exc)) from None
    for name in body_sets:
        if cut.node_sets[name].size == 0:
            raise SetupError("notches", f"the notches remove every point of body {name!r}")
    return cut, {name: cut.node_sets[name] for name in body_sets}


def build_cloud(deck: dk.Deck) -> PointCloud:
    """Geometry section (and further bodies) -> PointCloud with the deck's node sets
    (plus 'all' and one set per body of a deck with ``bodies``); the points inside the
    deck's ``notches`` are removed before the node sets are built."""
    cloud = geometry_cloud(deck.geometry, deck.discretisation)
    body_sets: dict[str, NDArray[np.intp]] = {}
    if has_bodies(deck):
        fit = cloud.grid_fit
        cloud, layout = build_body_points(deck, cloud)
        cloud = replace(cloud, grid_fit=fit)
        body_sets = layout.node_sets()
        clash = sorted(set(body_sets) & set(deck.node_sets))
        if clash:
            raise SetupError(
                f"node_sets.{clash[0]}",
                "has the name of a body (each body is a node set of that name); rename it",
            )
        if "all" in body_sets:
            raise SetupError("bodies", "'all' is built in (every point); rename the body")
    cloud, body_sets = _cut_notches(deck, cloud, body_sets)
    sets: dict[str, NDArray[np.intp]] = {"all": np.arange(cloud.n_points), **body_sets}
    visiting: set[str] = set()

    def resolve(name: str) -> NDArray[np.intp]:
        if name in sets:
            return sets[name]
        if name in visiting:
            raise SetupError(f"node_sets.{name}", "node sets refer to each other in a cycle")
        visiting.add(name)
        spec = deck.node_sets[name]
        _collect_refs(spec, resolve)
        try:
            idx = cloud.select(to_region(spec, sets, cloud.spacing))
        except ValueError as exc:
            raise SetupError(f"node_sets.{name}", str(exc)) from None
        if idx.size == 0:
            raise SetupError(
                f"node_sets.{name}",
                "selects no point; check the region against the geometry "
                f"(points span {cloud.bounds[0].tolist()} .. "
                f"{cloud.bounds[1].tolist()} m)",
            )
        sets[name] = idx
        return idx

    for name in deck.node_sets:
        resolve(name)
    return cloud.with_node_sets(**sets)


def _collect_refs(spec: dk.RegionSpec, resolve: Callable[[str], Any]) -> None:
    k = spec.kind()
    v = getattr(spec, k)
    if k == "set":
        resolve(v)
    elif k in ("all_of", "any_of"):
        for s in v:
            _collect_refs(s, resolve)
    elif k == "not_":
        _collect_refs(v, resolve)


def _solver_options(s: dk.Solver, kin: list, init: list, time_step: float | None) -> dict[str, Any]:
    """Keyword arguments of :class:`ExplicitSolver` from the deck's solver section."""
    return dict(
        time_step=time_step,
        integrator=s.integrator,
        constraints=kin,
        initial_velocities=init,
        safety_factor=s.safety_factor,
        allow_unstable=s.allow_unstable,
        blowup_factor=s.blowup_factor,
        max_stretch=s.max_stretch,
        check_every=s.check_every,
        steps=s.steps,
        end_time=s.end_time,
    )


def _hybrid_solver(
    deck: dk.Deck, cloud: PointCloud, second: Model, body: list, kin: list, init: list
) -> HybridSolver:
    """The first (cheap) model and the hybrid solver around it and the deck's model."""
    s = deck.solver
    assert isinstance(s, dk.Solver) and s.hybrid is not None
    h = s.hybrid
    material = second.material
    first: Model
    if h.first == "fdm":
        first = FDMModel1D(cloud, material, body)
    else:
        bonds = build_bonds(
            cloud, h.first_horizon_factor * cloud.spacing, deck.discretisation.partial_volume
        )
        first = Model(cloud, bonds, material, NO_DAMAGE, body)
    limit = min(first.stable_time_step(), second.stable_time_step())
    dt = s.time_step if s.time_step is not None else s.safety_factor * limit
    common = _solver_options(s, kin, init, time_step=dt)
    return HybridSolver(
        ExplicitSolver(first, **common),
        ExplicitSolver(second, **common),
        SwitchAtStretch(h.switch_fraction),
    )


def build_solver(
    deck: dk.Deck, cloud: PointCloud, model: Model, body: list, kin: list, init: list
) -> Solver:
    """The deck's solver section -> a solver (registry: ``solver.type``)."""
    s = deck.solver
    try:
        if isinstance(s, dk.Solver):
            if s.backend == "warp":
                return _warp_solver(deck, model, kin, init)
            if s.hybrid is not None:
                if s.precision != "float64":
                    raise SetupError("solver.precision", "a hybrid run is float64 only")
                return _hybrid_solver(deck, cloud, model, body, kin, init)
            if s.precision != "float64":
                _set_precision(model, s.precision)
            return ExplicitSolver(model, **_solver_options(s, kin, init, s.time_step))
        if isinstance(s, dk.StaticSolverSpec):
            return build_static(s, model, kin, init)
        return build_adr(s, model, kin, init)
    except SetupError:
        raise
    except ValueError as exc:
        named, msg = dk.named_key(str(exc))
        key = "solver.time_step" if isinstance(s, dk.Solver) else "solver"
        raise SetupError(named or key, msg) from None


def _warp_solver(deck: dk.Deck, model: Model, kin: list, init: list) -> Solver:
    """``solver.backend: warp``: the explicit step on a Warp device
    (:class:`~peridynamics.backends.warp_solver.WarpExplicitSolver`); what the backend
    does not run is refused by its deck key."""
    s = deck.solver
    assert isinstance(s, dk.Solver)
    for key, bad, why in (
        ("solver.hybrid", s.hybrid is not None, "hybrid runs are on the Numba backend only"),
        ("solver.method", s.method != "pd", "the FDM solver is on the Numba backend only"),
        ("solver.precision", s.precision != "float64", "the Warp backend is float64"),
    ):
        if bad:
            raise SetupError(key, f"{why}; remove it or set solver.backend: numba")
    from peridynamics.backends.warp_device import require_warp
    from peridynamics.backends.warp_families import unsupported

    try:
        require_warp()
    except ImportError as exc:
        raise SetupError("solver.backend", str(exc)) from None
    got = unsupported(model, s.integrator)
    if got is not None:
        raise SetupError(got[0], f"{got[1]}; use solver.backend: numba (the default)")
    from peridynamics.backends.warp_solver import WarpExplicitSolver

    options = _solver_options(s, kin, init, s.time_step)
    try:
        return WarpExplicitSolver(model, device=s.device, **options)
    except ValueError as exc:
        raise SetupError("solver.device", str(exc)) from None


def _set_precision(model: Model, precision: str) -> None:
    """``solver.precision: float32``: the PMB force pass with critical-stretch damage in
    float32 (:meth:`PMBForceModel.set_precision`); other models are refused by name."""
    from peridynamics.damage.critical_stretch import CriticalStretchLaw
    from peridynamics.models.pmb import PMBForceModel

    fm = model.force_model
    why = ""
    if type(fm) is not PMBForceModel:
        why = f"material.model {getattr(fm, 'name', type(fm).__name__)!r} (or bodies)"
    elif not isinstance(model.damage_law, CriticalStretchLaw):
        why = "this damage law (only damage.critical_stretch / fracture_energy)"
    elif model.softening is not None:
        why = "damage.sed_softening"
    elif model.viscosity is not None:
        why = "material.viscosity"
    if why:
        raise SetupError(
            "solver.precision",
            f"float32 is available for the PMB model with critical-stretch damage, not for "
            f"{why}; remove solver.precision or set it to float64",
        )
    assert isinstance(fm, PMBForceModel)
    fm.set_precision(precision)


def build_static(s: Any, model: Model, kin: list, init: list) -> Solver:
    """The implicit static solver from ``solver: {type: static, ...}`` (every key of the
    section is a keyword of :class:`~peridynamics.solvers.static.StaticSolver`)."""
    from peridynamics.solvers.static import StaticSolver

    if init:
        raise ValueError("initial velocities have no meaning in a static run")
    return StaticSolver(model, constraints=kin, **s.model_dump(exclude={"type"}))


def build_adr(s: Any, model: Model, kin: list, init: list) -> Solver:
    """Adaptive dynamic relaxation from ``solver: {type: adr, ...}`` (every key of the
    section is a keyword of :class:`~peridynamics.solvers.adr.ADRSolver`)."""
    from peridynamics.solvers.adr import ADRSolver

    if init:
        raise ValueError("initial velocities have no meaning in a static (adr) run")
    return ADRSolver(model, constraints=kin, **s.model_dump(exclude={"type"}))


def time_function(spec: Any) -> tf.TimeFunction:
    """Deck time function -> object."""
    if isinstance(spec, dk.ConstantTF):
        return tf.Constant(spec.value)
    if isinstance(spec, dk.RampTF):
        return tf.Ramp(end=spec.end, start=spec.start)
    if isinstance(spec, dk.TableTF):
        return tf.Table(tuple(spec.times), tuple(spec.values))
    if isinstance(spec, dk.SinePulseTF):
        return tf.SinePulse(spec.duration)
    if isinstance(spec, dk.SquarePulseTF):
        return tf.SquarePulse(spec.duration)
    if isinstance(spec, dk.BlastTF):
        from peridynamics.loading.blast import BlastPulse

        return BlastPulse(spec.charge_kg, spec.standoff_m, spec.shape, spec.delay)
    return tf.TriangularPulse(spec.peak, spec.rise_time, spec.duration)


def _kinematic_components(spec: Any, dim: int) -> list[int]:
    """Components a displacement / velocity / fixed condition prescribes ([] otherwise)."""
    if isinstance(spec, dk.DisplacementBC | dk.VelocityBC):
        return [COMP[c] for c in spec.components]
    if isinstance(spec, dk.FixedBC):
        if spec.components:
            return [COMP[c] for c in spec.components if c != "rotation"]
        return list(range(dim))
    return []


def build_conditions(deck: dk.Deck, cloud: PointCloud) -> tuple[list, list, list]:
    """(body forces, kinematic constraints, initial velocities)."""
    body: list[bc.BodyForce] = []
    kin: list[bc.PrescribedDisplacement | bc.PrescribedVelocity | bc.Fixed] = []
    init: list[bc.InitialVelocity] = []
    owner = np.full((cloud.n_points, cloud.dim), -1)  # which kinematic BC holds a dof
    for ibc, spec in enumerate(deck.boundary_conditions):
        nodes = cloud.node_set(spec.set)
        comps = np.asarray(_kinematic_components(spec, cloud.dim), dtype=np.intp)
        if comps.size:
            taken = owner[np.ix_(nodes, comps)]
            if np.any(taken >= 0):
                other = int(taken[taken >= 0][0])
                raise SetupError(
                    f"boundary_conditions.{ibc}",
                    f"prescribes the same node and component as boundary_conditions.{other} "
                    f"(sets {spec.set!r} and {deck.boundary_conditions[other].set!r} "
                    "overlap); a degree of freedom can have one kinematic condition only",
                )
            owner[np.ix_(nodes, comps)] = ibc
        if isinstance(spec, dk.DisplacementBC | dk.VelocityBC):
            kind = (
                bc.PrescribedDisplacement
                if isinstance(spec, dk.DisplacementBC)
                else bc.PrescribedVelocity
            )
            values = {str(k): v for k, v in spec.components.items()}
            kin.append(kind(nodes, values, time_function(spec.time_function)))
        elif isinstance(spec, dk.FixedBC):
            kin.append(bc.Fixed(nodes, tuple(spec.components) if spec.components else None))
        elif isinstance(spec, dk.InitialVelocityBC):
            init.append(bc.InitialVelocity(nodes, _initial_field(spec, ibc, nodes, cloud)))
        elif isinstance(spec, dk.BodyForceBC):
            body.append(bc.BodyForce(nodes, tuple(spec.value), time_function(spec.time_function)))
        elif isinstance(spec, dk.PressureBC) and spec.center is not None:
            body.append(
                bc.cavity_pressure_as_body_force(
                    nodes,
                    spec.scale,
                    cloud.x,
                    cloud.volume,
                    np.asarray(spec.center, dtype=float),
                    cloud.spacing,
                    thickness=cloud.cross_section,
                    layer_thickness=spec.layer_thickness,
                    function=time_function(spec.time_function),
                )
            )
        else:  # traction or pressure on a flat face
            normal: NDArray[np.float64] | None
            if isinstance(spec, dk.PressureBC):
                assert spec.normal is not None
                n = np.asarray(spec.normal, dtype=float)
                traction = -spec.scale * n / np.linalg.norm(n)
                normal = n
            else:
                traction = np.asarray(spec.value, dtype=float)
                normal = None if spec.normal is None else np.asarray(spec.normal, dtype=float)
            body.append(
                bc.traction_as_body_force(
                    nodes,
                    traction,
                    cloud.x,
                    cloud.spacing,
                    normal=normal,
                    layer_thickness=spec.layer_thickness,
                    function=time_function(spec.time_function),
                    jittered=cloud.irregular,
                    volume=cloud.volume,
                    cross_section=cloud.cross_section,
                )
            )
    return body, kin, init


def _initial_field(
    spec: dk.InitialVelocityBC, ibc: int, nodes: NDArray[np.intp], cloud: PointCloud
) -> tuple[float, ...] | NDArray[np.float64]:
    """The value of an initial condition on ``nodes``: one vector when every component
    is a number, else one row per node (expressions of x, y, z evaluated at the nodes'
    reference positions, or the rows of the file). Raises SetupError naming the key."""
    path = f"boundary_conditions.{ibc}"
    if spec.file is not None:
        try:
            values = initial_fields.read_point_values(spec.file, cloud.dim)
            return initial_fields.point_rows(values, nodes, cloud.n_points, Path(spec.file).name)
        except ValueError as exc:
            raise SetupError(f"{path}.file", str(exc)) from None
    assert spec.value is not None
    if all(not isinstance(c, str) for c in spec.value):
        return tuple(float(c) for c in spec.value)
    x = cloud.x[nodes]
    out = np.empty((len(nodes), len(spec.value)))
    for k, comp in enumerate(spec.value):
        if not isinstance(comp, str):
            out[:, k] = float(comp)
            continue
        try:
            out[:, k] = initial_fields.FieldExpression(comp)(x)
        except ValueError as exc:
            raise SetupError(f"{path}.value.{k}", str(exc)) from None
        bad = ~np.isfinite(out[:, k])
        if np.any(bad):
            first = x[np.flatnonzero(bad)[0]].tolist()
            raise SetupError(
                f"{path}.value.{k}",
                f"{comp!r} is not finite at {int(bad.sum())} of the {len(nodes)} points of "
                f"set {spec.set!r} (first at x = {first} m)",
            )
    return out


def build_bonds_for(deck: dk.Deck, cloud: PointCloud) -> Bonds:
    """Bonds with partial volumes, pre-cracks and the bonds across notches cut.

    A notch cuts like a pre-crack along its centre line (``Notch.crack``); in 3-D a
    notch without a z-range cuts over the body's z-extent widened by one spacing."""
    d = deck.discretisation
    notches = deck_notches(deck)
    z_bounds = None
    if notches and cloud.dim == 3:
        lo, hi = cloud.bounds
        z_bounds = (float(lo[2]) - cloud.spacing, float(hi[2]) + cloud.spacing)
    try:
        cracks = [make_crack(c.points) for c in deck.precracks]
        cracks += [notch.crack(z_bounds) for notch in notches]
        return build_bonds(cloud, d.delta, d.partial_volume, cracks)
    except ValueError as exc:
        raise SetupError("discretisation", str(exc)) from None


def build_material(m: Any) -> Any:
    """The deck's material section -> a material of its model family (registry
    :data:`peridynamics.materials.MATERIALS`, keyed by ``material.model``)."""
    try:
        if isinstance(m, dk.LPSMaterialSpec):
            return MATERIALS["lps"](m.youngs_modulus, m.poisson_ratio, m.density, m.influence)
        if isinstance(m, dk.CorrespondenceMaterialSpec):
            return MATERIALS["correspondence"](
                m.youngs_modulus,
                m.poisson_ratio,
                m.density,
                m.stabilization,
                0.1 if m.stabilization_g is None else m.stabilization_g,
                m.law,
            )
        if isinstance(m, dk.MicropolarMaterialSpec):
            return MATERIALS["micropolar"](
                m.youngs_modulus, m.poisson_ratio, m.density, m.rotational_stiffness_ratio
            )
        return MATERIALS[m.model](
            m.youngs_modulus, m.density, m.micromodulus_profile, m.micromodulus
        )
    except ValueError as exc:
        raise SetupError("material", str(exc)) from None


def build_damage(dmg: dk.Damage, m: Any, material: Any, cloud: PointCloud, bonds: Bonds) -> Any:
    """The damage object given to :class:`Model` for the deck's ``damage`` section.

    Parameters
    ----------
    dmg : Damage
        The validated ``damage`` section.
    m : material spec of the deck (selects the correspondence failure law).
    material : the material object built from ``m`` (calibrates s0 from G0).
    cloud : PointCloud
        Points of the body (node sets of ``no_fail``, dimension, cross-section).
    bonds : Bonds
        Its bonds (the horizon).

    Returns
    -------
    ``NO_DAMAGE``, :class:`CriticalStretch`, ``CorrespondenceFailure`` or
    :class:`~peridynamics.damage.bond_softening.SofteningBonds`. Raises SetupError when
    a softening law has no tail at this horizon.
    """
    if dmg.model == "none":
        return NO_DAMAGE
    no_fail = (
        np.unique(np.concatenate([cloud.node_set(n) for n in dmg.no_fail])) if dmg.no_fail else None
    )
    if dmg.bond_law != "brittle":  # tension softening (validated: f_t and G0 given)
        from peridynamics.damage.bond_softening import SofteningBonds

        assert dmg.tensile_strength is not None and dmg.fracture_energy is not None
        knee = dmg.trilinear_knee
        soft = SofteningBonds(
            dmg.bond_law,
            dmg.tensile_strength,
            dmg.fracture_energy,
            None if knee is None else (float(knee[0]), float(knee[1])),
            no_fail,
        )
        try:  # the envelope needs s_c > s0 at this horizon: say so before the run
            soft.envelope(material, cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane)
        except ValueError as exc:
            raise SetupError("damage.tensile_strength", str(exc)) from None
        return soft
    s0 = dmg.critical_stretch
    if dmg.model == "principal_stress":
        s0 = math.inf
    elif s0 is None:
        assert dmg.fracture_energy is not None
        s0 = material.critical_stretch(
            dmg.fracture_energy, cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane
        )
    w = dmg.weibull
    weibull = None if w is None else WeibullField(w.shape, w.seed, w.variable, w.u0_is)
    damage: Any = CriticalStretch(s0, no_fail, weibull)
    if isinstance(m, dk.CorrespondenceMaterialSpec):
        from peridynamics.damage.principal_stress import CorrespondenceFailure

        f_t = dmg.tensile_strength
        damage = CorrespondenceFailure(damage, math.inf if f_t is None else f_t)
    return damage


def build_model(deck: dk.Deck, cloud: PointCloud, bonds: Bonds, body: list) -> Model:
    """Material + damage + loads -> Model."""
    material = build_material(deck.material)
    m = deck.material
    dmg = deck.damage
    damage = build_damage(dmg, m, material, cloud, bonds)
    sed = dmg.sed_softening
    softening = (
        None
        if sed is None
        else SEDSoftening(sed.levels, sed.k_c, sed.residual, sed.threshold_stretch, sed.energy)
    )
    contact = build_contact(deck, cloud, bonds, material)
    visc = getattr(m, "viscosity", None)
    return Model(
        cloud,
        bonds,
        material,
        damage,
        body,
        surface_correction=deck.discretisation.surface_correction,
        viscosity=None if visc is None else BondViscosity(visc.linear, visc.quadratic),
        softening=softening,
        contact=contact,
        damping=getattr(deck.solver, "damping", 0.0),
    )


def build_contact(deck: dk.Deck, cloud: PointCloud, bonds: Bonds, material: Any) -> Any:
    """Short-range contact between points not joined by an intact bond (``None`` without a
    ``contact`` section); its stiffness from the PMB micromodulus of ``material``'s E."""
    if deck.contact is None:
        return None
    from peridynamics.contact import ShortRangeContact

    c0 = material.micromodulus_constant(cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane)
    d_c = deck.contact.distance_factor * cloud.spacing
    return ShortRangeContact(
        cloud.x,
        cloud.volume,
        bonds,
        contact_distance=d_c,
        stiffness=ShortRangeContact.parks_stiffness(
            c0, d_c, bonds.horizon, deck.contact.stiffness_factor
        ),
        friction_static=deck.contact.friction_static,
        friction_kinetic=deck.contact.friction_kinetic,
        global_ids=cloud.global_ids,
    )


# ---------------------------------------------------------------------- simulation
@dataclass
class Simulation(RunLoop):
    """A deck turned into objects, ready to run."""

    deck: dk.Deck
    cloud: PointCloud
    model: Model
    solver: Solver
    setup_s: float = 0.0
    #: a decomposed run (``mpiexec -n N``): the collective side (None when serial)
    session: Any = None
    #: a decomposed run: the whole body (``cloud`` is this rank's part)
    global_cloud: PointCloud | None = None

    @classmethod
    def from_deck(cls, deck: dk.Deck, comm: Any = None) -> Simulation:
        """Build geometry -> bonds -> model -> solver. Raises SetupError / DeckError.

        ``comm``: an mpi4py communicator of more than one rank decomposes the body over
        its ranks (:mod:`peridynamics.parallel`); every rank calls this."""
        t0 = time.perf_counter()
        if comm is not None and comm.Get_size() > 1:
            from peridynamics.parallel.build import build_distributed
            from peridynamics.parallel.session import Session

            parts = build_distributed(deck, comm)
            session = Session(parts["communicator"], parts["model"], parts["global_cloud"])
            return cls(
                deck, parts["cloud"], parts["model"], parts["solver"],
                setup_s=time.perf_counter() - t0, session=session,
                global_cloud=parts["global_cloud"],
            )  # fmt: skip
        cloud = build_cloud(deck)
        bonds = build_bonds_for(deck, cloud)
        body, kin, init = build_conditions(deck, cloud)
        s = deck.solver
        if isinstance(s, dk.Solver) and s.method == "fdm":
            m = deck.material
            assert isinstance(m, dk.Material)
            material = MATERIALS[m.model](m.youngs_modulus, m.density, m.micromodulus_profile)
            model: Model = FDMModel1D(cloud, material, body)
        elif has_bodies(deck):
            layout = body_layout(deck, cloud)
            contact = build_contact(deck, cloud, bonds, build_material(deck.material))
            model = build_bodies_model(deck, cloud, bonds, layout, body, contact)
        else:
            model = build_model(deck, cloud, bonds, body)
        if deck.rigid_bodies:
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
        solver = build_solver(deck, cloud, model, body, kin, init)
        return cls(deck, cloud, model, solver, setup_s=time.perf_counter() - t0)

    @property
    def n_steps(self) -> int:
        """Total number of steps of the run."""
        return self.solver.total_steps()

    def fingerprint(self) -> str:
        """Hash of the validated deck, the package version and (for mesh geometries) the
        mesh file: a checkpoint only resumes the same problem with the same code."""
        from peridynamics import __version__

        text = json.dumps(self.deck.model_dump(mode="json", by_alias=True), sort_keys=True)
        h = hashlib.sha256(text.encode())
        h.update(__version__.encode())
        if isinstance(self.deck.geometry, dk.MeshGeometry):
            h.update(Path(self.deck.geometry.file).read_bytes())
        return h.hexdigest()
