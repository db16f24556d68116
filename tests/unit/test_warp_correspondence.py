"""The correspondence family on the Warp device (Warp's CPU device) against the host
model: forces and pre-pass fields to 1e-12 of the Numba kernels and of the NumPy twins
(every stabilisation, both stress laws, 2-D and 3-D, broken bonds and a degenerate
family), the same bonds broken by critical stretch and by the correspondence failure
law (principal stress, no-fail points, degenerate-family rounds)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("warp", reason="warp-lang not installed (pip install '.[gpu]')")
pytestmark = pytest.mark.gpu  # the Warp tier (pytest -m gpu); the smoke test: test_warp_kernels.py

from peridynamics.backends.warp_correspondence import (  # noqa: E402
    DeviceCorrespondence,
    supports,
)
from peridynamics.backends.warp_device import DeviceModel, DeviceState  # noqa: E402
from peridynamics.bonds.bonds import build_bonds  # noqa: E402
from peridynamics.damage.critical_stretch import CriticalStretch  # noqa: E402
from peridynamics.damage.principal_stress import CorrespondenceFailure  # noqa: E402
from peridynamics.evaluation import Evaluator  # noqa: E402
from peridynamics.families.correspondence.force import DEGENERATE_RATIO  # noqa: E402
from peridynamics.families.correspondence.material import CorrespondenceMaterial  # noqa: E402
from peridynamics.geometry.generators import box, rectangle  # noqa: E402
from peridynamics.kernels import reference_correspondence as ref  # noqa: E402

STABS = ("none", "silling2017", "lbscmm")
DX = 1e-3


def _geometry(dim: int):
    if dim == 2:
        cloud = rectangle((20 * DX, 15 * DX), DX, thickness=1e-3, plane="stress")
        return cloud, build_bonds(cloud, 3.015 * DX)
    cloud = box((8 * DX, 7 * DX, 6 * DX), DX)
    return cloud, build_bonds(cloud, 2.015 * DX)


def _model(dim: int, stab: str, law: str = "st_venant_kirchhoff", damage=None) -> Evaluator:
    cloud, bonds = _geometry(dim)
    mat = CorrespondenceMaterial(70e9, 0.3, 2700.0, stab, law=law)
    if damage is None:
        return Evaluator(cloud, bonds, mat)
    return Evaluator(cloud, bonds, mat, damage=damage)


def _cut(m: Evaluator, rng: np.random.Generator, frac: float, degenerate: int | None) -> np.ndarray:
    """Intact flags with ``frac`` of the bonds cut (both directions) and, optionally,
    every bond of point ``degenerate`` cut but those along x (a singular K)."""
    b = m.bonds
    intact = b.bond_intact.copy()
    cut = rng.random(b.n_bonds) < frac
    if degenerate is not None:
        mine = b.bond_i == degenerate
        off_axis = np.abs(b.bond_xi[:, 1:]).max(axis=1) > 0
        cut |= mine & off_axis
    intact[cut] = 0
    intact[b.reverse_index()[cut]] = 0
    return intact


def _state(m: Evaluator, u: np.ndarray, intact: np.ndarray):
    s = m.new_state()
    s.u[...] = u
    s.intact[...] = intact
    return s


def _on_device(m: Evaluator, s):
    dm = DeviceModel(m, "cpu")
    ds = DeviceState(dm, s)
    return dm, ds, DeviceCorrespondence(m, dm)


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b| (0 when both vanish, inf when only b does)."""
    scale = np.abs(b).max()
    if scale == 0:
        return 0.0 if not np.abs(a).any() else np.inf
    return float(np.abs(a - b).max() / scale)


def _twin_force(m: Evaluator, u: np.ndarray, intact: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Force and F from the NumPy twins and the law's NumPy interface."""
    fm = m.force_model
    b = fm.bonds
    kinv, fgrad, sigma_s, omega0, active = ref.prepass(
        fm.bond_xi, u, b.offsets, b.bond_j, fm.weight, intact, fm.det_reference,
        DEGENERATE_RATIO, fm.mode, fm.stab_base,
    )  # fmt: skip
    piola = fm.law.first_piola(fgrad) * active[:, None, None]
    amat = np.einsum("nab,nbc->nac", piola - sigma_s, kinv)
    if fm.mode == 2:
        stab = active * 0.5 * fm.micromodulus
    elif fm.mode == 1:
        g = fm.silling_g * fm.micromodulus / b.horizon
        stab = np.where(omega0 > 0, active * g / np.where(omega0 > 0, omega0, 1.0), 0.0)
    else:
        stab = np.zeros(len(u))
    f = ref.force(fm.bond_xi, u, b.offsets, b.bond_j, fm.weight, intact, amat, fgrad, stab, fm.mode)
    return f, fgrad


@pytest.mark.parametrize("law", ["st_venant_kirchhoff", "linear_elastic"])
@pytest.mark.parametrize("stab", STABS)
@pytest.mark.parametrize("dim", [2, 3])
def test_force_matches_numba_and_twin(dim: int, stab: str, law: str) -> None:
    m = _model(dim, stab, law)
    rng = np.random.default_rng(10 * dim + STABS.index(stab))
    n = m.n_points
    intact = _cut(m, rng, 0.1, degenerate=n // 2 + 3)
    u = rng.normal(size=(n, dim)) * 2e-5
    host = _state(m, u, intact)
    dm, ds, fam = _on_device(m, host)
    m.evaluate(host, commit=False)
    m.force_model.update_max_stretch(host)  # the largest stretch: a pass where asked
    assert (host["family_active"] == 0).sum() >= 1  # the degenerate family is there
    fam.evaluate(ds, commit=False)
    assert not ds.broken.numpy().any()
    assert np.array_equal(ds.intact.numpy(), intact)
    force = ds.force.numpy()
    assert np.abs(host.force).max() > 0
    assert _rel(force, host.force) <= 1e-12
    for name in ("deformation_gradient", "force_tensor", "stabilization"):
        assert _rel(ds.fields[name].numpy(), host[name]) <= 1e-12, name
    np.testing.assert_array_equal(ds.fields["family_active"].numpy(), host["family_active"])
    np.testing.assert_allclose(
        ds.fields["max_stretch"].numpy(), host.max_stretch, rtol=0, atol=1e-14
    )
    f_twin, fgrad_twin = _twin_force(m, u, intact)
    assert _rel(force, f_twin) <= 1e-12
    fgrad = ds.fields["deformation_gradient"].numpy().reshape(fgrad_twin.shape)
    assert np.abs(fgrad - fgrad_twin).max() <= 1e-13
    # the stability check's stretch (the critical-stretch formula) agrees too
    out = dm.zeros(n, dm.wp.float64)
    fam.max_stretch(ds, out)
    np.testing.assert_allclose(out.numpy(), host.max_stretch, rtol=0, atol=1e-14)


@pytest.mark.parametrize("stab", STABS)
@pytest.mark.parametrize("dim", [2, 3])
def test_state_without_fields_uses_work_arrays(dim: int, stab: str) -> None:
    m = _model(dim, stab)
    rng = np.random.default_rng(7)
    u = rng.normal(size=(m.n_points, dim)) * 2e-5
    host = _state(m, u, m.bonds.bond_intact)
    bare = _state(m, u, m.bonds.bond_intact)
    for name in ("deformation_gradient", "force_tensor", "stabilization", "family_active"):
        del bare.fields[name]
    del bare.fields["max_stretch"]
    _, ds, fam = _on_device(m, bare)
    fam.evaluate(ds, commit=False)
    m.evaluate(host, commit=False)
    assert _rel(ds.force.numpy(), host.force) <= 1e-12
    assert _rel(fam.fgrad.numpy(), host["deformation_gradient"]) <= 1e-12


def _broken_per_point(m: Evaluator, before: np.ndarray, after: np.ndarray) -> np.ndarray:
    gone = (before.astype(bool) & ~after.astype(bool)).astype(np.int64)
    return np.bincount(m.bonds.bond_i, gone, minlength=m.n_points)


def _commit_both(m: Evaluator, u: np.ndarray, intact: np.ndarray):
    host = _state(m, u, intact)
    _, ds, fam = _on_device(m, host)
    n_host = m.evaluate(host, commit=True)
    fam.evaluate(ds, commit=True)
    return host, ds, n_host


@pytest.mark.parametrize("stab", STABS)
@pytest.mark.parametrize("dim", [2, 3])
def test_commit_critical_stretch(dim: int, stab: str) -> None:
    no_fail = np.arange(0, 40, 3)
    m = _model(dim, stab, damage=CriticalStretch(0.01, no_fail=no_fail))
    rng = np.random.default_rng(3 + dim)
    before = _cut(m, rng, 0.05, degenerate=None)
    u = rng.normal(size=(m.n_points, dim)) * 6e-6
    host, ds, n_host = _commit_both(m, u, before)
    assert n_host > 0 and (host.intact == 1).sum() > 0
    np.testing.assert_array_equal(ds.intact.numpy(), host.intact)
    broken = ds.broken.numpy()
    np.testing.assert_array_equal(broken, _broken_per_point(m, before, host.intact))
    assert broken.sum() == n_host
    assert _rel(ds.force.numpy(), host.force) <= 1e-12
    # without commit nothing breaks and the counts are zeroed
    u2 = u * 3
    _, ds2, fam2 = _on_device(m, _state(m, u2, before))
    ds2.broken.fill_(5)
    fam2.evaluate(ds2, commit=False)
    assert not ds2.broken.numpy().any()
    np.testing.assert_array_equal(ds2.intact.numpy(), before)


def _criteria_only(m: Evaluator, u: np.ndarray, before: np.ndarray) -> np.ndarray:
    """Bonds that the stretch and stress criteria alone break (no degenerate rounds)."""
    law = m.damage_law
    b = m.bonds
    s1 = m.force_model.max_principal_stress(u, before)
    mean = 0.5 * (s1[b.bond_i] + s1[b.bond_j])
    y = b.bond_xi + u[b.bond_j] - u[b.bond_i]
    stretch = np.linalg.norm(y, axis=1) / b.bond_length - 1.0
    thr = 0.5 * (law.point_s0[b.bond_i] + law.point_s0[b.bond_j])
    stress = (mean >= law.tensile_strength) & ~law.protected
    return before.astype(bool) & ((stretch >= thr) | stress)


@pytest.mark.parametrize("s0", [np.inf, 0.012])
@pytest.mark.parametrize("stab", STABS)
@pytest.mark.parametrize("dim", [2, 3])
def test_commit_principal_stress_failure(dim: int, stab: str, s0: float) -> None:
    no_fail = np.arange(5, 60, 4)
    rng = np.random.default_rng(20 + dim)
    m0 = _model(dim, stab)
    n = m0.n_points
    before = _cut(m0, rng, 0.05, degenerate=None)
    u = rng.normal(size=(n, dim)) * 5e-6
    s1 = m0.force_model.max_principal_stress(u, before)
    f_t = float(np.quantile(s1, 0.6))  # a large part of the body fails
    failure = CorrespondenceFailure(CriticalStretch(s0, no_fail=no_fail), f_t)
    m = _model(dim, stab, damage=failure)
    host, ds, n_host = _commit_both(m, u, before)
    assert n_host > 0
    after = ds.intact.numpy()
    np.testing.assert_array_equal(after, host.intact)
    broken = ds.broken.numpy()
    np.testing.assert_array_equal(broken, _broken_per_point(m, before, host.intact))
    assert broken.sum() == n_host
    # the degenerate rounds broke further bonds, and the no-fail points kept some
    crit = _criteria_only(m, u, before)
    gone = before.astype(bool) & ~after.astype(bool)
    assert (gone & ~crit).any()
    assert not (crit & ~gone).any()
    assert (host.intact[np.isin(m.bonds.bond_i, no_fail)] == 1).any()
    assert _rel(ds.force.numpy(), host.force) <= 1e-12
    for name in ("deformation_gradient", "force_tensor", "stabilization"):
        assert _rel(ds.fields[name].numpy(), host[name]) <= 1e-12, name
    # the device's principal stress of the trial is the host law's
    s1_host = m.damage_law.last_stress
    assert _rel(_device_s1(m, u, before), s1_host) <= 1e-12


def _device_s1(m: Evaluator, u: np.ndarray, intact: np.ndarray) -> np.ndarray:
    """The largest principal Cauchy stress that the device pre-pass computes."""
    _, ds, fam = _on_device(m, _state(m, u, intact))
    fam.prepass(ds, want_stress=True)
    return np.asarray(fam.s1.numpy())


def test_supports_rejects_other_models_and_laws() -> None:
    from peridynamics.families.lps.material import LPSMaterial

    cloud, bonds = _geometry(2)
    lps = Evaluator(cloud, bonds, LPSMaterial(70e9, 0.3, 2700.0, "constant"))
    why = supports(lps)
    assert why is not None and why.startswith("material.model")
    with pytest.raises(ValueError, match="material.model"):
        DeviceCorrespondence(lps, DeviceModel(lps, "cpu"))
    m = _model(2, "lbscmm")
    assert supports(m) is None

    class Other:
        name = "neo_hookean"

    m.force_model.law = Other()
    why = supports(m)
    assert why is not None and why.startswith("material.law")
    with pytest.raises(ValueError, match="material.law"):
        DeviceCorrespondence(m, DeviceModel(m, "cpu"))
