"""The contract every force model keeps, checked on every family of ``cases.CASES``.

1. Rigid motion (translation plus rotation) gives no force and no energy.
2. Force = -grad(energy): V_i f_i = -dE/dq_i, E = sum_i W_i V_i, by central differences,
   for every dof group (displacements, rotations).
3. The analytic tangent (where the family has one) is the finite-difference tangent,
   and symmetric.
4. The Numba kernels equal their NumPy twins (where the family has them).
5. The stiffness bound gives a stable step: with the mass M = V inertia,
   lambda_max(M^-1 K) dt^2 <= 4 for dt^2 = min_k,i 2 inertia_k,i / K_k,i (central
   differences are stable for omega dt <= 2; Silling & Askari 2005).
6. A checkpoint round trip keeps every field the family declares, and a fresh model
   reading it back gives the same force bits.

Tolerances are relative to the largest entry of the compared quantity; the measured
spread on these models (largest over the cases) is given beside each.
"""

from __future__ import annotations

from pathlib import Path

import numba
import numpy as np
import pytest
from numpy.typing import NDArray

from peridynamics.io.checkpoint import read_checkpoint, write_checkpoint
from peridynamics.state import State
from tests.contracts.cases import CASES, Case, ForceModel, blank_state, built

#: rigid motion: max |V f| over that of a uniform 1e-3 strain; measured <= 8e-13 for a
#: 0.3 rad rotation (geometrically exact families), 7e-12 for 1e-7 rad (linearised
#: ones: their force is O(angle^2), 6.5e-10 at 1e-6 rad)
RIGID_FORCE = 1e-10
#: rigid motion: max W over that of a uniform 1e-3 strain; measured <= 4e-25 (exact
#: families), 7.2e-23 (linearised ones at 1e-7 rad)
RIGID_ENERGY = 1e-20
#: force against central differences of the energy (h = 1e-6 spacing): measured
#: <= 1.9e-10 (truncation O(h^2) and round-off O(1e-16 E / h) both below)
GRADIENT = 1e-8
#: analytic tangent against central differences of the force (h = 1e-6 spacing):
#: measured <= 3.1e-10
TANGENT = 1e-8
#: symmetry of the tangent: analytic ones measured <= 2e-16; a finite-difference
#: tangent a family returns as its own (softening bonds) <= 9.3e-11
SYMMETRY = 1e-9
#: Numba kernels against NumPy twins (other summation order): measured <= 1e-13
TWIN = 1e-12
#: the stiffness bound is not too conservative: (omega_max dt / 2)^2 >= 0.1 (the step at
#: most sqrt(10) times shorter than the stable one); measured 0.13 (correspondence,
#: docs/theory_correspondence.md: bound / omega^2 of 3.1-7.8) to 0.67 (LPS)
BOUND_FLOOR = 0.1
#: finite-difference step relative to the spacing (rotations: over the radius of gyration)
H = 1e-6

ids = [c.id for c in CASES]
case_params = pytest.mark.parametrize("case", CASES, ids=ids)


@pytest.fixture(autouse=True, scope="module")
def serial_numba():
    """One Numba thread: hundreds of evaluations of models of ~100 points, where a
    parallel launch costs more than the work."""
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(before)


# -- generic dof handling -----------------------------------------------------------------
def evaluate(model: ForceModel, st: State) -> None:
    model.prepass(st)
    model.force(st)


def dof_layout(model: ForceModel) -> list[tuple[str, str, int, NDArray[np.float64]]]:
    """(value field, force field, components, inertia (n,)) per dof group."""
    return [
        (d.value, d.force, d.components, model.dof_inertia(k)) for k, d in enumerate(model.dofs())
    ]


def get_q(model: ForceModel, st: State) -> NDArray[np.float64]:
    """All dofs, flat in the tangent's order (per point: group 0's components, then 1's)."""
    return np.concatenate(
        [st[v].reshape(model.n_points, -1) for v, *_ in dof_layout(model)], 1
    ).ravel()


def set_q(model: ForceModel, st: State, q: NDArray[np.float64]) -> None:
    q = q.reshape(model.n_points, -1)
    k = 0
    for v, _, c, _ in dof_layout(model):
        st[v][...] = q[:, k : k + c].reshape(st[v].shape)
        k += c


def vforce(model: ForceModel, st: State) -> NDArray[np.float64]:
    """V_i times the generalised force density of every dof, flat (N, N m)."""
    vol = model.cloud.volume[:, None]
    return np.concatenate(
        [vol * st[f].reshape(model.n_points, -1) for _, f, *_ in dof_layout(model)], 1
    ).ravel()


def steps(model: ForceModel) -> NDArray[np.float64]:
    """Finite-difference step per dof: H spacing, over the radius of gyration for
    rotations (sqrt(inertia), m)."""
    h = H * model.cloud.spacing
    return np.concatenate(
        [np.repeat(h / np.sqrt(inertia)[:, None], c, 1) for _, _, c, inertia in dof_layout(model)],
        1,
    ).ravel()


def energy(model: ForceModel, st: State) -> float:
    return float(np.sum(model.energy_density(st) * model.cloud.volume))


def dense_fd_tangent(model: ForceModel, st: State) -> NDArray[np.float64]:
    """K = -d(V f)/dq column by column (central differences), dense."""
    work, q0, h = st.copy(), get_q(model, st), steps(model)
    k = np.empty((len(q0), len(q0)))
    for col in range(len(q0)):  # one column per dof: the models are small
        q = q0.copy()
        q[col] += h[col]
        set_q(model, work, q)
        evaluate(model, work)
        plus = vforce(model, work)
        q[col] = q0[col] - h[col]
        set_q(model, work, q)
        evaluate(model, work)
        k[:, col] = -(plus - vforce(model, work)) / (2 * h[col])
    return k


def tangent_or_fd(model: ForceModel, st: State) -> NDArray[np.float64]:
    k = model.tangent(st)
    return dense_fd_tangent(model, st) if k is None else k.toarray()


def fresh(case: Case) -> tuple[ForceModel, State]:
    b = built(case.id)
    return b.model, b.state.copy()


# -- 1. rigid motion ----------------------------------------------------------------------
def uniform_strain(model: ForceModel, st: State, strain: float) -> None:
    st.u[...] = 0.0
    st.u[:, 0] = strain * (model.cloud.x[:, 0] - model.cloud.x[:, 0].mean())


@case_params
def test_rigid_motion_gives_no_force_and_no_energy(case: Case) -> None:
    model, _ = fresh(case)
    st = blank_state(model)  # every bond as built
    x = model.cloud.x - model.cloud.x.mean(axis=0)
    uniform_strain(model, st, 1e-3)
    evaluate(model, st)
    f_ref, w_ref = np.abs(vforce(model, st)).max(), model.energy_density(st).max()
    assert f_ref > 0 and w_ref > 0
    a, d = case.rotation, model.dim
    rot = np.eye(d)
    if d > 1:
        rot[:2, :2] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    st.u[...] = x @ rot.T - x + 1e-3 * np.arange(1, d + 1)
    if case.set_rotation is not None:
        case.set_rotation(st, a)
    evaluate(model, st)
    f_rigid = np.abs(vforce(model, st)).max() / f_ref
    w_rigid = np.abs(model.energy_density(st)).max() / w_ref
    assert f_rigid <= RIGID_FORCE, f"rigid-motion force {f_rigid:.3g} of a 1e-3 strain's"
    assert w_rigid <= RIGID_ENERGY, f"rigid-motion energy {w_rigid:.3g} of a 1e-3 strain's"


# -- 2. force = -grad energy --------------------------------------------------------------
@case_params
def test_force_is_minus_energy_gradient(case: Case) -> None:
    model, st = fresh(case)
    evaluate(model, st)
    vf = vforce(model, st)
    q0, h = get_q(model, st), steps(model)
    per_point = len(q0) // model.n_points
    rng = np.random.default_rng(7)
    points = rng.choice(model.n_points, min(8, model.n_points), replace=False)
    dofs = (points[:, None] * per_point + np.arange(per_point)).ravel()
    work = st.copy()
    worst = 0.0
    for dof in dofs:
        q = q0.copy()
        q[dof] += h[dof]
        set_q(model, work, q)
        e_plus = energy(model, work)
        q[dof] = q0[dof] - h[dof]
        set_q(model, work, q)
        grad = (e_plus - energy(model, work)) / (2 * h[dof])
        group = slice(dof % per_point, None, per_point)  # the same component everywhere
        worst = max(worst, abs(-grad - vf[dof]) / np.abs(vf[group]).max())
    assert worst <= GRADIENT, f"|V f + dE/dq| = {worst:.3g} of max |V f|"


# -- 3. tangent ---------------------------------------------------------------------------
@case_params
def test_analytic_tangent_is_the_finite_difference_tangent(case: Case) -> None:
    model, st = fresh(case)
    k = model.tangent(st)
    if k is None:
        pytest.skip(f"{case.id}: no analytic tangent")
    k = k.toarray()
    fd = dense_fd_tangent(model, st)
    scale = np.abs(fd).max()
    err, asym = np.abs(k - fd).max() / scale, np.abs(k - k.T).max() / scale
    assert err <= TANGENT, f"|K - K_fd| = {err:.3g} of max |K|"
    assert asym <= SYMMETRY, f"|K - K^T| = {asym:.3g} of max |K|"


# -- 4. Numba == NumPy --------------------------------------------------------------------
@case_params
def test_numba_equals_numpy_twin(case: Case) -> None:
    if case.twin is None:
        pytest.skip(f"{case.id}: no NumPy twin")
    model, st = fresh(case)
    evaluate(model, st)
    model.update_max_stretch(st)  # the largest stretch: a pass of its own where asked
    for what, got, want in case.twin(model, st):
        got, want = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
        assert got.shape == want.shape, what
        scale = max(np.abs(want).max(), 1e-300)
        err = np.abs(got - want).max() / scale
        assert err <= TWIN, f"{what}: Numba and NumPy differ by {err:.3g} of the largest"


# -- 5. stiffness bound -------------------------------------------------------------------
@case_params
def test_stiffness_bound_covers_the_largest_eigenvalue(case: Case) -> None:
    model, _ = fresh(case)
    st = blank_state(model)  # the undamaged model at rest: what the bound is of
    k = tangent_or_fd(model, st)
    vol = model.cloud.volume
    inertia = np.concatenate([np.repeat(i[:, None], c, 1) for _, _, c, i in dof_layout(model)], 1)
    m = (vol[:, None] * inertia).ravel()  # mass per unit density
    lam = np.linalg.eigvalsh(0.5 * (k + k.T) / np.sqrt(np.outer(m, m)))[-1]
    dt2 = min(
        float(np.min(2.0 * model.dof_inertia(g) / model.dof_stiffness_bound(g)))
        for g in range(len(model.dofs()))
    )
    ratio = lam * dt2 / 4.0
    assert ratio <= 1.0, f"(omega_max dt / 2)^2 = {ratio:.3g}: the bound is not conservative"
    assert ratio >= BOUND_FLOOR, f"(omega_max dt / 2)^2 = {ratio:.3g}: the bound wastes steps"


# -- 6. checkpoint round trip ---------------------------------------------------------------
@case_params
def test_checkpoint_round_trip(case: Case, tmp_path: Path) -> None:
    model, st = fresh(case)
    evaluate(model, st)
    write_checkpoint(tmp_path, st, {}, "contract")
    back, _, _ = read_checkpoint(tmp_path)
    declared = {"intact", "max_stretch"}
    declared |= {getattr(d, a) for d in model.dofs() for a in ("value", "rate", "force", "body")}
    declared |= {s.name for s in model.state_fields()} | set(built(case.id).extra_fields)
    for name in sorted(declared):
        assert name in back, name
        assert back[name].dtype == st[name].dtype and np.array_equal(back[name], st[name]), name
    again = case.build()  # a fresh model reads the State back
    (again.restore or again.model.on_restore)(back)
    evaluate(again.model, back)
    evaluate(model, st)
    for _, f, *_ in dof_layout(model):
        assert np.array_equal(back[f], st[f]), f
