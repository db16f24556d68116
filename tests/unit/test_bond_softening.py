"""Tension-softening PMB bonds (bilinear, trilinear after Petersson 1981): the energy to
break a bond, the strength's independence of the horizon, Numba == NumPy, force ==
-grad(energy), secant unloading, failure and the explicit fast path (deck-level runs:
``test_bond_softening_decks.py``).

The oracles are independent of the code under test: the brittle critical stretch and
the micromodulus are written out from their textbook formulas, and the envelope is
``np.interp`` through its corner points."""

from __future__ import annotations

import math

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.damage.bond_softening import SofteningBonds
from peridynamics.families.pmb_softening.envelope import softening_envelope
from peridynamics.geometry import box, rectangle
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import reference_softening as ref
from peridynamics.kernels.reference import stretch

# the long tier (CI: pytest -m long): the softening kernels compile for about a minute cold
pytestmark = pytest.mark.long

E, RHO, FT, G0 = 30e9, 2400.0, 3e6, 20.0  # concrete-like: s0 = f_t / E = 1e-4
H = 1e-3  # 2-D thickness, 1-D area (m, m^2)
KNEES = {"bilinear": (0.5, 0.5), "trilinear": (2.0 / 9.0, 1.0 / 3.0)}  # Petersson


def brittle_sc(dim: int, delta: float) -> float:
    """Critical stretch of the brittle bond with fracture energy G0 (constant profile):
    1-D sqrt(3 G0/(E delta)), plane stress sqrt(4 pi G0/(9 E delta)) (Ha & Bobaru 2010),
    3-D sqrt(5 G0/(9 K delta)) with K = E/(3(1 - 2 nu)), nu = 1/4 (Silling & Askari)."""
    if dim == 1:
        return math.sqrt(3 * G0 / (E * delta))
    if dim == 2:
        return math.sqrt(4 * math.pi * G0 / (9 * E * delta))
    return math.sqrt(5 * G0 / (9 * (E / 1.5) * delta))


def micromodulus(dim: int, delta: float) -> float:
    """c (N/m^6): 2E/(A delta^2), 9E/(pi h delta^3) (plane stress), 12E/(pi delta^4)."""
    return {1: 2 * E / (H * delta**2), 2: 9 * E / (math.pi * H * delta**3)}.get(
        dim, 12 * E / (math.pi * delta**4)
    )


def oracle_g(s: np.ndarray, s0: float, sf: float, law: str) -> np.ndarray:
    """The envelope through its corners (0, 0), (s0, s0), (s1, beta s0), (sf, 0)."""
    r, beta = KNEES[law]
    s1 = s0 + r * (sf - s0)
    return np.interp(s, [0.0, s0, s1, sf], [0.0, s0, beta * s0, 0.0], right=0.0)


def pair(dim: int, length: float = 1e-3) -> tuple[PointCloud, Evaluator, np.ndarray]:
    """Two points one oblique bond apart (no partial volumes, no surface correction),
    and the unit bond vector."""
    n = np.array([1.0, 0.6, -0.3][:dim])
    n /= np.linalg.norm(n)
    x = np.array([np.zeros(dim), length * n])
    vol = np.array([1.3e-9, 0.7e-9])
    cloud = PointCloud(x, vol, length, H if dim < 3 else 1.0, "stress" if dim == 2 else None)
    return cloud, build_bonds(cloud, 1.5 * length, partial_volume="none"), n


def soft_model(dim: int, law: str, **kw: object) -> tuple[Evaluator, np.ndarray]:
    cloud, bonds, n = pair(dim)
    return Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), SofteningBonds(law, FT, G0, **kw)), n


def pull(model: Evaluator, state, n: np.ndarray, s: float, commit: bool = True) -> float:
    """Stretch the pair to s along the bond; returns the bond force (N) on point 1
    along the bond (tension positive)."""
    state.u[0] = 0.0
    state.u[1] = s * model.bonds.bond_length[0] * n
    model.evaluate(state, commit=commit)
    return float(-model.cloud.volume[1] * state.force[1] @ n)


# ------------------------------------------------------------------------- energy
# 2-D in the default selection; 1-D and 3-D (their own kernels to compile): the long tier
@pytest.mark.parametrize("law", ["bilinear", "trilinear"])
@pytest.mark.parametrize(
    "dim", [pytest.param(1, marks=pytest.mark.long), 2, pytest.param(3, marks=pytest.mark.long)]
)
def test_energy_to_break_one_bond_is_its_share_of_g0(law: str, dim: int) -> None:
    model, n = soft_model(dim, law)
    env = model.force_model.envelope
    delta, length = model.bonds.horizon, float(model.bonds.bond_length[0])
    v0, v1 = model.cloud.volume
    expected = 0.5 * micromodulus(dim, delta) * brittle_sc(dim, delta) ** 2 * length * v0 * v1
    # the kernel's force is piecewise linear in s: the trapezoid is exact with the corners
    nodes = np.union1d(np.linspace(0.0, 1.05 * env.s_f, 3001), [env.s0, env.s1, env.s_f])
    state = model.new_state()
    force = np.array([pull(model, state, n, s) for s in nodes])
    work = float(np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(nodes)) * length)
    assert work == pytest.approx(expected, rel=1e-10, abs=0)
    assert state.bonds_broken == 2 and not state.intact.any() and force[-1] == 0.0
    assert env.s0 == FT / E  # the strength is f_t / E
    assert force.max() == pytest.approx(model.stiffness[1] * v1 * env.s0, rel=1e-12, abs=0)


@pytest.mark.parametrize("law", ["bilinear", "trilinear"])
def test_strength_is_independent_of_the_horizon_and_g0_is_conserved(law: str) -> None:
    material, soft = BondBasedMaterial(E, RHO), SofteningBonds(law, FT, G0)
    s0s, sfs = [], []
    for delta in (1.5e-3, 3e-3):
        env = softening_envelope(soft, material, 2, delta, H, "stress")
        s0s.append(env.s0)
        sfs.append(env.s_f)
        r, beta = KNEES[law]
        s1 = env.s0 + r * (env.s_f - env.s0)
        corners_s = np.array([0.0, env.s0, s1, env.s_f])
        corners_g = np.array([0.0, env.s0, beta * env.s0, 0.0])
        area = float(np.sum(0.5 * (corners_g[1:] + corners_g[:-1]) * np.diff(corners_s)))
        # G = int g ds * K_2 int_0^delta c r^3 dr, K_2 = 2 h (the bonds across a crack)
        g_total = area * 2 * H * micromodulus(2, delta) * delta**4 / 4
        assert g_total == pytest.approx(G0, rel=1e-12, abs=0)
        assert env.work() == pytest.approx(area, rel=1e-12, abs=0)
    assert s0s[0] == s0s[1] == FT / E
    assert sfs[0] > sfs[1] > s0s[0]  # a larger horizon: a shorter tail


def test_strength_above_what_g0_allows_is_refused_with_the_fix() -> None:
    with pytest.raises(ValueError, match="tensile_strength") as info:
        softening_envelope(
            SofteningBonds("bilinear", 30e6, 0.5), BondBasedMaterial(E, RHO), 2, 3e-3, H, "stress"
        )
    assert "fracture_energy" in str(info.value) and "smaller horizon" in str(info.value)
    with pytest.raises(ValueError, match="trilinear_knee"):
        SofteningBonds("bilinear", FT, G0, knee=(0.3, 0.3))
    with pytest.raises(ValueError, match="beta"):
        SofteningBonds("trilinear", FT, G0, knee=(0.3, 1.0))


# -------------------------------------------------------------- kernels and oracles
def random_body(dim: int, seed: int) -> tuple[Evaluator, object, np.random.Generator]:
    """A small cloud with random displacements, history, broken bonds and no-fail
    points; the state is filled in."""
    rng = np.random.default_rng(seed)
    dx = 1e-3
    cloud = rectangle((0.008, 0.006), dx, H) if dim == 2 else box((0.005, 0.004, 0.004), dx)
    bonds = build_bonds(cloud, 3.015 * dx)
    soft = SofteningBonds("trilinear", FT, G0, knee=(0.3, 0.4), no_fail=np.array([0, 5]))
    model = Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), soft)
    sf = model.force_model.envelope.s_f
    rev = bonds.reverse_index()
    state = model.new_state()
    state.u[:] = rng.normal(0.0, 0.4 * sf * dx, cloud.x.shape)
    kappa = np.where(rng.random(bonds.n_bonds) < 0.5, 0.0, rng.uniform(0, 1.2 * sf, bonds.n_bonds))
    state["bond_kappa"][:] = np.maximum(kappa, kappa[rev])
    broken = rng.random(bonds.n_bonds) < 0.05
    state.intact[broken | broken[rev]] = 0
    return model, state, rng


def twin_args(model: Evaluator, state) -> tuple:
    b = model.bonds
    return (model.cloud.x, state.u, b.bond_i, b.bond_j, b.bond_length)


@pytest.mark.parametrize("dim", [2, 3])
def test_kernels_equal_the_numpy_twins(dim: int) -> None:
    model, state, _ = random_body(dim, 1)
    fm, b = model.force_model, model.bonds
    r, beta = fm.knee
    kappa = state["bond_kappa"]
    fm.force(state)
    f_ref, smax_ref = ref.force(
        *twin_args(model, state),
        fm.stiffness,
        state.intact,
        kappa,
        fm.point_s0,
        fm.point_sf,
        r,
        beta,
    )
    assert np.abs(f_ref).max() > 0
    np.testing.assert_allclose(state.force, f_ref, rtol=1e-12, atol=1e-12 * np.abs(f_ref).max())
    np.testing.assert_allclose(state.max_stretch, smax_ref, rtol=1e-12, atol=1e-18)
    w = fm.energy_density(state)
    w_ref = ref.energy_density(
        *twin_args(model, state),
        fm.stiffness,
        state.intact,
        kappa,
        fm.point_s0,
        fm.point_sf,
        r,
        beta,
    )
    np.testing.assert_allclose(w, w_ref, rtol=1e-12, atol=1e-12 * w_ref.max())
    k_trial, proposed = np.empty(b.n_bonds), np.empty(b.n_bonds, dtype=np.uint8)
    count = fm.trial(state, k_trial, proposed)
    k_ref, p_ref = ref.trial(*twin_args(model, state), state.intact, kappa, fm.point_sf)
    # a stretch is a difference of numbers near 1: its rounding is absolute (~1e-16)
    np.testing.assert_allclose(k_trial, k_ref, rtol=1e-12, atol=1e-15)
    assert np.array_equal(proposed, p_ref) and count == int(p_ref.sum()) > 0
    # the kernels' branches were all exercised: elastic, softening, compressed, failed
    s = stretch(*twin_args(model, state))
    kap = np.maximum(kappa, s)
    s0b = 0.5 * (fm.point_s0[b.bond_i] + fm.point_s0[b.bond_j])
    assert np.isinf(s0b).any() and (s < 0).any() and (kap > s0b).any() and (kap < s0b).any()


@pytest.mark.parametrize("law", ["bilinear", "trilinear"])
def test_unloading_is_secant_and_compression_keeps_full_stiffness(law: str) -> None:
    model, n = soft_model(2, law)
    env = model.force_model.envelope
    k = model.stiffness[1] * model.cloud.volume[1]  # force per unit stretch (N)
    state = model.new_state()
    peak = env.s0 + 0.3 * (env.s_f - env.s0)  # past the peak (both sides of the knee)
    for s in np.linspace(0.0, peak, 50):
        assert pull(model, state, n, s) == pytest.approx(
            k * oracle_g(s, env.s0, env.s_f, law), rel=1e-9, abs=1e-12 * k * env.s0
        )
    slope = float(oracle_g(peak, env.s0, env.s_f, law)) / peak
    assert slope < 0.5  # a reduced secant
    for s in (0.9 * peak, 0.5 * peak, 0.1 * peak, 1e-3 * peak):
        assert pull(model, state, n, s) == pytest.approx(k * slope * s, rel=1e-9, abs=0)
    assert state["bond_kappa"][0] == pytest.approx(peak, rel=1e-12, abs=0)  # unloading keeps it
    for s in (-0.5 * env.s0, -3 * env.s0):  # compression: full stiffness
        assert pull(model, state, n, s) == pytest.approx(k * s, rel=1e-9, abs=0)
    assert pull(model, state, n, peak) == pytest.approx(k * slope * peak, rel=1e-9, abs=0)
    beyond = peak + 0.2 * (env.s_f - env.s0)  # reloading past the history: the envelope
    assert pull(model, state, n, beyond) == pytest.approx(
        k * oracle_g(beyond, env.s0, env.s_f, law), rel=1e-9, abs=0
    )


def test_failed_bond_is_broken_and_carries_nothing() -> None:
    model, n = soft_model(3, "trilinear")
    sf = model.force_model.envelope.s_f
    pure = model.new_state()  # a pure evaluation past s_f: no force, nothing committed
    assert pull(model, pure, n, 1.001 * sf, commit=False) == 0.0
    assert pure.intact.all() and pure.bonds_broken == 0 and not pure["bond_kappa"].any()
    assert model.commit_damage(pure) == 2 and not pure.intact.any()  # what ADR does
    state = model.new_state()
    assert pull(model, state, n, 0.5 * sf) > 0
    assert pull(model, state, n, 1.001 * sf) == 0.0
    assert state.bonds_broken == 2 and not state.intact.any()
    assert pull(model, state, n, -1e-3) == 0.0  # not even in compression
    assert state.bonds_broken == 2


def test_no_fail_points_never_soften() -> None:
    model, n = soft_model(2, "bilinear", no_fail=np.array([1]))
    assert not model.damage_law.active
    k = model.stiffness[1] * model.cloud.volume[1]
    state = model.new_state()
    s = 2 * model.force_model.envelope.s_f
    assert pull(model, state, n, s) == pytest.approx(k * s, rel=1e-9, abs=0)
    assert state.intact.all() and state.bonds_broken == 0


@pytest.mark.parametrize("dim", [2, 3])
def test_fused_explicit_path_equals_trial_commit_force(dim: int) -> None:
    model, state, _ = random_body(dim, 3)
    split = state.copy()
    broken = model.evaluate(state, commit=True)  # the fused pass
    law = model.damage_law
    assert law.fused_model is model.force_model
    kappa0 = split["bond_kappa"].copy()
    proposed = law.trial(split)
    assert np.array_equal(split["bond_kappa"], kappa0)  # a trial changes nothing
    assert law.commit(split) == proposed == broken > 0
    model.force_model.force(split)
    for name in ("force", "max_stretch", "intact", "bond_kappa"):
        assert np.array_equal(state[name], split[name]), name
    assert state.bonds_broken == split.bonds_broken == broken
    assert (state["bond_kappa"] > kappa0).any()
