"""The point strain-energy density on the Warp device (DeviceEnergy, Warp's CPU device)
against the host force models' ``energy_density`` (Numba kernels / the laws' NumPy
interface) and the NumPy twins: PMB (1-D, 2-D, 3-D, with SED-softened stiffness), LPS
and correspondence (every stabilisation, both device stress laws), broken bonds and
random displacements."""

from __future__ import annotations

import numpy as np
import pytest

wp = pytest.importorskip("warp", reason="warp-lang not installed (pip install '.[gpu]')")
pytestmark = pytest.mark.gpu  # the Warp tier (pytest -m gpu); the smoke test: test_warp_kernels.py

from peridynamics import BondBasedMaterial, Evaluator, build_bonds  # noqa: E402
from peridynamics.backends._warp_dsl import _pmb_force_break  # noqa: E402
from peridynamics.backends.warp_device import DeviceModel, DeviceState, to_device  # noqa: E402
from peridynamics.backends.warp_energy import DeviceEnergy, supports  # noqa: E402
from peridynamics.backends.warp_extras import DeviceSED  # noqa: E402
from peridynamics.damage import CriticalStretch, SEDSoftening  # noqa: E402
from peridynamics.damage.bond_softening import SofteningBonds  # noqa: E402
from peridynamics.families.correspondence.force import DEGENERATE_RATIO  # noqa: E402
from peridynamics.families.correspondence.material import CorrespondenceMaterial  # noqa: E402
from peridynamics.families.lps.material import LPSMaterial  # noqa: E402
from peridynamics.geometry import bar, box, rectangle  # noqa: E402
from peridynamics.kernels import reference  # noqa: E402
from peridynamics.kernels import reference_correspondence as ref_corr  # noqa: E402
from peridynamics.kernels import reference_lps as ref_lps  # noqa: E402

DEVICE = "cpu"
DX = 1e-3
RTOL = 1e-12


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b| (b must not vanish)."""
    scale = np.abs(b).max()
    assert scale > 0
    return float(np.abs(a - b).max() / scale)


def _cut(model: Evaluator, rng: np.random.Generator, frac: float) -> np.ndarray:
    """The reference flags with ``frac`` of the bonds cut, both directions."""
    b = model.bonds
    intact = b.bond_intact.copy()
    hit = np.flatnonzero(rng.random(b.n_bonds) < frac)
    intact[hit] = 0
    intact[b.reverse_index()[hit]] = 0
    return intact


def _state(model: Evaluator, u: np.ndarray, intact: np.ndarray):
    s = model.new_state()
    s.u[...] = u
    s.intact[...] = intact
    return s


def _device_w(model: Evaluator, host, **kw) -> tuple[np.ndarray, DeviceEnergy, DeviceState]:
    dm = DeviceModel(model, DEVICE)
    ds = DeviceState(dm, host)
    en = DeviceEnergy(model, dm, **kw)
    return en.strain_energy_density(ds).numpy(), en, ds


def _check_intact_matters(model: Evaluator, w: np.ndarray, u: np.ndarray, intact: np.ndarray):
    """With every bond intact the device gives other values: the flags are read."""
    whole, _, _ = _device_w(model, _state(model, u, model.bonds.bond_intact))
    assert (intact == 0).any()
    assert _rel(w, whole) > 1e-6


# ---------------------------------------------------------------------------------- PMB
def _pmb_model(dim: int, corr: bool) -> Evaluator:
    if dim == 1:
        cloud = bar(0.03, DX, area=1e-4)
    elif dim == 2:
        cloud = rectangle((0.020, 0.015), DX, thickness=2e-3, jitter=0.15, seed=1)
    else:
        cloud = box((0.007, 0.006, 0.005), DX, jitter=0.15, seed=2)
    bonds = build_bonds(cloud, 3.015 * DX)
    return Evaluator(cloud, bonds, BondBasedMaterial(70e9, 2700.0), surface_correction=corr)


@pytest.mark.parametrize(("dim", "corr"), [(1, False), (2, True), (2, False), (3, True)])
def test_pmb_matches_numba_and_numpy(dim: int, corr: bool) -> None:
    model = _pmb_model(dim, corr)
    assert supports(model)
    fm = model.force_model
    rng = np.random.default_rng(dim)
    intact = _cut(model, rng, 0.15)
    u = rng.normal(size=model.cloud.x.shape) * 2e-3 * DX
    host = _state(model, u, intact)
    w, en, _ = _device_w(model, host)
    assert en.kind == "pmb" and w.shape == (model.n_points,)
    w_host = fm.energy_density(host)
    assert _rel(w, w_host) <= RTOL
    assert np.array_equal(w, w_host)  # same arithmetic, no fast-math on either side
    b = fm.bonds
    twin = reference.strain_energy_density(
        model.cloud.x, u, b.bond_i, b.bond_j, b.bond_length, fm.stiffness, intact
    )
    assert _rel(w, twin) <= RTOL
    _check_intact_matters(model, w, u, intact)


def test_pmb_explicit_stiffness_is_read() -> None:
    model = _pmb_model(2, False)
    rng = np.random.default_rng(5)
    u = rng.normal(size=model.cloud.x.shape) * 2e-3 * DX
    host = _state(model, u, _cut(model, rng, 0.1))
    dm = DeviceModel(model, DEVICE)
    ds = DeviceState(dm, host)
    scale = rng.uniform(0.5, 1.5, model.bonds.n_bonds)
    k = to_device(model.force_model.stiffness * scale, DEVICE)
    w = DeviceEnergy(model, dm, stiffness=k).strain_energy_density(ds).numpy()
    model.force_model.stiffness *= scale
    assert _rel(w, model.force_model.energy_density(host)) <= RTOL
    with pytest.raises(ValueError, match="float64 of shape"):
        DeviceEnergy(model, dm, stiffness=dm.zeros(3, wp.float64))


# ---------------------------------------------------------------------------------- SED
def test_pmb_sed_softened_stiffness_follows_host() -> None:
    """After committing evaluations that raise SED levels, the energy read with the
    device's softened stiffness matches the host model (whose stiffness softened in
    place); the initial stiffness gives other values."""
    dx = 5e-4
    cloud = rectangle((0.010, 0.008), dx, thickness=2e-3)
    soft = SEDSoftening(levels=6, k_c=3.0, residual=0.05, threshold_stretch=1e-3)
    model = Evaluator(
        cloud, build_bonds(cloud, 3 * dx), BondBasedMaterial(4.71e9, 1810.0),
        CriticalStretch(0.00318), surface_correction=True, softening=soft,
    )  # fmt: skip
    assert supports(model)
    x = cloud.x
    n = model.n_points
    host = model.new_state()
    dm = DeviceModel(model, DEVICE)
    ds = DeviceState(dm, model.new_state())
    sed = DeviceSED(model, dm)
    en = DeviceEnergy(model, dm)  # default: the array kept under "stiffness"
    assert en.stiffness is sed.stiffness
    s0 = dm.upload("point_s0", np.asarray(model.point_s0, dtype=np.float64))
    stiffness0 = model._sed.stiffness0.copy()
    noise = np.random.default_rng(3).normal(size=x.shape)
    centre = x.mean(axis=0)
    for step in range(1, 7):
        eps = 5e-4 * step
        u = eps * (x - centre) * np.array([1.0, -0.3]) + 0.3 * eps * 5e-4 * noise
        host.u[...] = u
        model.evaluate(host, commit=True)
        wp.copy(ds.u, to_device(u, DEVICE))
        dm.launch(
            _pmb_force_break,
            n,
            [dm.x, ds.u, dm.offsets, dm.bond_j, sed.stiffness, ds.intact, s0, ds.force,
             ds.broken],
        )  # fmt: skip
        sed.update(ds)
        np.testing.assert_array_equal(ds.intact.numpy(), host.intact)
        w = en.strain_energy_density(ds).numpy()
        assert _rel(w, model.force_model.energy_density(host)) <= RTOL
    assert (host["sed_level"] > 0).any() and (host.intact == 0).any()
    assert not np.allclose(sed.stiffness.numpy(), stiffness0, rtol=1e-3, atol=0)
    w0 = DeviceEnergy(model, dm, stiffness=to_device(stiffness0, DEVICE))
    assert _rel(w0.strain_energy_density(ds).numpy(), w) > 1e-3


# ---------------------------------------------------------------------------------- LPS
def _lps_model(dim: int, corr: bool, influence: str) -> Evaluator:
    if dim == 2:
        c = rectangle((0.020, 0.015), DX, thickness=1e-3, jitter=0.15, seed=dim)
    else:
        c = box((0.007, 0.006, 0.005), DX, jitter=0.15, seed=dim)
    mat = LPSMaterial(2.0e9, 0.3, 1500.0, influence=influence)
    return Evaluator(c, build_bonds(c, 3.015 * DX), mat, surface_correction=corr)


@pytest.mark.parametrize(
    ("dim", "corr", "influence"),
    [(2, False, "constant"), (2, True, "inverse"), (3, False, "inverse"), (3, True, "constant")],
)
def test_lps_matches_numba_and_numpy(dim: int, corr: bool, influence: str) -> None:
    model = _lps_model(dim, corr, influence)
    assert supports(model)
    fm = model.force_model
    rng = np.random.default_rng(10 + dim)
    intact = _cut(model, rng, 0.15)
    u = rng.normal(size=model.cloud.x.shape) * 0.02 * DX
    host = _state(model, u, intact)
    host["dilatation"][...] = 123.0  # stale: the energy recomputes the dilatation
    w, en, ds = _device_w(model, host)
    assert en.kind == "lps"
    w_host = fm.energy_density(host)
    assert _rel(w, w_host) <= RTOL
    assert np.array_equal(w, w_host)  # same arithmetic, no fast-math on either side
    b = fm.bonds
    twin = ref_lps.energy_density(
        model.cloud.x, u, b.bond_i, b.bond_j, b.bond_length, fm.omega_volume, intact,
        fm.theta_scale, fm.k_theta, fm.extension_coef, model.n_points,
    )  # fmt: skip
    assert _rel(w, twin) <= RTOL
    np.testing.assert_array_equal(ds.fields["dilatation"].numpy(), 123.0)  # untouched
    _check_intact_matters(model, w, u, intact)


# ------------------------------------------------------------------------ correspondence
def _corr_model(dim: int, stab: str, law: str) -> Evaluator:
    if dim == 2:
        cloud = rectangle((20 * DX, 15 * DX), DX, thickness=1e-3, plane="stress")
        bonds = build_bonds(cloud, 3.015 * DX)
    else:
        cloud = box((8 * DX, 7 * DX, 6 * DX), DX)
        bonds = build_bonds(cloud, 2.015 * DX)
    return Evaluator(cloud, bonds, CorrespondenceMaterial(70e9, 0.3, 2700.0, stab, law=law))


def _corr_twin(model: Evaluator, u: np.ndarray, intact: np.ndarray) -> np.ndarray:
    fm = model.force_model
    b = fm.bonds
    _, fgrad, _, omega0, active = ref_corr.prepass(
        fm.bond_xi, u, b.offsets, b.bond_j, fm.weight, intact, fm.det_reference,
        DEGENERATE_RATIO, fm.mode, fm.stab_base,
    )  # fmt: skip
    if fm.mode == 2:
        stab = active * 0.5 * fm.micromodulus
    elif fm.mode == 1:
        g = fm.silling_g * fm.micromodulus / b.horizon
        stab = np.where(omega0 > 0, active * g / np.where(omega0 > 0, omega0, 1.0), 0.0)
    else:
        stab = np.zeros(len(u))
    extra = ref_corr.stabilization_energy(
        fm.bond_xi, u, b.offsets, b.bond_j, fm.weight, intact, fgrad, stab, fm.mode
    )
    return np.asarray(active * fm.law.energy_density(fgrad) + extra)


@pytest.mark.parametrize("law", ["st_venant_kirchhoff", "linear_elastic"])
@pytest.mark.parametrize("stab", ["none", "silling2017", "lbscmm"])
@pytest.mark.parametrize("dim", [2, 3])
def test_correspondence_matches_host_and_numpy(dim: int, stab: str, law: str) -> None:
    model = _corr_model(dim, stab, law)
    assert supports(model)
    fm = model.force_model
    rng = np.random.default_rng(20 * dim + len(stab) + len(law))
    n = model.n_points
    intact = _cut(model, rng, 0.1)
    # a degenerate family: every bond of one point cut but those along x
    b = model.bonds
    p = n // 2 + 3
    off_axis = (b.bond_i == p) & (np.abs(b.bond_xi[:, 1:]).max(axis=1) > 0)
    intact[off_axis] = 0
    intact[b.reverse_index()[off_axis]] = 0
    u = rng.normal(size=(n, dim)) * 2e-5
    host = _state(model, u, intact)
    fields = {k: np.array(v, copy=True) for k, v in host.fields.items()}
    w, en, ds = _device_w(model, host)
    assert en.kind == "correspondence"
    assert en.active.numpy()[p] == 0.0 and w[p] == 0.0
    w_host = fm.energy_density(host)
    assert _rel(w, w_host) <= RTOL
    assert _rel(w, _corr_twin(model, u, intact)) <= RTOL
    if stab != "none":  # the stabilisation energy is part of what is compared
        lawless = np.asarray(
            en.active.numpy() * fm.law.energy_density(en.fgrad.numpy().reshape(n, dim, dim))
        )
        assert _rel(lawless, w_host) > 1e-6
    for name, a in fields.items():  # the State's fields are left alone
        np.testing.assert_array_equal(ds.fields[name].numpy(), a, err_msg=name)
    _check_intact_matters(model, w, u, intact)


# ------------------------------------------------------------------------------ supports
def test_supports_and_refusals() -> None:
    soft = Evaluator(
        bar(0.01, DX, area=1e-4), build_bonds(bar(0.01, DX, area=1e-4), 3.015 * DX),
        BondBasedMaterial(70e9, 2700.0), SofteningBonds("bilinear", 30e6, 50.0),
    )  # fmt: skip
    assert not supports(soft)
    dm = DeviceModel(soft, DEVICE)
    with pytest.raises(ValueError, match="no device energy kernel"):
        DeviceEnergy(soft, dm)
    f32 = _pmb_model(2, False)
    assert supports(f32)
    f32.force_model.set_precision("float32")
    assert not supports(f32)
    lps = _lps_model(2, False, "constant")
    with pytest.raises(ValueError, match="PMB force model only"):
        DeviceEnergy(lps, DeviceModel(lps, DEVICE), stiffness=dm.zeros(3, wp.float64))
