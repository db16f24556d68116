"""The stable step with mass damping and linear viscosity
(:mod:`peridynamics.evaluation.stability`), against the empirical limit of the real
integrators found by bisection; the automatic step under absurd damping; prescribed
velocities that move whatever the damping; the warnings and instability messages that
name the key."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, ExplicitSolver, build_bonds
from peridynamics.evaluation.stability import StableStep
from peridynamics.families.viscosity import BondViscosity
from peridynamics.geometry import bar
from peridynamics.loading.conditions import PrescribedVelocity
from peridynamics.solvers import SimulationUnstable
from peridynamics.solvers.plausibility import ImplausibleSettingWarning, findings

E, RHO, DX = 200e9, 7850.0, 1e-3


def bar_model(damping: float = 0.0, b1: float = 0.0, n: int = 24, **material) -> Evaluator:
    """A 1-D PMB bar of n points, delta = 3 dx."""
    cloud = bar(n * DX, DX, area=1e-4)
    mat = BondBasedMaterial(material.get("E", E), material.get("rho", RHO))
    visc = BondViscosity(b1) if b1 else None
    return Evaluator(cloud, build_bonds(cloud, 3 * DX), mat, damping=damping, viscosity=visc)


def quiet_solver(model: Evaluator, **kw) -> ExplicitSolver:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ImplausibleSettingWarning)
        return ExplicitSolver(model, **kw)


def test_bound_formula_and_its_limits() -> None:
    el = 1e-6
    assert StableStep(el).value == el
    for xi in (0.1, 1.0, 7.0):  # Belytschko, Liu & Moran (2000), section 6.3
        step = StableStep(el, damping=4 * xi / el)
        assert step.xi == pytest.approx(xi, rel=1e-15)
        assert step.value == pytest.approx(el * (math.sqrt(1 + xi * xi) - xi), rel=1e-12)
        visc = StableStep(el, gamma=xi * el)
        assert visc.value == pytest.approx(step.value, rel=1e-12)
    assert StableStep(el, damping=1e30).value == pytest.approx(2e-30, rel=1e-12)  # 2 / c_d
    assert StableStep(el, gamma=1e30).value == pytest.approx(el**2 / 2e30, rel=1e-12)
    assert StableStep(el, damping=1e300, gamma=1e280).value == pytest.approx(2e-300, rel=1e-6)
    assert StableStep(math.inf, damping=10.0).value == pytest.approx(0.2)  # no bonds: 2 / c_d
    assert StableStep(el, damping=1e3).limited_by() is None
    assert StableStep(el, damping=1e8).limited_by() == "solver.damping"
    assert StableStep(el, damping=1e6, gamma=1e-4).limited_by() == "material.viscosity.linear"


@pytest.mark.parametrize("xi", [0.3, 4.0, 300.0])
def test_bound_is_sharp_for_the_fastest_mode(xi: float) -> None:
    """One mode at omega = 2 / dt_el: the lagged-velocity recurrence
    u+ = (2 - W^2 - C) u - (1 - C) u-, W = omega dt, C = c dt, has spectral radius 1 at
    the bound and above 1 just beyond it."""
    el = 1e-6
    step = StableStep(el, damping=4 * xi / el)
    w, c = 2 / el, step.damping

    def radius(dt: float) -> float:
        roots = np.roots([1.0, -(2 - (w * dt) ** 2 - c * dt), 1 - c * dt])
        return float(np.abs(roots).max())

    assert radius(step.value) == pytest.approx(1.0, abs=1e-6)
    assert radius(1.001 * step.value) > 1.0 + 1e-7
    assert radius(0.999 * step.value) <= 1.0 + 1e-12


def _stays_bounded(model: Evaluator, dt: float, integrator: str, n: int = 300) -> bool:
    """n steps of the real solver from random velocities: True unless max |v| grows
    100-fold (or goes non-finite)."""
    solver = quiet_solver(
        model, time_step=dt, allow_unstable=True, check_every=10**9, integrator=integrator
    )
    s = solver.init()
    s.v[:] = np.random.default_rng(1).normal(0.0, 1e-3, s.v.shape)  # m/s
    s.u_prev[:] = s.u - dt * s.v
    v0 = float(np.abs(s.v).max())
    with np.errstate(all="ignore"):
        for _ in range(n):
            solver.step(s)
        return bool(np.isfinite(s.v).all() and np.abs(s.v).max() < 100 * v0)


def empirical_limit(model: Evaluator, integrator: str, iterations: int = 8) -> float:
    """The largest step that stays bounded, by bisection (in log dt) between the bound
    and 3 x the bound."""
    lo, hi = model.stable_time_step(), 3 * model.stable_time_step()
    assert _stays_bounded(model, lo, integrator) and not _stays_bounded(model, hi, integrator)
    for _ in range(iterations):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if _stays_bounded(model, mid, integrator) else (lo, mid)
    return lo


#: (mass damping c_d dt_el, b1, integrator, the largest empirical / bound measured x 1.1)
CASES = [
    (0.0, 0.0, "velocity_verlet", 1.25),  # plain: 1.118 (the Lanczos bound's sqrt(1.25))
    (100.0, 0.0, "velocity_verlet", 1.1),  # xi = 25 from damping: 1.013
    (100.0, 0.0, "central_difference", 1.1),
    (0.0, 40.0, "velocity_verlet", 1.4),  # xi = 18 from viscosity: 1.272
    (40.0, 20.0, "central_difference", 1.25),  # both, xi = 10 + 9: 1.118
]


@pytest.mark.parametrize(("cd_dt", "b1", "integrator", "factor"), CASES)
def test_bound_is_below_the_empirical_limit(
    serial_numba, cd_dt: float, b1: float, integrator: str, factor: float
) -> None:
    el = bar_model().stable_time_step()
    model = bar_model(damping=cd_dt / el, b1=b1)
    bound = model.stable_time_step()
    emp = empirical_limit(model, integrator)
    assert bound <= emp <= factor * bound, (bound, emp, emp / bound)


@pytest.mark.parametrize("integrator", ["velocity_verlet", "central_difference"])
def test_automatic_step_stays_stable_under_absurd_damping(integrator: str) -> None:
    """damping 1e12 /s (and 1e30): the automatic step runs, finite; the prescribed end
    moves at its 1 m/s (u = v t) and the damping holds the rest back."""
    for damping in (1e12, 1e30):
        model = bar_model(damping=damping)
        end = np.array([0], dtype=np.intp)
        pv = PrescribedVelocity(end, {"x": 1.0})
        solver = quiet_solver(model, constraints=[pv], integrator=integrator, check_every=5)
        assert solver.dt <= 2.0 / damping
        s = solver.init()
        solver.run(s, 40)
        assert np.isfinite(s.u).all() and np.isfinite(s.v).all()
        assert s.u[0, 0] == pytest.approx(s.t, rel=1e-12) and s.v[0, 0] == 1.0
        assert np.abs(s.u[1:]).max() <= s.u[0, 0]


def test_prescribed_velocity_is_exact_even_on_an_unstable_step() -> None:
    """With allow_unstable and damping 1e30 the free points blow up, but the prescribed
    point still moves by dt v per step (before: u + dt v_h - dt v_h lost it)."""
    model = bar_model(damping=1e30)
    pv = PrescribedVelocity(np.array([0], dtype=np.intp), {"x": 1.0})
    solver = quiet_solver(
        model, constraints=[pv], time_step=1e-7, allow_unstable=True, check_every=10**9
    )
    s = solver.init()
    with np.errstate(all="ignore"):
        for _ in range(3):
            solver.step(s)
    assert s.u[0, 0] == pytest.approx(3e-7, rel=1e-12)


def test_no_finding_for_a_plausible_model() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        solver = ExplicitSolver(bar_model(damping=1e4, b1=0.5), time_step=1e-8)
    assert findings(solver) == []


@pytest.mark.parametrize(
    ("kw", "key"),
    [
        ({"damping": 1e12}, "solver.damping"),
        ({"b1": 1e30}, "material.viscosity.linear"),
        ({"E": 1e-300}, "material.youngs_modulus"),
        ({"rho": 1e12}, "material.density"),
    ],
)
def test_warnings_name_the_key(kw: dict, key: str) -> None:
    with pytest.warns(ImplausibleSettingWarning, match=key.replace(".", r"\.")):
        solver = ExplicitSolver(bar_model(**kw))
    assert solver.stable_time_step > 0 and math.isfinite(solver.stable_time_step)


def test_tiny_time_step_warns_with_a_guess() -> None:
    with pytest.warns(ImplausibleSettingWarning, match="solver.time_step") as got:
        ExplicitSolver(bar_model(), time_step=2e-300, steps=30)
    msg = str(got[0].message)
    assert "did you mean 2e-07 s" in msg and "30 steps reach t = 6e-299 s" in msg


def _blow_up(solver: ExplicitSolver) -> str:
    s = solver.init()
    s.body[:] = 0.0
    s.v[:] = np.random.default_rng(0).normal(0.0, 1e3, s.v.shape)
    s.u_prev[:] = s.u - solver.dt * s.v
    with pytest.raises(SimulationUnstable) as info, np.errstate(all="ignore"):
        solver.run(s, 400)
    return str(info.value)


def test_instability_message_names_the_cause() -> None:
    """A user step: reduce solver.time_step. The automatic step: not the cause, the
    implausible key (here the modulus) or the loads."""
    model = bar_model()
    user = quiet_solver(model, time_step=3 * model.stable_time_step(), allow_unstable=True)
    msg = _blow_up(user)
    assert "Reduce solver.time_step" in msg and "stable limit" in msg
    auto = quiet_solver(bar_model(E=1e-300), max_stretch=1e-12)
    msg = _blow_up(auto)
    assert "The time step was automatic" in msg and "material.youngs_modulus" in msg
    assert "Reduce" not in msg
    plain = quiet_solver(bar_model(), max_stretch=1e-12)
    assert "check the loads and boundary conditions" in _blow_up(plain)


def test_hybrid_with_the_automatic_step_does_not_blame_the_step() -> None:
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck
    from tests.helpers import EXAMPLES

    path = EXAMPLES / "spalling" / "test_bar_fdm_pd3.yaml"
    auto = Simulation.from_deck(load_deck(path, overrides=["solver.time_step=null"])).solver
    assert auto.first.time_step is None and auto.second.time_step is None
    assert auto.dt == pytest.approx(0.8 * auto.stable_time_step, rel=1e-12)
    given = Simulation.from_deck(load_deck(path)).solver
    assert given.second.time_step == given.dt == 2e-6


@pytest.mark.parametrize("overrides", [["solver.method=fdm"], ["solver.hybrid={first: fdm}"]])
def test_finite_differences_and_hybrids_are_damped_too(overrides: list[str]) -> None:
    """``solver.damping`` reaches the finite-difference model (it was dropped before)."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck
    from tests.helpers import EXAMPLES

    path = EXAMPLES / "bar_wave_1d" / "deck.yaml"
    sets = ["solver.end_time=null", "solver.steps=200", *overrides]
    peaks = []
    for damping in (0.0, 1.0e4):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sim = Simulation.from_deck(load_deck(path, [*sets, f"solver.damping={damping}"]))
        solver = sim.solver
        state = solver.init()
        while not solver.done(state):
            solver.step(state)
        peaks.append(float(np.abs(state.u).max()))
    assert peaks[1] < 0.9 * peaks[0]
