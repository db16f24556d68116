"""Finite-strain (logarithmic, Hencky) correspondence plasticity: the Numba kernel
against its NumPy twin, the Jacobi eigensolver against LAPACK, the small-strain limit,
objectivity, uniaxial compression to a log strain of -1 against the closed form of the
J2 law in log strain and Kirchhoff stress, isochoric plastic flow, the deck key."""

from __future__ import annotations

import math

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.deck import DeckError, parse_deck
from peridynamics.families.correspondence.plasticity import DruckerPrager, J2Plasticity
from peridynamics.kernels import finite_plasticity as fkernels
from peridynamics.kernels import plasticity as kernels
from peridynamics.kernels import reference_plasticity as twins

E, NU = 117e9, 0.35
MU = E / (2 * (1 + NU))
LAM = E * NU / ((1 + NU) * (1 - 2 * NU))
BULK = LAM + 2 * MU / 3


def _kernel(law, f, hist, active=None, small=False):
    n, d, _ = f.shape
    active = np.ones(n) if active is None else active
    piola, t, new = np.empty((n, d, d)), np.empty((n, 3, 3)), np.empty_like(hist)
    run = kernels.corotated_update if small else fkernels.hencky_update
    run(np.ascontiguousarray(f), active, law.law_id, law.params(LAM, MU), hist, new, piola, t)
    return piola, t, new


def _rotation(angle: float, axis) -> np.ndarray:
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * kx @ kx


def test_jacobi_eigensolver_matches_lapack() -> None:
    rng = np.random.default_rng(3)
    cases = [np.eye(3), np.diag([2.0, 2.0, 0.5]), np.diag([1.0, 3.0, 2.0])]
    for _ in range(30):
        a = rng.standard_normal((3, 3))
        cases.append(a @ a.T + 0.1 * np.eye(3))
    q = _rotation(0.7, [1, 2, 3])
    cases.append(q @ np.diag([1.5, 1.5, 0.7]) @ q.T)  # a repeated eigenvalue
    vals, vecs, m = np.empty(3), np.empty((3, 3)), np.empty((3, 3))
    for a in cases:
        fkernels.sym_eig3(a, vals, vecs, m)
        scale = np.abs(a).max()
        assert np.allclose(vecs.T @ vecs, np.eye(3), atol=1e-14)
        assert np.abs(vecs @ np.diag(vals) @ vecs.T - a).max() <= 1e-14 * scale
        assert np.allclose(np.sort(vals), np.linalg.eigvalsh(a), rtol=0, atol=1e-14 * scale)


def _plastic_history(law, f, steps=4):
    """A committed plastic history: the twin driven to ``f`` in ``steps`` steps."""
    n, d, _ = f.shape
    hist = np.zeros((n, law.history_size))
    for k in range(1, steps + 1):
        fk = np.eye(d) + (f - np.eye(d)) * k / steps
        _, _, hist = twins.hencky_update(fk, np.ones(n), law.law_id, law.params(LAM, MU), hist)
    return hist


LAWS = [
    J2Plasticity(120e6, 1e9, 2e9, strain="logarithmic"),
    DruckerPrager(10e6, 30.0, 10.0, 2e6, strain="logarithmic"),
]


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("d", [2, 3])
def test_kernel_is_its_numpy_twin(law, d: int) -> None:
    rng = np.random.default_rng(11)
    n = 30
    f0 = np.eye(d) + 0.3 * rng.standard_normal((n, d, d))  # large strains
    f0 = np.where(np.linalg.det(f0)[:, None, None] > 0.2, f0, np.eye(d))
    hist = _plastic_history(law, 0.7 * f0 + 0.3 * np.eye(d))
    active = np.ones(n)
    active[4] = 0.0
    piola, t, new = _kernel(law, f0, hist, active)
    p2, t2, n2 = twins.hencky_update(f0, active, law.law_id, law.params(LAM, MU), hist)
    scale = np.abs(t2).max()
    assert scale > 0 and np.abs(n2[:, -1]).max() > 0  # the points yield
    assert np.abs(piola - p2).max() <= 1e-11 * scale
    assert np.abs(t - t2).max() <= 1e-11 * scale
    assert np.abs(new - n2).max() <= 1e-11 * max(np.abs(n2).max(), 1.0)
    assert np.array_equal(new[4], hist[4]) and not piola[4].any()


@pytest.mark.parametrize("law", LAWS)
def test_small_strain_limit_is_second_order(law) -> None:
    """At strain eps the log and the small (corotated) forms differ by O(eps^2) in P
    (relative O(eps)), elastic and plastic: the difference falls 100-fold per decade."""
    rng = np.random.default_rng(5)
    g = rng.standard_normal((20, 3, 3))
    small = type(law)(**{**law.__dict__, "strain": "small"})
    diffs = []
    for eps in (2e-3, 2e-4):
        f = np.eye(3) + eps * g
        # a fixed plastic history (scaled with eps) so both forms start from the same one
        hist = np.zeros((20, law.history_size))
        hist[:, 0], hist[:, 4], hist[:, 8] = 0.3 * eps, -0.15 * eps, -0.15 * eps
        p_log = _kernel(law, f, hist)[0]
        p_small = _kernel(small, f, hist, small=True)[0]
        diffs.append(np.abs(p_log - p_small).max() / E)
    assert diffs[0] < 20 * 2e-3**2  # |g| ~ 3: the strain is up to ~ 3 eps
    assert 50.0 < diffs[0] / diffs[1] < 200.0


@pytest.mark.parametrize("law", LAWS)
def test_objective_under_a_superposed_rotation(law) -> None:
    rng = np.random.default_rng(2)
    f = np.eye(3) + 0.2 * rng.standard_normal((10, 3, 3))
    hist = _plastic_history(law, 0.8 * f + 0.2 * np.eye(3))
    p, t, new = _kernel(law, f, hist)
    assert np.abs(new[:, -1] - hist[:, -1]).max() > 0  # still flowing
    q = _rotation(1.1, [0.3, -1.0, 0.5])
    pq, tq, newq = _kernel(law, q @ f, hist)
    scale = np.abs(p).max()
    assert np.abs(pq - q @ p).max() <= 1e-11 * scale
    assert np.abs(tq - t).max() <= 1e-11 * scale
    assert np.abs(newq - new).max() <= 1e-12 * max(np.abs(new).max(), 1.0)


def _uniaxial_compression(law, final=-1.0, steps=100):
    """A homogeneous point in uniaxial Kirchhoff stress: the axial log strain down to
    ``final`` (F = diag(exp(e1), exp(e2), exp(e2))), the lateral e2 by Newton with
    T_22 = 0, the history committed each step. Returns (e1, T_11, P_11, hist, F)."""
    hist = np.zeros((1, law.history_size))
    e2 = 0.0
    rows = []
    for e1 in np.linspace(0.0, final, steps + 1)[1:]:

        def t22(e, h=hist, a=e1):
            f = np.diag(np.exp([a, e, e]))[None]
            return _kernel(law, f, h)

        for _ in range(40):
            res = t22(e2)[1][0, 1, 1]
            dh = 1e-7
            slope = (t22(e2 + dh)[1][0, 1, 1] - t22(e2 - dh)[1][0, 1, 1]) / (2 * dh)
            e2 -= res / slope
            if abs(res) < 1e-6 * law.yield_stress:
                break
        p, t, hist = t22(e2)
        rows.append((e1, t[0, 0, 0], p[0, 0, 0], t[0, 1, 1]))
    return np.array(rows), hist, np.diag(np.exp([final, e2, e2]))


def test_uniaxial_compression_to_log_strain_minus_one() -> None:
    """Closed form of J2 with linear hardening in log strain and Kirchhoff stress:
    |tau| = sigma_y + E H/(E + H) (|e| - sigma_y/E) past yield, H = H_iso + H_kin."""
    law = J2Plasticity(120e6, 0.4e9, 0.1e9, strain="logarithmic")
    rows, hist, f = _uniaxial_compression(law)
    e1, tau, piola, lateral = rows.T
    h = law.hardening_modulus + law.kinematic_modulus
    closed = -np.where(
        np.abs(e1) * E < law.yield_stress,
        E * np.abs(e1),
        law.yield_stress + E * h / (E + h) * (np.abs(e1) - law.yield_stress / E),
    )
    err = np.abs(tau - closed).max() / np.abs(closed).max()
    assert err < 0.01
    assert np.abs(lateral).max() < 1e-5 * law.yield_stress
    # P_11 = tau_11 / lambda_1 (P = tau F^-T, F diagonal)
    assert np.allclose(piola, tau / np.exp(e1), rtol=1e-10)
    # the small-strain form is far off at this strain (the log form is needed)
    small = J2Plasticity(120e6, 0.4e9, 0.1e9)
    hist_s = np.zeros((1, small.history_size))
    _, t_s, _ = _kernel(small, f[None], hist_s, small=True)
    assert abs(t_s[0, 0, 0] - closed[-1]) > 0.05 * abs(closed[-1])
    # isochoric flow: tr(eps_p) = 0, so ln J is the elastic volume strain p_tau / K
    eps_p = hist[0, :9].reshape(3, 3)
    assert abs(np.trace(eps_p)) < 1e-12 * np.abs(eps_p).max()
    assert abs(eps_p[0, 0] + 1.0) < 0.01  # nearly all of the strain is plastic
    assert math.isclose(math.exp(np.trace(eps_p)), 1.0, abs_tol=1e-12)  # det F_p
    ln_j = math.log(np.linalg.det(f))
    assert math.isclose(ln_j, tau[-1] / (3.0 * BULK), rel_tol=1e-6)


DECK = {
    "name": "hencky",
    "geometry": {"type": "box", "size": [0.006, 0.006, 0.006]},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 2.015},
    "material": {
        "model": "correspondence",
        "youngs_modulus": E,
        "poisson_ratio": NU,
        "density": 8930.0,
        "plasticity": {"type": "j2", "yield_stress": 120e6, "hardening_modulus": 1e9},
    },
    "boundary_conditions": [{"type": "initial_velocity", "set": "all", "value": [1.0, 0, 0]}],
    "solver": {"type": "explicit", "steps": 2},
    "output": {"plot": "none", "vtk_every": 0},
}


def test_deck_key_strain() -> None:
    deck = {**DECK, "material": {**DECK["material"]}}
    assert parse_deck(deck).material.plasticity.strain == "small"  # default
    sim = Simulation.from_deck(parse_deck(deck))
    assert sim.model.force_model.strain == "small"
    deck["material"]["plasticity"] = {**DECK["material"]["plasticity"], "strain": "logarithmic"}
    sim = Simulation.from_deck(parse_deck(deck))
    assert sim.model.force_model.strain == "logarithmic"
    deck["material"]["plasticity"]["strain"] = "hencky"
    with pytest.raises(DeckError, match=r"material\.plasticity\.j2\.strain"):
        parse_deck(deck)
    with pytest.raises(ValueError, match=r"material\.plasticity\.strain"):
        J2Plasticity(1e8, strain="log")
    lps = {**DECK["material"], "model": "lps"}
    lps["plasticity"] = {"type": "j2", "yield_stress": 1e8, "strain": "logarithmic"}
    with pytest.raises(DeckError, match=r"material\.plasticity\.strain"):
        parse_deck({**DECK, "material": lps})


@pytest.mark.long
def test_the_taylor_bar_example_shortens_and_bulges(tmp_path) -> None:
    """examples/plasticity/taylor_bar.py at dx = 1.6 mm (2 cells in the radius): the bar
    stops against the wall, shortens and spreads; physical bounds only."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "examples" / "plasticity" / "taylor_bar.py"
    spec = importlib.util.spec_from_file_location("taylor_bar_example", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    dx = 1.6e-3
    assert mod.main(["--out", str(tmp_path), "--spacing", str(dx)]) == 0
    res = __import__("json").loads((tmp_path / "taylor_bar.json").read_text())["cases"][0]
    data = mod.deck(dx)
    l0, r0 = data["geometry"]["length"], data["geometry"]["radius"]
    v0 = abs(data["boundary_conditions"][0]["value"][2])
    t_end = data["solver"]["end_time"]
    # shortened, but by less than the distance the rear travels at v0 in the run
    assert l0 - v0 * t_end < res["final_length_m"] < 0.95 * l0
    # spread at the impact face, within the disc one cell thick that holds the volume
    assert 1.1 * r0 < res["footprint_radius_m"] < r0 * math.sqrt(l0 / dx)
    assert res["min_z_m"] > 0.0  # nothing through the wall
    # stopped: the elastic energy left, (sigma_y^2 / E) / (rho v0^2) ~ 0.3 %, bounds the rebound
    assert res["kinetic_energy_fraction"] < 0.05
    assert (tmp_path / "taylor_bar.png").is_file()
