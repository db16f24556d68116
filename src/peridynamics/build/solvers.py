"""The deck's solver section -> a solver (registry :data:`SOLVERS`, keyed by
``solver.type``): explicit dynamics (Numba or Warp backend, float32 PMB, hybrid
FDM/PD), adaptive dynamic relaxation and the implicit static solver."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from peridynamics import deck as dk
from peridynamics.bonds import build_bonds
from peridynamics.build.errors import SetupError
from peridynamics.build.fatigue import build_fatigue_solver
from peridynamics.build.thermal import build_heat, build_heat_steady, couple, install_expansion
from peridynamics.damage import NO_DAMAGE
from peridynamics.deck.thermal_coupling import coupling_of
from peridynamics.evaluation import Evaluator
from peridynamics.geometry import PointCloud
from peridynamics.solvers.base import Solver
from peridynamics.solvers.explicit import ExplicitSolver
from peridynamics.solvers.fdm import FDMModel1D
from peridynamics.solvers.hybrid import HybridSolver, SwitchAtStretch


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
    deck: dk.Deck, cloud: PointCloud, second: Evaluator, body: list, kin: list, init: list
) -> HybridSolver:
    """The first (cheap) model and the hybrid solver around it and the deck's model."""
    s = deck.solver
    assert isinstance(s, dk.Solver) and s.hybrid is not None
    h = s.hybrid
    material = second.material
    first: Evaluator
    if h.first == "fdm":
        first = FDMModel1D(cloud, material, body, damping=s.damping)
    else:
        bonds = build_bonds(
            cloud, h.first_horizon_factor * cloud.spacing, deck.discretisation.partial_volume
        )
        first = Evaluator(cloud, bonds, material, NO_DAMAGE, body, damping=s.damping)
    limit = min(first.stable_time_step(), second.stable_time_step())
    dt = s.time_step if s.time_step is not None else s.safety_factor * limit
    common = _solver_options(s, kin, init, time_step=dt)
    solvers = ExplicitSolver(first, **common), ExplicitSolver(second, **common)
    if s.time_step is None:  # automatic: an instability message must not blame the step
        for solver in solvers:
            solver.time_step = None
    return HybridSolver(*solvers, SwitchAtStretch(h.switch_fraction))


def build_explicit(
    deck: dk.Deck, cloud: PointCloud, model: Evaluator, body: list, kin: list, init: list
) -> Solver:
    """Explicit dynamics from ``solver: {type: explicit, ...}`` (the default)."""
    s = deck.solver
    assert isinstance(s, dk.Solver)
    if s.backend == "warp":
        return _warp_solver(deck, model, kin, init)
    if s.hybrid is not None:
        if s.precision != "float64":
            raise SetupError("solver.precision", "a hybrid run is float64 only")
        return _hybrid_solver(deck, cloud, model, body, kin, init)
    if s.precision != "float64":
        _set_precision(model, s.precision)
    return ExplicitSolver(model, **_solver_options(s, kin, init, s.time_step))


def _warp_solver(deck: dk.Deck, model: Evaluator, kin: list, init: list) -> Solver:
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


def _set_precision(model: Evaluator, precision: str) -> None:
    """``solver.precision: float32``: the PMB force pass with critical-stretch damage in
    float32 (:meth:`PMBForceModel.set_precision`); other models are refused by name."""
    from peridynamics.damage.critical_stretch import CriticalStretchLaw
    from peridynamics.families.pmb.force import PMBForceModel

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


def build_static(
    deck: dk.Deck, cloud: PointCloud, model: Evaluator, body: list, kin: list, init: list
) -> Solver:
    """The implicit static solver from ``solver: {type: static, ...}`` (every key of the
    section is a keyword of :class:`~peridynamics.solvers.static.StaticSolver`)."""
    from peridynamics.solvers.direct import direct_backend
    from peridynamics.solvers.static import StaticSolver

    if init:
        raise ValueError("initial velocities have no meaning in a static run")
    try:  # the environment's choice of direct solver, checked before the run
        direct_backend()
    except ValueError as exc:
        raise SetupError("solver.linear_solver", str(exc)) from None
    keys = deck.solver.model_dump(exclude={"type"})
    if model.comm.n_owned is not None:  # a rank of a decomposed run
        from peridynamics.solvers.static_distributed import DistributedStaticSolver

        return DistributedStaticSolver(model, constraints=kin, **keys)
    return StaticSolver(model, constraints=kin, **keys)


def build_adr(
    deck: dk.Deck, cloud: PointCloud, model: Evaluator, body: list, kin: list, init: list
) -> Solver:
    """Adaptive dynamic relaxation from ``solver: {type: adr, ...}`` (every key of the
    section is a keyword of :class:`~peridynamics.solvers.adr.ADRSolver`)."""
    from peridynamics.solvers.adr import ADRSolver

    if init:
        raise ValueError("initial velocities have no meaning in a static (adr) run")
    return ADRSolver(model, constraints=kin, **deck.solver.model_dump(exclude={"type"}))


SolverBuilder = Callable[[dk.Deck, PointCloud, Evaluator, list, list, list], Solver]
#: ``solver.type`` -> builder(deck, cloud, model, body forces, constraints, initial)
SOLVERS: dict[str, SolverBuilder] = {
    "explicit": build_explicit,
    "static": build_static,
    "adr": build_adr,
    "fatigue": build_fatigue_solver,
    "heat": build_heat,
    "heat_steady": build_heat_steady,
}


def _bind_step_time(model: Evaluator, solver: Solver) -> None:
    """Give a force model that integrates its history in time (``bind_step_time``: the
    viscoelastic LPS) the time of one solver step: explicit ``dt``, dynamic relaxation
    ``load_time / load_steps``."""
    bind = getattr(model.force_model, "bind_step_time", None)
    if bind is None:
        return
    load_time = getattr(solver, "load_time", None)
    if load_time is not None:  # a load-stepping solver: the pseudo-time of one step
        bind(float(load_time) / solver.load_steps)  # type: ignore[attr-defined]
    else:
        bind(float(solver.dt))  # type: ignore[attr-defined]


def build_solver(
    deck: dk.Deck, cloud: PointCloud, model: Evaluator, body: list, kin: list, init: list
) -> Solver:
    """The deck's solver section -> a solver (registry :data:`SOLVERS`: ``solver.type``)."""
    s = deck.solver
    try:
        if coupling_of(deck) is None:
            solver = SOLVERS[s.type](deck, cloud, model, body, kin, init)
            _bind_step_time(model, solver)
            return solver
        install_expansion(deck, model)  # thermal expansion: docs/theory_thermal.md
        return couple(deck, cloud, model, SOLVERS[s.type](deck, cloud, model, body, kin, init))
    except SetupError:
        raise
    except ValueError as exc:
        named, msg = dk.named_key(str(exc))
        key = "solver.time_step" if s.type == "explicit" else "solver"
        raise SetupError(named or key, msg) from None
