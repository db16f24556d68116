"""The LPS family of the Warp backend (DeviceLPS) on Warp's CPU device against the host
evaluation (Numba kernels, Evaluator.evaluate) and the NumPy twins: forces and dilatation to
1e-12 relative, the same bonds broken with the same per-point counts."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

wp = pytest.importorskip("warp", reason="warp-lang not installed (pip install '.[gpu]')")
pytestmark = pytest.mark.gpu  # the Warp tier (pytest -m gpu); the smoke test: test_warp_kernels.py

from peridynamics.backends.warp_device import DeviceModel, DeviceState  # noqa: E402
from peridynamics.backends.warp_lps import DeviceLPS, supports  # noqa: E402
from peridynamics.bonds import build_bonds  # noqa: E402
from peridynamics.damage.critical_stretch import NO_DAMAGE, CriticalStretch  # noqa: E402
from peridynamics.evaluation import Evaluator  # noqa: E402
from peridynamics.families.lps.material import LPSMaterial  # noqa: E402
from peridynamics.families.pmb.material import BondBasedMaterial  # noqa: E402
from peridynamics.geometry import box, rectangle  # noqa: E402
from peridynamics.kernels import reference_lps as ref  # noqa: E402
from peridynamics.state import State  # noqa: E402

DX = 1e-3
RTOL = 1e-12


def lps_model(dim, surface_correction, influence="constant", damage=NO_DAMAGE, seed=0):
    """30 x 20 (2-D) or 10 x 8 x 6 (3-D) jittered points, Voronoi volumes."""
    if dim == 2:
        c = rectangle((0.030, 0.020), DX, thickness=1e-3, jitter=0.15, seed=seed)
    else:
        c = box((0.010, 0.008, 0.006), DX, jitter=0.15, seed=seed)
    b = build_bonds(c, 3.015 * DX)
    mat = LPSMaterial(2.0e9, 0.3, 1500.0, influence=influence)
    return Evaluator(c, b, mat, damage=damage, surface_correction=surface_correction)


def copy_state(st: State) -> State:
    out = State()
    for name, a in st.fields.items():
        out[name] = np.array(a, copy=True)
    return out


def break_pairs(model, st, fraction, seed):
    """Break a random ``fraction`` of the bonds, both directions."""
    b = model.bonds
    hit = np.flatnonzero(np.random.default_rng(seed).random(b.n_bonds) < fraction)
    st.intact[hit] = 0
    st.intact[b.reverse_index()[hit]] = 0


def on_device(model, host: State):
    dm = DeviceModel(model, "cpu")
    return dm, DeviceState(dm, copy_state(host)), DeviceLPS(model, dm)


def rel(a, b):
    return float(np.abs(a - b).max() / np.abs(b).max())


CASES = [
    (2, False, "constant"),
    (2, True, "inverse"),
    (3, False, "inverse"),
    (3, True, "constant"),
]


@pytest.mark.parametrize(("dim", "corr", "influence"), CASES)
def test_pure_evaluation_matches_numba_and_numpy(dim, corr, influence):
    model = lps_model(dim, corr, influence, damage=CriticalStretch(1e-6), seed=dim)
    fm = model.force_model
    assert (fm.omega_volume_far is not fm.omega_volume) == corr
    st = model.new_state()
    rng = np.random.default_rng(10 + dim)
    st.u[:] = rng.normal(0.0, 0.02 * DX, st.u.shape)
    break_pairs(model, st, 0.15, seed=dim)
    dm, ds, fam = on_device(model, st)
    ds.broken.fill_(7)  # a pure evaluation zeroes the counts
    ds.force.fill_(1e30)  # and overwrites the force
    assert model.evaluate(st, commit=False) == 0
    fam.evaluate(ds, commit=False)
    f = ds.force.numpy()
    theta = ds.fields["dilatation"].numpy()
    assert np.abs(st.force).max() > 0 and np.abs(st["dilatation"]).max() > 0
    assert rel(f, st.force) <= RTOL
    assert rel(theta, st["dilatation"]) <= RTOL
    np.testing.assert_array_equal(ds.intact.numpy(), st.intact)  # pure: nothing breaks
    assert not ds.broken.numpy().any()
    # the NumPy twins, with the far end's weights
    b = model.bonds
    n = model.n_points
    args = (model.cloud.x, st.u, b.bond_i, b.bond_j, b.bond_length, fm.omega_volume, st.intact)
    theta_ref = ref.dilatation(*args, fm.theta_scale, n)
    f_ref, smax_ref = ref.force(
        *args, theta_ref, fm.dilatation_coef, fm.extension_coef, n, wv_far=fm.omega_volume_far
    )
    assert rel(theta, theta_ref) <= RTOL
    assert rel(f, f_ref) <= RTOL
    # the largest stretch of the stability check
    out = dm.zeros(n, wp.float64)
    fam.max_stretch(ds, out)
    assert smax_ref.max() > 0
    assert np.abs(out.numpy() - smax_ref).max() <= RTOL * smax_ref.max()


@pytest.mark.parametrize(("dim", "corr", "influence"), CASES[::3])
def test_committing_evaluation_breaks_the_same_bonds(dim, corr, influence):
    damage = CriticalStretch(4e-3, no_fail=np.arange(0, 40, 3))
    model = lps_model(dim, corr, influence, damage=damage, seed=20 + dim)
    st = model.new_state()
    break_pairs(model, st, 0.05, seed=dim)
    dm, ds, fam = on_device(model, st)
    rng = np.random.default_rng(dim)
    owner = model.bonds.bond_i
    for amp in (2e-3, 3e-3):  # two steps: the second breaks further bonds
        st.u[:] = rng.normal(0.0, amp * DX, st.u.shape)
        ds.u.assign(st.u)
        before = st.intact.copy()
        broken = model.evaluate(st, commit=True)
        fam.evaluate(ds, commit=True)
        assert 0 < broken < 0.5 * before.sum()
        np.testing.assert_array_equal(ds.intact.numpy(), st.intact)
        counts = np.bincount(owner, (before != st.intact).astype(np.int64), model.n_points)
        np.testing.assert_array_equal(ds.broken.numpy(), counts)
        assert int(ds.broken.numpy().sum()) == broken
        assert rel(ds.force.numpy(), st.force) <= RTOL
        assert rel(ds.fields["dilatation"].numpy(), st["dilatation"]) <= RTOL


def test_no_damage_and_a_state_without_the_dilatation_field():
    model = lps_model(2, False)
    st = model.new_state()
    st.u[:] = np.random.default_rng(3).normal(0.0, 0.01 * DX, st.u.shape)
    host = copy_state(st)
    del host.fields["dilatation"]
    dm, ds, fam = on_device(model, host)
    assert "dilatation" not in ds.fields
    ds.broken.fill_(1)
    fam.evaluate(ds, commit=True)  # the infinite threshold breaks nothing, launches nothing
    assert not ds.broken.numpy().any()
    model.evaluate(st, commit=True)
    assert rel(ds.force.numpy(), st.force) <= RTOL
    assert rel(fam.theta.numpy(), st["dilatation"]) <= RTOL


def test_unsupported_models_name_the_deck_key():
    lps = lps_model(2, False)
    assert supports(lps) is None
    other_law = SimpleNamespace(force_model=lps.force_model, damage_law=SimpleNamespace(name="x"))
    reason = supports(other_law)
    assert reason is not None and reason.startswith("damage.model")
    assert "critical stretch" in reason
    dm = DeviceModel(lps, "cpu")
    with pytest.raises(ValueError, match=r"damage\.model.*critical stretch for LPS"):
        DeviceLPS(other_law, dm)
    c = rectangle((0.01, 0.01), DX, thickness=1e-3)
    pmb = Evaluator(c, build_bonds(c, 3.015 * DX), BondBasedMaterial(2.0e9, 1500.0))
    assert supports(pmb).startswith("material.model")
