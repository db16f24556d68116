"""The implicit static solver (:mod:`peridynamics.solvers.static`): linear elasticity of
a micropolar cantilever, direct and iterative linear solvers, PMB and LPS (Newton on a
geometrically nonlinear model; finite-difference tangent), bond breaking between solves
(schemes A/B/C, event-driven load levels, Woodbury re-use of the factorisation), the
ends of a failed run, and the deck route.

Oracles: force balance (reaction = applied load), Timoshenko & Goodier's tip deflection,
linearity (load stepping changes nothing), the older linear solver
:func:`peridynamics.solvers.linear_static.solve_linear_static`, a direct factorisation after
every event (no re-use), and bond stretches recomputed here from the displacements.
All models are small (at most 1 260 points).
"""

from __future__ import annotations

import copy
import json
from typing import Any

import numpy as np
import pytest

from peridynamics.analysis.beams import timoshenko_goodier_tip_deflection
from peridynamics.app.run import Simulation
from peridynamics.bonds.bonds import build_bonds
from peridynamics.bonds.precrack import make_crack
from peridynamics.build.errors import SetupError
from peridynamics.damage.critical_stretch import CriticalStretch
from peridynamics.deck import DeckError, parse_deck
from peridynamics.evaluation import Evaluator
from peridynamics.families.lps.material import LPSMaterial
from peridynamics.families.micropolar.material import MicropolarMaterial
from peridynamics.families.pmb.material import BondBasedMaterial
from peridynamics.geometry.generators import rectangle
from peridynamics.loading.conditions import BodyForce, Fixed, PrescribedDisplacement
from peridynamics.solvers.linear import UnconstrainedModel
from peridynamics.solvers.linear_static import solve_linear_static
from peridynamics.solvers.static import StaticSolver

E_STEEL, NU, RHO_STEEL = 200e9, 0.2, 7850.0
E_AL, RHO_AL = 70e9, 2700.0


# small problems: one Numba thread is faster than several (results do not depend on it)
pytestmark = pytest.mark.usefixtures("serial_numba")


def _run(solver: StaticSolver, limit: int = 10_000) -> tuple[Any, list]:
    s = solver.init()
    results = []
    while not solver.done(s):
        results.append(solver.step(s))
        assert len(results) < limit
    return s, results


def _dofs(s: Any) -> np.ndarray:
    return np.concatenate([s.u, s["theta"]], axis=1)


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


# -------------------------------------------------------------- 1-2. micropolar cantilever
CL_DX, CL_L, CL_H, CL_P = 0.01, 0.4, 0.1, -1000.0  # m, m, m, N (downward end shear)


def _cantilever() -> tuple[Evaluator, np.ndarray, np.ndarray]:
    """0.4 m x 0.1 m, thickness 1 m, plane stress; a fictitious clamped layer of 3
    columns at x < 0; the end shear P as a body force on the last column."""
    dx = CL_DX
    cloud = rectangle((CL_L + 3 * dx, CL_H), dx, thickness=1.0, origin=(-3 * dx, 0.0))
    x = cloud.x
    clamp = np.flatnonzero(x[:, 0] < 0.0)
    tip = np.flatnonzero(x[:, 0] > CL_L - dx)
    b = CL_P / cloud.volume[tip].sum()
    bonds = build_bonds(cloud, 3.015 * dx, partial_volume="truncated")
    model = Evaluator(
        cloud,
        bonds,
        MicropolarMaterial(E_STEEL, NU, RHO_STEEL),
        body_forces=[BodyForce(tip, (0.0, b))],
        surface_correction=True,
    )
    assert len(clamp) == 30 and len(tip) == 10
    return model, clamp, tip


@pytest.fixture(scope="module")
def cantilever_direct() -> tuple[Evaluator, np.ndarray, np.ndarray, Any, dict]:
    model, clamp, tip = _cantilever()
    solver = StaticSolver(model, [Fixed(clamp)], load_steps=1, linear_solver="direct")
    s, results = _run(solver)
    assert len(results) == 1
    return model, clamp, tip, s, solver.summary_fields(s)


def test_cantilever_one_newton_iteration_balance_and_timoshenko(cantilever_direct) -> None:
    model, clamp, tip, s, summary = cantilever_direct
    assert summary["converged"] is True and summary["message"] == "final load reached"
    assert summary["newton_iterations"] == 1  # linear model: one iteration is exact
    assert summary["linear_solver"] == "direct" and summary["factorizations"] == 1
    assert s["static_load_factor"][0] == 1.0
    # the clamped layer carries the whole load (its rotations are fixed too)
    assert np.all(s.u[clamp] == 0.0) and np.all(s["theta"][clamp] == 0.0)
    vol = model.cloud.volume[:, None]
    reaction = -(vol[clamp] * s.force[clamp]).sum(axis=0)
    assert abs(reaction[1] + CL_P) <= 1e-8 * abs(CL_P)  # balances the applied load
    assert abs(reaction[0]) <= 1e-8 * abs(CL_P)
    # relative residual of the free dofs
    free = np.setdiff1d(np.arange(model.n_points), clamp)
    unbalanced = np.concatenate(
        [vol * (s.force + s.body), vol * (s["moment"] + s["body_moment"])], axis=1
    )[free]
    assert np.linalg.norm(unbalanced) <= 1e-8 * abs(CL_P)
    tip_uy = float(s.u[tip, 1].mean())
    ref = timoshenko_goodier_tip_deflection(CL_P, CL_L, CL_H, 1.0, E_STEEL, NU)
    assert tip_uy < 0.0
    assert abs(tip_uy - ref) <= 0.05 * abs(ref), (tip_uy, ref)


def test_cantilever_load_stepping_is_linear(cantilever_direct) -> None:
    model, clamp, _, s1, _ = cantilever_direct
    solver = StaticSolver(model, [Fixed(clamp)], load_steps=4, linear_solver="direct")
    s4, results = _run(solver)
    summary = solver.summary_fields(s4)
    assert len(results) == 4 and summary["solves"] == 4 and summary["converged"] is True
    assert all(r.converged and r.residual <= 1e-8 for r in results)
    assert summary["factorizations"] == 1  # constant tangent: factored once
    assert _rel(_dofs(s4), _dofs(s1)) <= 1e-10


def test_cantilever_iterative_solver_matches_direct(cantilever_direct) -> None:
    model, clamp, _, s_direct, _ = cantilever_direct
    # one Newton iteration suffices for this linear model; the small limits keep a
    # failing linear solve from costing minutes of cut-backs
    solver = StaticSolver(
        model,
        [Fixed(clamp)],
        load_steps=1,
        linear_solver="iterative",
        max_iterations=3,
        max_cutbacks=0,
    )
    s, results = _run(solver)
    summary = solver.summary_fields(s)
    assert summary["linear_solver"] == "iterative"
    assert summary["converged"] is True, summary["message"]
    assert results[-1].residual <= solver.tolerance
    assert _rel(_dofs(s), _dofs(s_direct)) <= 1e-6


# ------------------------------------------------------------------------ 3. PMB plate
PL_DX = 1e-3


def _plate(material: Any, nx: int, ny: int) -> tuple[Evaluator, np.ndarray, np.ndarray, float]:
    cloud = rectangle((nx * PL_DX, ny * PL_DX), PL_DX)
    model = Evaluator(cloud, build_bonds(cloud, 3.015 * PL_DX), material, surface_correction=True)
    x = cloud.x
    left = np.flatnonzero(x[:, 0] < PL_DX)
    right = np.flatnonzero(x[:, 0] > (nx - 1) * PL_DX)
    gauge = (nx - 1) * PL_DX  # between the centres of the end columns
    return model, left, right, gauge


def test_pmb_matches_the_linear_solver_at_small_strain_and_newton_converges() -> None:
    model, left, right, gauge = _plate(BondBasedMaterial(E_AL, RHO_AL), 20, 8)
    x = model.cloud.x
    fixed_dofs = np.concatenate([2 * left, 2 * left + 1, 2 * right])
    for strain in (1e-5, 1e-3):
        d = strain * gauge
        bc = [Fixed(left), PrescribedDisplacement(right, {"x": d})]
        solver = StaticSolver(model, bc, load_steps=2)
        s, results = _run(solver)
        summary = solver.summary_fields(s)
        assert summary["converged"] is True and len(results) == 2
        for r in results:
            assert r.converged and r.residual <= solver.tolerance
            assert 1 <= r.iterations <= 5
        assert np.all(s.u[right, 0] == d) and np.all(s.u[left] == 0.0)
        if strain == 1e-5:
            values = np.concatenate([np.zeros(2 * len(left)), np.full(len(right), d)])
            u_lin = solve_linear_static(model.force_model, fixed_dofs, values, np.zeros_like(x))
            # the PMB force follows the deformed bond: nonlinear at O(strain)
            assert _rel(s.u, u_lin) <= 1e-5


# ------------------------------------------------------------------------ 4. LPS plate
def _lps_stretch(model: Evaluator, left: np.ndarray, right: np.ndarray, gauge: float) -> Any:
    strain = 1e-3
    bc = [
        Fixed(left, ("x",)),
        Fixed(left[:1]),  # one point pinned in y: no rigid motion, free contraction
        PrescribedDisplacement(right, {"x": strain * gauge}),
    ]
    solver = StaticSolver(model, bc, load_steps=1)
    s, results = _run(solver)
    summary = solver.summary_fields(s)
    assert summary["converged"] is True, summary["message"]
    assert results[-1].residual <= solver.tolerance and results[-1].iterations <= 6
    assert summary["factorizations"] == results[-1].iterations  # refactored per iteration
    return s


@pytest.mark.parametrize("tangent", ["analytic", "finite_difference"])
def test_lps_newton_converges_with_lateral_contraction(tangent: str, monkeypatch) -> None:
    model, left, right, gauge = _plate(LPSMaterial(E_AL, 0.25, RHO_AL), 10, 6)
    if tangent == "finite_difference":  # a model without an analytic tangent
        monkeypatch.setattr(model.force_model, "tangent", lambda state: None)
    s = _lps_stretch(model, left, right, gauge)
    x = model.cloud.x
    mid = (x[:, 0] > 3 * PL_DX) & (x[:, 0] < 7 * PL_DX)
    top = np.flatnonzero(mid & (x[:, 1] > x[:, 1].max() - 1e-9))
    bottom = np.flatnonzero(mid & (x[:, 1] < x[:, 1].min() + 1e-9))
    width_change = s.u[top, 1].mean() - s.u[bottom, 1].mean()
    nominal = 0.25 * 1e-3 * (x[:, 1].max() - x[:, 1].min())
    assert width_change < 0.0  # contraction
    assert 0.5 * nominal < -width_change < 2.0 * nominal, (width_change, nominal)
    assert s.u[right, 0].min() > 0.0
    if tangent == "finite_difference":  # the same equilibrium as with the analytic one
        ref_model, *_ = _plate(LPSMaterial(E_AL, 0.25, RHO_AL), 10, 6)
        ref = _lps_stretch(ref_model, left, right, gauge)
        assert _rel(s.u, ref.u) <= 1e-6


# ------------------------------------------------------------ 5. bond breaking, mini DCB
DCB_DX, DCB_L, DCB_D = 1e-3, 0.06, 1e-5  # m; opening +-d on the load column
# s0: 0.8 of the largest elastic stretch at the full opening (1.98e-4), so the crack
# starts near lambda = 0.8 and a few dozen pairs break
DCB_S0 = 1.6e-4


def _dcb(s0: float = DCB_S0) -> tuple[Evaluator, list]:
    """60 x 20 points (+ 3 clamped columns at x > L), crack from the left edge along
    the mid-line to 0.4 L, opening +-d on the left column of each arm."""
    dx = DCB_DX
    cloud = rectangle((DCB_L + 3 * dx, 20 * dx), dx, thickness=0.01, origin=(0.0, -10 * dx))
    x = cloud.x
    crack = make_crack([[-1.0, 0.0], [0.4 * DCB_L, 0.0]])
    bonds = build_bonds(cloud, 3.015 * dx, partial_volume="truncated", cracks=[crack])
    clamp = np.flatnonzero(x[:, 0] > DCB_L)
    left = np.flatnonzero(x[:, 0] < dx)
    top, bottom = left[x[left, 1] > 0.0], left[x[left, 1] < 0.0]
    model = Evaluator(
        cloud,
        bonds,
        MicropolarMaterial(E_STEEL, NU, RHO_STEEL),
        CriticalStretch(s0, no_fail=clamp),
        surface_correction=True,
    )
    bc = [
        Fixed(clamp),
        PrescribedDisplacement(top, {"y": DCB_D}),
        PrescribedDisplacement(bottom, {"y": -DCB_D}),
    ]
    return model, bc


def _ratios(model: Evaluator, s: Any) -> tuple[np.ndarray, np.ndarray]:
    """(pair representatives i < j that can break, their l / l_c with 0 if broken),
    recomputed from the displacement."""
    b = model.bonds
    s0 = model.point_s0
    thr = 0.5 * (s0[b.bond_i] + s0[b.bond_j])
    rep = np.flatnonzero((b.bond_i < b.bond_j) & np.isfinite(thr))
    stretch = model.force_model.bond_stretch(s)  # type: ignore[attr-defined]
    xi = b.bond_xi
    length = np.linalg.norm(xi, axis=1)
    du = s.u[b.bond_j] - s.u[b.bond_i]
    np.testing.assert_allclose(stretch, np.sum(du * xi, axis=1) / length**2, atol=1e-15)
    return rep, stretch[rep] / thr[rep] * (s.intact[rep] != 0)


class Trace:
    """A run of the DCB with what every step did."""

    def __init__(self, s0: float = DCB_S0, **kw: Any) -> None:
        self.model, bc = _dcb(s0)
        self.solver = StaticSolver(self.model, bc, **kw)
        s = self.solver.init()
        self.steps: list[dict] = []
        while not self.solver.done(s):
            before = s.intact.copy()
            rep, r_before = _ratios(self.model, s)
            result = self.solver.step(s)
            _, r_after = _ratios(self.model, s)
            newly = np.flatnonzero((before != 0) & (s.intact == 0))
            self.steps.append(
                {
                    "result": result,
                    "lam": self.solver.lam,
                    "pending": self.solver._pending,
                    "violating_before": set(rep[r_before >= 1.0].tolist()),
                    "ratio_before": dict(zip(rep.tolist(), r_before.tolist(), strict=True)),
                    "max_ratio_after": float(r_after.max()),
                    "broken_pairs": set(
                        newly[newly < self.model.bonds.reverse_index()[newly]].tolist()
                    ),
                }
            )
            assert len(self.steps) < 2000
        self.state = s
        self.summary = self.solver.summary_fields(s)

    @property
    def breaking_steps(self) -> list[dict]:
        return [st for st in self.steps if st["result"].broken]


@pytest.fixture(scope="module")
def dcb_c() -> Trace:
    return Trace(load_steps=4, breaking="C", reuse_factorization=True)


@pytest.mark.long
def test_dcb_breaks_a_few_dozen_pairs_and_ends(dcb_c: Trace) -> None:
    t = dcb_c
    assert t.summary["converged"] is True, t.summary["message"]
    assert t.summary["load_factor"] == 1.0 and not t.solver._pending
    pairs = t.state.bonds_broken // 2
    assert 20 <= pairs <= 200, pairs
    assert t.summary["breaking_events"] == len(t.breaking_steps) > 1
    assert sum(st["result"].broken for st in t.steps) == t.state.bonds_broken


@pytest.mark.long
def test_dcb_reuse_of_the_factorization_changes_nothing_but_the_cost(dcb_c: Trace) -> None:
    fresh = Trace(load_steps=4, breaking="C", reuse_factorization=False)
    assert np.array_equal(fresh.state.intact, dcb_c.state.intact)
    assert _rel(_dofs(dcb_c.state), _dofs(fresh.state)) <= 1e-8
    assert [st["lam"] for st in fresh.steps] == pytest.approx(
        [st["lam"] for st in dcb_c.steps], rel=1e-8
    )
    assert dcb_c.summary["reuse_factorization"] is True
    assert fresh.summary["factorizations"] >= fresh.summary["breaking_events"]
    assert dcb_c.summary["factorizations"] < fresh.summary["factorizations"]
    assert dcb_c.summary["update_column_solves"] > 0  # the Woodbury correction was used


def _check_scheme(t: Trace, per_event: int | None) -> None:
    """Every breaking solve breaks the ``per_event`` most stretched violating pairs of
    the state before it (all of them when ``per_event`` is None)."""
    assert t.breaking_steps
    for st in t.breaking_steps:
        assert "bonds_broken" in st["result"].events
        violating, broken = st["violating_before"], st["broken_pairs"]
        assert st["result"].broken == 2 * len(broken)
        assert broken <= violating
        if per_event is None:
            assert broken == violating
        else:
            assert len(broken) == min(per_event, len(violating))
            r = st["ratio_before"]
            left = violating - broken
            if left:
                assert min(r[k] for k in broken) >= max(r[k] for k in left)


@pytest.mark.long
def test_dcb_schemes_a_b_c(dcb_c: Trace) -> None:
    _check_scheme(dcb_c, 4)
    b = Trace(load_steps=4, breaking="B")
    _check_scheme(b, 1)
    assert all(st["result"].broken == 2 for st in b.breaking_steps)
    assert b.summary["breaking_events"] > dcb_c.summary["breaking_events"]
    # many bonds violate at once when the load jumps well past the first event
    # (s0 at 0.66 of the largest elastic stretch at lambda = 1)
    c = Trace(1.3e-4, load_steps=1, breaking="C", event_driven=False)
    a = Trace(1.3e-4, load_steps=1, breaking="A", event_driven=False)
    assert len(c.steps[0]["violating_before"]) == 0 and c.steps[1]["result"].broken
    assert len(c.breaking_steps[0]["violating_before"]) > 4
    _check_scheme(c, 4)
    _check_scheme(a, None)
    assert a.summary["breaking_events"] < c.summary["breaking_events"]
    for t in (b, c, a):
        assert t.summary["converged"] is True
        rev = t.model.bonds.reverse_index()
        assert np.array_equal(t.state.intact, t.state.intact[rev])


@pytest.mark.long
def test_dcb_no_violation_is_left_behind(dcb_c: Trace) -> None:
    steps = dcb_c.steps
    for k, st in enumerate(steps):
        assert st["result"].converged
        if st["pending"]:
            assert st["max_ratio_after"] >= 1.0
            assert steps[k + 1]["result"].broken > 0  # the next solve breaks
            assert steps[k + 1]["lam"] == st["lam"]  # at the same load
        else:
            assert st["max_ratio_after"] <= 1.0 + dcb_c.solver.tolerance
            if k + 1 < len(steps):
                assert steps[k + 1]["result"].broken == 0
    assert steps[-1]["max_ratio_after"] < 1.0


@pytest.mark.long
def test_dcb_event_driven_load_hits_the_first_event(dcb_c: Trace) -> None:
    steps = dcb_c.steps
    first = next(k for k, st in enumerate(steps) if st["pending"])
    st = steps[first]
    assert first > 0 and not steps[first - 1]["pending"]
    # the load was raised exactly to the event, not to a level k / N
    assert abs(st["max_ratio_after"] - 1.0) <= 1e-6, st["max_ratio_after"]
    assert 0.25 < st["lam"] < 1.0 and abs(4 * st["lam"] - round(4 * st["lam"])) > 1e-3
    assert steps[first - 1]["max_ratio_after"] < 1.0
    # ... and the elastic solution scales with the load: s_max = lambda / lambda_c
    lam_c = st["lam"] / st["max_ratio_after"]
    assert steps[first - 1]["max_ratio_after"] == pytest.approx(
        steps[first - 1]["lam"] / lam_c, rel=1e-8
    )


@pytest.mark.long
def test_dcb_both_directions_of_a_broken_pair_break(dcb_c: Trace) -> None:
    intact = dcb_c.state.intact
    rev = dcb_c.model.bonds.reverse_index()
    assert np.array_equal(intact, intact[rev])
    initial = dcb_c.model.bonds.bond_intact
    assert np.count_nonzero(initial == 0) > 0  # the pre-crack
    assert np.count_nonzero(intact == 0) == np.count_nonzero(initial == 0) + (
        dcb_c.state.bonds_broken
    )


# ------------------------------------------------------------------ 6. failure handling
@pytest.mark.parametrize("material", ["pmb", "micropolar"])
def test_an_unconstrained_body_is_a_set_up_error_naming_the_boundary_conditions(
    material: str,
) -> None:
    """A stiffness singular at the first solve (nothing holds the rigid-body motion)
    is an error naming ``boundary_conditions`` and the fix, not a run that ends
    'completed' with zero displacement and a warning (before: exit 0)."""
    cloud = rectangle((10 * PL_DX, 6 * PL_DX), PL_DX)
    x = cloud.x
    right = np.flatnonzero(x[:, 0] > 9 * PL_DX)
    mat: Any = (
        BondBasedMaterial(E_AL, RHO_AL)
        if material == "pmb"
        else MicropolarMaterial(E_STEEL, NU, RHO_STEEL)
    )
    model = Evaluator(
        cloud,
        build_bonds(cloud, 3.015 * PL_DX),
        mat,
        body_forces=[BodyForce(right, (1e9, 0.0))],
        surface_correction=True,
    )
    solver = StaticSolver(model, [], load_steps=2, linear_solver="direct")
    s = solver.init()
    with pytest.raises(UnconstrainedModel, match="hold the rigid-body motions|Hold the rigid") as e:
        solver.step(s)
    assert e.value.path == "boundary_conditions"
    assert np.isfinite(s.u).all()


def test_an_unconstrained_deck_exits_2_naming_the_key(tmp_path) -> None:
    """The command line prints the key and the fix and exits 2 (a set-up error)."""
    from tests.helpers import EXAMPLES, cli

    deck = EXAMPLES / "lps" / "plate_hole.yaml"
    got = cli("run", deck, "--out", tmp_path / "run", "--quiet", "--set", "solver.type=static",
              "--set", "discretisation.spacing=4e-3", "--set", "solver.max_iterations=50",
              "--set", "output.vtk_every=0")  # fmt: skip
    assert got.returncode == 2, got.stderr
    assert "boundary_conditions: the static stiffness is singular" in got.stderr
    assert "Traceback" not in got.stderr


def test_newton_non_convergence_cuts_back_then_stops() -> None:
    model, left, right, gauge = _plate(BondBasedMaterial(E_AL, RHO_AL), 20, 8)
    bc = [Fixed(left), PrescribedDisplacement(right, {"x": 1e-2 * gauge})]
    solver = StaticSolver(
        model, bc, load_steps=1, max_iterations=1, tolerance=1e-14, max_cutbacks=3
    )
    s = solver.init()
    result = solver.step(s)
    assert solver.done(s) and not result.converged
    assert result.events.count("cut_back") == 3 and result.events[-1] == "not_converged"
    summary = solver.summary_fields(s)
    assert summary["converged"] is False and summary["cutbacks"] == 3
    assert summary["load_factor"] == 0.0
    for word in ("load_steps", "max_iterations", "tolerance"):
        assert word in summary["message"]


# ---------------------------------------------------------------------------- 7. decks
DECK: dict = {
    "name": "micropolar_static",
    "geometry": {
        "type": "rectangle",
        "size": [0.13, 0.04],
        "origin": [-0.03, 0.0],
        "thickness": 1.0,
        "plane": "stress",
    },
    "discretisation": {"spacing": 0.01, "horizon_factor": 3.015},
    "material": {
        "model": "micropolar",
        "youngs_modulus": E_STEEL,
        "poisson_ratio": NU,
        "density": RHO_STEEL,
    },
    "node_sets": {
        "clamp": {"box": {"min": [-1.0, -1.0], "max": [0.0, 1.0]}},
        "tip": {"edge": {"normal": [1.0, 0.0]}},
    },
    "boundary_conditions": [
        {"type": "fixed", "set": "clamp"},
        {"type": "traction", "set": "tip", "value": [0.0, -1000.0]},
    ],
    "solver": {"type": "static", "load_steps": 2},
    "output": {"plot": "none"},
}


def _paths(exc: DeckError) -> list[str]:
    return [path for path, _ in exc.errors]


@pytest.mark.long
def test_micropolar_static_deck_runs(tmp_path) -> None:
    sim = Simulation.from_deck(parse_deck(copy.deepcopy(DECK)))
    assert isinstance(sim.solver, StaticSolver)
    sim.run(tmp_path, quiet=True, progress=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    results = summary["results"]
    assert results["solver"] == "static" and results["converged"] is True
    assert results["solves"] == 2 and results["newton_iterations"] == 1
    assert results["steps"] == 2 and results["max_displacement_m"] > 0.0


def test_deck_rejects_an_unknown_breaking_scheme() -> None:
    d = copy.deepcopy(DECK)
    d["solver"]["breaking"] = "D"
    with pytest.raises(DeckError) as info:
        parse_deck(d)
    assert "solver.breaking" in _paths(info.value)


def test_deck_rejects_micropolar_nu_above_the_plane_strain_limit() -> None:
    d = copy.deepcopy(DECK)
    d["geometry"]["plane"] = "strain"
    d["material"]["poisson_ratio"] = 0.3
    with pytest.raises(DeckError) as info:
        parse_deck(d)
    assert "material.poisson_ratio" in _paths(info.value)
    d["geometry"]["plane"] = "stress"  # 0.3 <= 1/3 is fine in plane stress
    parse_deck(d)


def test_micropolar_deck_with_adr_asks_for_the_static_solver() -> None:
    d = copy.deepcopy(DECK)
    d["solver"] = {"type": "adr"}
    with pytest.raises((DeckError, SetupError)) as info:
        Simulation.from_deck(parse_deck(d))
    assert "static" in str(info.value) and "micropolar" in str(info.value)


def test_rotation_component_needs_a_micropolar_model() -> None:
    d = copy.deepcopy(DECK)
    d["material"] = {"youngs_modulus": E_AL, "density": RHO_AL}
    d["geometry"]["plane"] = "stress"
    d["boundary_conditions"][0]["components"] = ["rotation"]
    with pytest.raises(DeckError) as info:
        parse_deck(d)
    assert any(p.startswith("boundary_conditions.0.components") for p in _paths(info.value))
    assert "boundary_conditions.0.components.rotation" in _paths(info.value)


@pytest.mark.parametrize("refresh", [3, 1000])
def test_woodbury_update_equals_a_fresh_factorisation(refresh: int, monkeypatch) -> None:
    """UpdatedDirect after many removals == SuperLU of the updated matrix, with the
    capacitance inverse updated incrementally (refresh 1000) or recomputed often (3)."""
    import scipy.sparse as sp

    from peridynamics.solvers import linear as lin

    monkeypatch.setattr(lin, "REFRESH_EVENTS", refresh)
    rng = np.random.default_rng(3)
    n = 60
    # a chain of springs plus a diagonal: SPD; "pairs" are the springs (i, i+1)
    k_spring = rng.uniform(1.0, 2.0, n - 1)
    pair = np.array([[1.0, -1.0], [-1.0, 1.0]])
    rows = np.concatenate([np.arange(n - 1), np.arange(1, n)] * 2)
    cols = np.concatenate([np.arange(n - 1), np.arange(1, n), np.arange(1, n), np.arange(n - 1)])
    vals = np.concatenate([k_spring, k_spring, -k_spring, -k_spring])
    k0 = sp.csr_matrix((vals, (rows, cols)), shape=(n, n)) + sp.diags(rng.uniform(0.5, 1.0, n))
    upd = lin.UpdatedDirect(lin.DirectSolver(k0), n)
    k = k0.toarray()
    b = rng.normal(size=n)
    for event, first in enumerate(rng.choice(n - 1, size=12, replace=False)):
        dofs = np.array([[first, first + 1]])
        blocks = (0.5 * k_spring[first] * pair)[None]  # remove half of the spring
        upd.remove(dofs, blocks)
        k[np.ix_(dofs[0], dofs[0])] -= blocks[0]
        x = upd.solve(b)
        assert np.allclose(x, np.linalg.solve(k, b), rtol=1e-10, atol=1e-12), event
    assert upd.rank <= 24 and upd.column_solves == upd.rank


def test_static_solver_refuses_sed_softening() -> None:
    """The static solver never commits softening levels; a softening deck is refused by
    key instead of running as if it were elastic."""
    from tests.helpers import EXAMPLES, cli

    proc = cli(
        "check", "--bonds", str(EXAMPLES / "static_fracture" / "notched_plate_adr.yaml"),
        "--set", "damage.sed_softening={levels: 10, k_c: 4.0, residual: 0.05}",
        "--set", "solver={type: static}",
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "damage.sed_softening: the static solver does not soften bonds" in proc.stderr


def test_a_large_static_lps_model_left_to_auto_gets_a_warning_naming_the_key() -> None:
    """linear_solver: auto picks the direct solver below 250 000 free dofs; for LPS and
    correspondence (coupling two horizons) that filled past 20 GB at 101 136 points in
    2-D, where the iterative solver took 61 s: a warning names the key and the fix."""
    import warnings

    from peridynamics.build.plausibility import ImplausibleInput, warn_direct_solver
    from peridynamics.deck import load_deck
    from tests.helpers import EXAMPLES

    path = EXAMPLES / "lps" / "plate_hole.yaml"
    deck = load_deck(path, ["solver.type=static", "solver.max_iterations=50"])
    with pytest.warns(ImplausibleInput, match="solver.linear_solver: auto .* iterative"):
        warn_direct_solver(deck, 25_284)
    quiet = [
        (deck, 19_000),  # small enough
        (load_deck(path, ["solver.type=static", "solver.max_iterations=50",
                          "solver.linear_solver=iterative"]), 25_284),  # chosen
        (load_deck(path), 25_284),  # adr: no factorisation
    ]  # fmt: skip
    for d, n in quiet:
        with warnings.catch_warnings():
            warnings.simplefilter("error", ImplausibleInput)
            warn_direct_solver(d, n)
