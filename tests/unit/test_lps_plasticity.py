"""Elastic-plastic LPS (Mitchell 2011): the Numba kernels against their NumPy twins, the
elastic LPS below yield, force = -grad(free energy) at a fixed plastic history, the
uniaxial-stress path of an interior point against closed-form J2 (yield, hardening
slope E H / (E + H), unloading slope E), the history commit, a checkpoint round trip,
the deck keys, and (long) the example bar through dynamic relaxation."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.build.decomposed import _refuse
from peridynamics.build.errors import SetupError
from peridynamics.deck import DeckError, parse_deck
from peridynamics.families.lps import LPSMaterial
from peridynamics.families.lps import plastic as pl
from peridynamics.kernels import reference_lps_plasticity as twins

E, NU, RHO = 200e9, 0.3, 7800.0
SY, H = 2e5, 2e10  # a yield strain of 1e-6: the geometric nonlinearity stays ~1e-6
DECK = {
    "name": "lps_plastic",
    "geometry": {"type": "box", "size": [0.009, 0.009, 0.009]},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 2.015},
    "material": {"model": "lps", "youngs_modulus": E, "poisson_ratio": NU, "density": RHO,
                 "plasticity": {"type": "j2", "yield_stress": SY, "hardening_modulus": H}},
    "solver": {"type": "adr", "load_steps": 4},
    "output": {"plot": "none", "vtk_every": 0},
}  # fmt: skip


def _model(deck: dict | None = None):
    return Simulation.from_deck(parse_deck(copy.deepcopy(deck or DECK))).model


def _random_state(model, seed: int = 1, u_scale: float = 1e-9, broken: float = 0.05):
    """Random displacements and history; a share ``broken`` of the bonds broken (both
    directions)."""
    fm = model.force_model
    rng = np.random.default_rng(seed)
    s = model.new_state()
    s.u[...] = u_scale * rng.standard_normal(s.u.shape)
    cut = rng.random(len(s.intact)) < broken
    s.intact[cut | cut[fm.reverse]] = 0
    s[pl.EXTENSION][...] = 3e-10 * rng.standard_normal(fm.bonds.n_bonds)
    s[pl.STRAIN][...] = 2e-6 * rng.random(fm.cloud.n_points)
    return s


def test_kernels_are_their_numpy_twins() -> None:
    model = _model()
    fm = model.force_model
    s = _random_state(model)
    fm.prepass(s)
    fm.force(s)
    plastic = s[pl.SCALE] < 1.0
    assert 0 < plastic.sum() < len(plastic)  # both branches
    b = fm.bonds
    theta, scale, q = twins.return_map(
        fm.cloud.x, s.u, b.bond_i, b.bond_j, b.bond_length, fm.omega_volume, s.intact,
        fm.theta_scale, fm.extension_coef, s[pl.EXTENSION], s[pl.STRAIN], fm.shear, SY, H,
    )  # fmt: skip
    assert np.abs(theta - s["dilatation"]).max() <= 1e-12 * np.abs(theta).max()
    assert np.abs(scale - s[pl.SCALE]).max() <= 1e-12
    assert np.abs(q - s[pl.STRAIN_TRIAL]).max() <= 1e-12 * q.max()
    f, p = twins.force(
        fm.cloud.x, s.u, b.bond_i, b.bond_j, b.bond_length, fm.omega_volume,
        fm.omega_volume_far, s.intact, theta, fm.dilatation_coef, fm.extension_coef,
        fm.reverse, s[pl.EXTENSION], scale,
    )  # fmt: skip
    assert np.abs(f - s.force).max() <= 1e-12 * np.abs(f).max()
    assert np.abs(p - s[pl.EXTENSION_TRIAL]).max() <= 1e-12 * np.abs(p).max()


def test_below_yield_it_is_the_elastic_lps() -> None:
    model = _model()
    fm = model.force_model
    s = model.new_state()
    rng = np.random.default_rng(2)
    s.u[...] = 1e-11 * rng.standard_normal(s.u.shape)  # strains ~1e-8, below yield
    cut = rng.random(len(s.intact)) < 0.05
    s.intact[cut | cut[fm.reverse]] = 0
    fm.prepass(s)
    fm.force(s)
    elastic = LPSMaterial(E, NU, RHO).force_model(fm.cloud, fm.bonds, fm.surface_correction)
    t = s.copy()
    elastic.prepass(t)
    elastic.force(t)
    assert np.all(s[pl.SCALE] == 1.0) and not s[pl.EXTENSION_TRIAL].any()
    err = np.abs(s.force - t.force).max() / np.abs(t.force).max()
    assert err <= 1e-14, err
    th = np.abs(t["dilatation"]).max()
    assert np.abs(s["dilatation"] - t["dilatation"]).max() <= 1e-14 * th


def test_force_is_minus_the_free_energy_gradient_at_a_fixed_history() -> None:
    d = copy.deepcopy(DECK)
    d["material"]["plasticity"]["yield_stress"] = 1e12  # stays elastic about the history
    model = _model(d)
    fm = model.force_model
    s = _random_state(model, seed=3, u_scale=1e-7, broken=0.0)
    fm.prepass(s)
    fm.force(s)
    assert np.all(s[pl.SCALE] == 1.0)
    vol = fm.cloud.volume
    h = 1e-11
    for p, c in ((0, 0), (300, 1), (364, 2), (500, 0)):
        up, dn = s.copy(), s.copy()
        up.u[p, c] += h
        dn.u[p, c] -= h
        grad = ((fm.energy_density(up) - fm.energy_density(dn)) @ vol) / (2 * h)
        assert abs(s.force[p, c] * vol[p] + grad) <= 1e-6 * np.abs(s.force[p] * vol[p]).max()


def _uniaxial_path(model, strains):
    """Axial and lateral stress of the central point (its neighbours' families are
    whole: it is 4 spacings = 2 horizons from every face) under homogeneous strains
    diag(ex, el, el), el found by the secant method so that its lateral stress vanishes;
    the history committed at every step."""
    fm = model.force_model
    x = fm.cloud.x
    c = int(np.argmin(np.linalg.norm(x - x.mean(0), axis=1)))
    s = model.new_state()

    def stress(ex: float, el: float) -> np.ndarray:
        s.u[...] = x @ np.diag([ex, el, el])
        return fm.point_stress(s)[c]

    out = []
    for ex in strains:
        a, b = -NU * ex, -0.5 * ex
        fa, fb = stress(ex, a)[1, 1], stress(ex, b)[1, 1]
        for _ in range(30):
            if abs(fb) < 1e-12 * SY or fb == fa:
                break
            a, b, fa = b, b - fb * (b - a) / (fb - fa), fb
            fb = stress(ex, b)[1, 1]
        sig = stress(ex, b)
        fm.commit_history(s, fresh=True)
        out.append((sig[0, 0], abs(sig[1, 1]), s[pl.STRAIN][c]))
    return np.array(out)


def test_uniaxial_stress_path_of_an_interior_point_is_closed_form_j2() -> None:
    """Measured: elastic slope 1 + 2.7e-7, yield 1 + 4.3e-7, hardening slope 1 + 8.9e-6,
    unloading slope 1 + 2.6e-6 (the geometric nonlinearity of strains ~1e-6)."""
    ey = SY / E
    eps = ey * np.array([0.5, 1.0, 2.0, 3.0, 4.0, 3.0, 2.0])
    sig, lateral, q = _uniaxial_path(_model(), eps).T
    et = E * H / (E + H)
    assert abs(sig[0] / (E * eps[0]) - 1) < 1e-5  # elastic slope E
    assert abs(sig[1] / SY - 1) < 1e-5  # yield at sigma_y
    assert abs((sig[4] - sig[2]) / (eps[4] - eps[2]) / et - 1) < 1e-4  # E H / (E + H)
    assert abs((sig[4] - sig[6]) / (eps[4] - eps[6]) / E - 1) < 1e-4  # unloading slope E
    assert lateral.max() < 1e-10 * SY
    # the equivalent plastic strain is the uniaxial plastic strain (eps - ey) E / (E + H)
    assert abs(q[4] / ((eps[4] - ey) * E / (E + H)) - 1) < 1e-4 and q[6] == q[4]


def test_history_is_committed_only_when_the_solver_commits() -> None:
    model = _model()
    fm = model.force_model
    specs = {f.name: f for f in fm.state_fields()}
    assert specs[pl.EXTENSION].history and specs[pl.STRAIN].history
    assert not specs[pl.EXTENSION_TRIAL].history and not specs[pl.STRAIN_TRIAL].history
    s = model.new_state()
    s.u[...] = fm.cloud.x @ np.diag([8e-6, -4e-6, -4e-6])
    model.evaluate(s, commit=False)
    assert not s[pl.EXTENSION].any() and s[pl.EXTENSION_TRIAL].any()
    model.commit_damage(s)  # an accepted load step
    assert np.array_equal(s[pl.EXTENSION], s[pl.EXTENSION_TRIAL])
    assert np.array_equal(s[pl.STRAIN], s[pl.STRAIN_TRIAL]) and s[pl.STRAIN].max() > 0


def test_a_checkpoint_keeps_the_history_and_resumes_bit_for_bit(tmp_path) -> None:
    from peridynamics.io.checkpoint import load_checkpoint, write_checkpoint

    d = copy.deepcopy(DECK)
    d["geometry"]["size"] = [0.006, 0.006, 0.006]
    d["solver"] = {"type": "explicit", "steps": 10}
    sim = Simulation.from_deck(parse_deck(d))
    s = sim.solver.init()
    s.u[...] = sim.model.cloud.x @ np.diag([8e-6, -4e-6, -4e-6])
    for _ in range(3):
        sim.solver.step(s)
    assert np.abs(s[pl.EXTENSION]).max() > 0
    r = load_checkpoint(write_checkpoint(tmp_path, s, {}, "fp")).state
    for name in (pl.EXTENSION, pl.STRAIN):
        assert np.array_equal(r[name], s[name])
    again = Simulation.from_deck(parse_deck(copy.deepcopy(d)))
    again.solver.resume(r)
    for _ in range(3):
        sim.solver.step(s)
        again.solver.step(r)
    assert np.array_equal(r[pl.EXTENSION], s[pl.EXTENSION]) and np.array_equal(r.u, s.u)
    assert np.array_equal(r[pl.STRAIN], s[pl.STRAIN])


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"plasticity": {"type": "j2", "yield_stress": -1.0}}, "yield_stress"),
        ({"plasticity": {"type": "j2", "yield_stress": 1e6, "hardening_modulus": -1.0}},
         "hardening_modulus"),
        ({"plasticity": {"type": "j2", "yield_stress": 1e6, "kinematic_modulus": 1e9}},
         "material.plasticity.kinematic_modulus"),
        ({"plasticity": {"type": "drucker_prager", "cohesion": 1e6, "friction_angle": 30.0}},
         "material.plasticity.type"),
        ({"viscoelastic": {"fraction": 0.5, "relaxation_time": 1.0}}, "material.plasticity"),
        ({"solver": {"type": "fatigue"}}, "solver.type"),
        ({"solver": {"steps": 5, "backend": "warp"}}, "solver.backend"),
        ({"geometry": {"type": "rectangle", "size": [0.01, 0.005]}}, "material.plasticity"),
        ({"damage": {"model": "plastic_strain", "critical_plastic_strain": 0.1}}, "damage.model"),
    ],
)  # fmt: skip
def test_bad_keys_name_the_key(change: dict, key: str) -> None:
    d = copy.deepcopy(DECK)
    for k, v in change.items():
        if k in ("plasticity", "viscoelastic"):
            d["material"][k] = v
        else:
            d[k] = v
    with pytest.raises(DeckError) as err:
        parse_deck(d)
    assert key in str(err.value)


def test_mpi_is_refused_by_key() -> None:
    with pytest.raises(SetupError, match=r"material\.plasticity"):
        _refuse(parse_deck(copy.deepcopy(DECK)), 2)


@pytest.mark.long
def test_the_example_bar_against_closed_form_j2(tmp_path) -> None:
    """``examples/plasticity/lps_bar.yaml`` (20 x 6 x 6 points, ADR): measured elastic
    slope 1.024 E and unloading slope 1.027 E (the bar stiffness of the surface-corrected
    lattice, as in the elastic LPS), yield 1.027 sigma_y, hardening slope 1.015 E H / (E
    + H); the unloading slope is the bar's own elastic slope within 0.3 %."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "examples" / "plasticity" / "make_figures.py"
    spec = importlib.util.spec_from_file_location("plasticity_figures", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    res = mod.main(["--case", "lps", "--out", str(tmp_path)])
    assert (tmp_path / "lps_bar.png").is_file() and (tmp_path / "lps_bar.json").is_file()
    assert abs(res["elastic_slope_over_E"] - 1) < 0.04
    assert abs(res["yield_stress_over_sigma_y"] - 1) < 0.04
    assert abs(res["hardening_slope_over_closed_form"] - 1) < 0.03
    assert abs(res["unloading_slope_over_E"] / res["elastic_slope_over_E"] - 1) < 0.005
