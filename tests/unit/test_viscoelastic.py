"""Viscoelastic LPS (Mitchell 2011): the exact Maxwell update, the Numba kernel against
its NumPy twin, exact relaxation at constant deviatoric extension against two elastic
LPS models (instantaneous and relaxed), the instantaneous force against the energy
gradient, the history commit, the deck keys, and (long) a 3-D bar in relaxation and
creep through dynamic relaxation against the standard linear solid."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.build.decomposed import _refuse
from peridynamics.build.errors import SetupError
from peridynamics.deck import DeckError, parse_deck
from peridynamics.families.lps import LPSMaterial
from peridynamics.families.lps import viscoelastic as ve
from peridynamics.kernels import reference_viscoelastic as twins
from peridynamics.kernels import viscoelastic as kernels

E, NU, RHO = 1e9, 0.3, 1000.0
FRACTION, TAU = 0.6, 0.2
K = E / (3 * (1 - 2 * NU))
G = E / (2 * (1 + NU))

DECK = {
    "name": "visco",
    "geometry": {"type": "box", "size": [0.006, 0.006, 0.006]},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 2.015},
    "material": {"model": "lps", "youngs_modulus": E, "poisson_ratio": NU, "density": RHO,
                 "viscoelastic": {"fraction": FRACTION, "relaxation_time": TAU}},
    "solver": {"type": "adr", "load_steps": 4},
    "output": {"plot": "none", "vtk_every": 0},
}  # fmt: skip


def _model(deck: dict | None = None):
    return Simulation.from_deck(parse_deck(copy.deepcopy(deck or DECK))).model


def _moduli(shear: float) -> tuple[float, float]:
    """(E, nu) of bulk modulus K and the given shear modulus."""
    return 9 * K * shear / (3 * K + shear), (3 * K - 2 * shear) / (2 * (3 * K + shear))


def test_decay_and_beta() -> None:
    assert kernels.decay_and_beta(0.0, TAU) == (1.0, 0.0)
    for x in (1e-6, 9.99e-5, 1.01e-4, 0.3, 5.0):
        d, b = kernels.decay_and_beta(x * TAU, TAU)
        assert d == pytest.approx(math.exp(-x), rel=1e-14)
        # beta = sum_k>=1 (-1)^(k+1) x^k / (k+1)!, summed to convergence
        exact = sum((-1) ** (k + 1) * x**k / math.factorial(k + 1) for k in range(1, 40))
        assert b == pytest.approx(exact, rel=1e-11)


def _random_state(model, seed: int = 1):
    rng = np.random.default_rng(seed)
    s = model.new_state()
    s.u[...] = 1e-5 * rng.standard_normal(s.u.shape)
    s.intact[rng.random(len(s.intact)) < 0.05] = 0
    s[ve.BACK][...] = 1e-6 * rng.standard_normal(len(s.intact))
    s[ve.DEVIATORIC][...] = 1e-6 * rng.standard_normal(len(s.intact))
    return s


def test_kernel_is_its_numpy_twin() -> None:
    model = _model()
    fm = model.force_model
    s = _random_state(model)
    fm.prepass(s)
    b = fm.bonds
    force = np.zeros_like(s.u)
    eb_t, ed_t = np.empty(b.n_bonds), np.empty(b.n_bonds)
    decay, beta = kernels.decay_and_beta(0.05, TAU)
    args = (s.u, b.offsets, b.bond_j, b.bond_length, fm.omega_volume, fm.omega_volume_far,
            s.intact, s["dilatation"], fm.extension_coef, fm.reverse, FRACTION, decay, beta,
            s[ve.BACK], s[ve.DEVIATORIC])  # fmt: skip
    kernels.viscous_force_3d(fm.cloud.x, *args, eb_t, ed_t, force)
    f2, eb2, ed2 = twins.viscous_force(fm.cloud.x, s.u, b.bond_i, *args[2:])
    assert np.abs(force - f2).max() <= 1e-9 * np.abs(f2).max()
    assert np.abs(eb_t - eb2).max() <= 1e-12 * np.abs(eb2).max()
    assert np.abs(ed_t - ed2).max() <= 1e-9 * np.abs(ed2).max()


def test_constant_deviatoric_extension_relaxes_exactly() -> None:
    """u held from t = 0: every eb = ed (1 - exp(-t/tau)), so the force is the elastic
    LPS force of the instantaneous moduli relaxing towards that of the relaxed ones,
    f(t) = f_inf + exp(-t/tau) (f_0 - f_inf), for any step sizes."""
    model = _model()
    fm = model.force_model
    cloud, bonds = fm.cloud, fm.bonds
    oracle = []
    for shear in (G, (1 - FRACTION) * G):
        e, nu = _moduli(shear)
        m = LPSMaterial(e, nu, RHO).force_model(cloud, bonds, fm.surface_correction)
        s = model.new_state()
        s.u[...] = cloud.x @ np.array([[2e-4, 1e-4, 0], [0, -3e-4, 5e-5], [1e-4, 0, 1e-4]]).T
        m.prepass(s)
        m.force(s)
        oracle.append(s.force.copy())
    f0, finf = oracle
    s.force[...] = 0.0
    t = -1e-3  # the first commit ends at t = 0: eb = 0, ed = ed(u)
    fm.bind_step_time(1e-3)
    s.t = t
    model.evaluate(s, commit=True)
    assert np.abs(s.force - f0).max() <= 1e-9 * np.abs(f0).max()
    now = 0.0
    for h in (0.013, 0.2, 0.001, 0.07, 0.4, 0.35):
        s.t = now
        fm.bind_step_time(h)
        model.evaluate(s, commit=True)
        now += h
        want = finf + math.exp(-now / TAU) * (f0 - finf)
        assert np.abs(s.force - want).max() <= 1e-9 * np.abs(f0).max(), now


def test_instantaneous_force_is_minus_the_energy_gradient() -> None:
    model = _model()
    fm = model.force_model
    s = model.new_state()
    rng = np.random.default_rng(3)
    s.u[...] = 1e-5 * rng.standard_normal(s.u.shape)
    s.t = -fm.step_time  # the step ends at t = 0, the time of the (zero) history: dt = 0
    fm.prepass(s)
    fm.force(s)  # eb = 0: the elastic part
    vol = fm.cloud.volume
    h = 1e-10
    for p, c in ((0, 0), (40, 1), (107, 2)):
        up, dn = s.copy(), s.copy()
        up.u[p, c] += h
        dn.u[p, c] -= h
        grad = ((fm.energy_density(up) - fm.energy_density(dn)) @ vol) / (2 * h)
        assert abs(s.force[p, c] * vol[p] + grad) <= 1e-6 * np.abs(s.force[p] * vol[p]).max()


def test_history_is_committed_only_when_the_solver_commits() -> None:
    model = _model()
    fm = model.force_model
    specs = {f.name: f for f in fm.state_fields()}
    assert specs[ve.BACK].history and specs[ve.DEVIATORIC].history
    assert specs[ve.COMMIT_TIME].history and not specs[ve.BACK_TRIAL].history
    assert fm.step_time == pytest.approx(0.25)  # adr: 1 s of pseudo-time in 4 load steps
    s = model.new_state()
    s.u[...] = fm.cloud.x @ np.diag([4e-4, -1e-4, -1e-4])
    model.evaluate(s, commit=False)
    assert not s[ve.BACK].any() and s[ve.DEVIATORIC_TRIAL].any()
    model.commit_damage(s)  # an accepted load step
    assert np.array_equal(s[ve.DEVIATORIC], s[ve.DEVIATORIC_TRIAL])
    assert s[ve.COMMIT_TIME][0] == pytest.approx(0.25)


def test_a_checkpoint_keeps_the_history_and_resumes_bit_for_bit(tmp_path) -> None:
    from peridynamics.io.checkpoint import load_checkpoint, write_checkpoint

    d = copy.deepcopy(DECK)
    d["solver"] = {"type": "explicit", "steps": 10}
    d["material"]["viscoelastic"]["relaxation_time"] = 1e-6
    sim = Simulation.from_deck(parse_deck(d))
    s = sim.solver.init()
    s.u[...] = sim.model.cloud.x @ np.diag([4e-4, -1e-4, -1e-4])
    for _ in range(3):
        sim.solver.step(s)
    assert np.abs(s[ve.BACK]).max() > 0
    r = load_checkpoint(write_checkpoint(tmp_path, s, {}, "fp")).state
    for name in (ve.BACK, ve.DEVIATORIC, ve.COMMIT_TIME):
        assert np.array_equal(r[name], s[name])
    again = Simulation.from_deck(parse_deck(copy.deepcopy(d)))
    again.solver.resume(r)
    for _ in range(3):
        sim.solver.step(s)
        again.solver.step(r)
    assert np.array_equal(r[ve.BACK], s[ve.BACK]) and np.array_equal(r.u, s.u)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"viscoelastic": {"fraction": 1.5, "relaxation_time": 1.0}}, "fraction"),
        ({"viscoelastic": {"fraction": 0.5, "relaxation_time": -1.0}}, "relaxation_time"),
        ({"viscoelastic": {"fraction": 0.5}}, "relaxation_time"),
        ({"viscoelastic": {"fraction": 0.5, "relaxation_time": 1, "tau": 1}}, "tau"),
        ({"solver": {"type": "static"}}, "solver.type"),
        ({"solver": {"steps": 5, "backend": "warp"}}, "solver.backend"),
        ({"geometry": {"type": "rectangle", "size": [0.01, 0.005]}}, "material.viscoelastic"),
    ],
)  # fmt: skip
def test_bad_keys_name_the_key(change: dict, key: str) -> None:
    d = copy.deepcopy(DECK)
    for k, v in change.items():
        if k == "viscoelastic":
            d["material"][k] = v
        else:
            d[k] = v
    with pytest.raises(DeckError) as err:
        parse_deck(d)
    assert key in str(err.value)


def test_mpi_is_refused_by_key() -> None:
    with pytest.raises(SetupError, match=r"material\.viscoelastic"):
        _refuse(parse_deck(copy.deepcopy(DECK)), 2)


# -- (long) a bar in relaxation and creep -------------------------------------------------
LENGTH, SIDE = 0.02, 0.004


def _bar(mode: str, steps: int, fraction: float = FRACTION, shear: float = G) -> np.ndarray:
    """(t, axial strain of the middle, axial stress) per load step of a 3-D bar, 20 x 4 x
    4 points, its left layer held in x and its right layer pulled (``relax``: a
    displacement ramped over the first load step then held; ``creep``: a 1 MPa traction
    likewise), by dynamic relaxation over 1 s of pseudo-time in ``steps`` load steps."""
    e, nu = _moduli(shear)
    d = copy.deepcopy(DECK)
    d["geometry"] = {"type": "box", "size": [LENGTH, SIDE, SIDE]}
    d["discretisation"] = {"spacing": 1e-3, "horizon_factor": 3.015}
    d["material"].update(youngs_modulus=e, poisson_ratio=nu)
    d["material"]["viscoelastic"]["fraction"] = fraction
    d["node_sets"] = {
        "left": {"box": {"min": [-1, -1, -1], "max": [0.001, 1, 1]}},
        "right": {"box": {"min": [LENGTH - 0.001, -1, -1], "max": [1, 1, 1]}},
    }
    tf = {"type": "table", "times": [0.0, 1.0 / steps, 1.0][-min(steps + 1, 3):],
          "values": [0.0, 1.0, 1.0][-min(steps + 1, 3):]}  # fmt: skip
    tf["times"][0] = 0.0
    tf["values"][0] = 0.0
    load = (
        {"type": "displacement", "set": "right", "components": {"x": 1e-3 * (LENGTH - 1e-3)}}
        if mode == "relax"
        else {"type": "traction", "set": "right", "value": [1e6, 0.0, 0.0]}
    )
    d["boundary_conditions"] = [
        {"type": "fixed", "set": "left", "components": ["x"]},
        {**load, "time_function": tf},
    ]
    d["solver"] = {"type": "adr", "load_steps": steps, "tolerance": 1e-10,
                   "max_iterations": 200000, "proportional": False}  # fmt: skip
    sim = Simulation.from_deck(parse_deck(d))
    x, vol = sim.model.cloud.x, sim.model.cloud.volume
    a, b = np.abs(x[:, 0] - 0.0065) < 1e-4, np.abs(x[:, 0] - 0.0125) < 1e-4
    right = x[:, 0] > LENGTH - 0.001
    s = sim.solver.init()
    rows = []
    for _ in range(steps):
        assert sim.solver.step(s).converged
        eps = (s.u[b, 0].mean() - s.u[a, 0].mean()) / 0.006
        rows.append((s.t, eps, -(s.force[right, 0] * vol[right]).sum() / SIDE**2))
    return np.array(rows)


def _ramp(t: np.ndarray, t1: float, start: float, end: float, rate: float) -> np.ndarray:
    """Response to a unit input ramped over [0, t1] then held, of a standard linear
    solid whose step response is ``end + (start - end) exp(-rate t)``."""
    tm = np.minimum(t, t1)
    return (end * tm + (start - end) / rate * (np.exp(-rate * (t - tm)) - np.exp(-rate * t))) / t1


@pytest.mark.long
def test_bar_relaxation_and_creep_against_the_standard_linear_solid() -> None:
    """The bar's instantaneous and relaxed Young's moduli E0, Einf are measured by two
    elastic runs of the same discretisation (fraction 0; shear moduli mu and (1 -
    lambda) mu); the analytic SLS (bulk elastic, shear relaxing) then has the
    relaxation modulus E(t) = Einf + (E0 - Einf) exp(-c t), c = (1 - lambda) E0 /
    (Einf tau), and the creep compliance J(t) = 1/Einf + (1/E0 - 1/Einf) exp(-a t),
    a = (1 - lambda) / tau."""
    e0 = _bar("relax", 1, 0.0)[-1]
    einf = _bar("relax", 1, 0.0, (1 - FRACTION) * G)[-1]
    e0, einf = e0[2] / e0[1], einf[2] / einf[1]
    # the discrete bar's moduli against the continuum ones (measured 7.0 % and 7.8 % high)
    assert abs(e0 / E - 1) < 0.1
    steps = 10
    t1 = 1.0 / steps
    c, a = (1 - FRACTION) * e0 / (einf * TAU), (1 - FRACTION) / TAU
    relax = _bar("relax", steps)
    want = _ramp(relax[:, 0], t1, e0, einf, c)
    err_relax = np.abs(relax[:, 2] / relax[:, 1] / want - 1).max()
    creep = _bar("creep", steps)
    want = 1e6 * _ramp(creep[:, 0], t1, 1 / e0, 1 / einf, a)
    err_creep = np.abs(creep[:, 1] / want - 1).max()
    print(f"E0/E {e0 / E:.4f}, relaxation {err_relax:.2e}, creep {err_creep:.2e}")
    assert err_relax < 0.01 and err_creep < 0.01


@pytest.mark.long
def test_the_example_runs_at_small_size(tmp_path) -> None:
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "examples" / "viscoelastic" / "make_figures.py"
    spec = importlib.util.spec_from_file_location("viscoelastic_figures", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    res = mod.main(["--out", str(tmp_path), "--load-steps", "3"])
    assert (tmp_path / "bar_sls.png").is_file() and (tmp_path / "bar_sls.json").is_file()
    # 3 load steps: under the traction ramp of 1/3 s the strain is not linear in time
    # within the step (it creeps during the ramp), which the update assumes: measured
    # 2.6 % in creep and 0.39 % in relaxation (0.49 % and 0.11 % with 10 load steps)
    assert res["load_steps"] == 3 and res["max_relative_error"] < 0.05
