"""Device (Warp, CPU device) viscous bond forces and SED softening against the host."""

from __future__ import annotations

import numpy as np
import pytest

wp = pytest.importorskip("warp", reason="warp-lang not installed (pip install '.[gpu]')")
pytestmark = pytest.mark.gpu  # the Warp tier (pytest -m gpu); the smoke test: test_warp_kernels.py

from peridynamics import BondBasedMaterial, Evaluator, build_bonds  # noqa: E402
from peridynamics.backends._warp_dsl import _pmb_force_break  # noqa: E402
from peridynamics.backends.warp_device import DeviceModel, DeviceState, to_device  # noqa: E402
from peridynamics.backends.warp_extras import DeviceSED, DeviceViscosity, supports  # noqa: E402
from peridynamics.damage import CriticalStretch, SEDSoftening  # noqa: E402
from peridynamics.families.viscosity import BondViscosity  # noqa: E402
from peridynamics.geometry import bar, box, rectangle  # noqa: E402
from peridynamics.kernels import reference  # noqa: E402
from peridynamics.kernels.viscous import add_viscous_force  # noqa: E402

DEVICE = "cpu"
E, RHO = 193e9, 8027.0


def _cloud(dim: int, dx: float):
    if dim == 1:
        return bar(0.03, dx, area=1e-4)
    if dim == 2:
        return rectangle((0.010, 0.008), dx, thickness=2e-3)
    return box((0.004, 0.004, 0.0035), dx)


def _put(dev, host: np.ndarray) -> None:
    wp.copy(dev, to_device(host, DEVICE))


# ----------------------------------------------------------------------------- viscosity
@pytest.mark.parametrize("dim", [1, 2, 3])
def test_device_viscosity_matches_numba_and_numpy(dim: int) -> None:
    dx = 1e-3 if dim < 3 else 5e-4
    cloud = _cloud(dim, dx)
    bonds = build_bonds(cloud, 3.015 * dx, "truncated")
    model = Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), viscosity=BondViscosity(0.5, 2.0))
    assert supports(model) is None
    rng = np.random.default_rng(dim)
    b = model.bonds
    u = rng.normal(size=cloud.x.shape) * 1e-6
    v = rng.normal(size=cloud.x.shape)
    intact = (rng.random(b.n_bonds) > 0.1).astype(np.uint8)
    intact = np.minimum(intact, intact[b.reverse_index()])
    f0 = rng.normal(size=cloud.x.shape) * 1e3  # add() adds to what is there

    state = model.new_state()
    state.u[...] = u
    state.v[...] = v
    state.intact[...] = intact
    state.force[...] = f0
    dm = DeviceModel(model, DEVICE)
    ds = DeviceState(dm, state)
    visc = DeviceViscosity(model, dm)
    visc.add(ds)
    got = ds.force.numpy()

    lin, quad = model._viscous
    numba = f0.copy()
    add_viscous_force(
        cloud.x, u, v, b.offsets, b.bond_j, model.inv_length, b.bond_volume, intact, lin,
        quad, numba,
    )  # fmt: skip
    twin = f0 + reference.viscous_force(
        cloud.x, u, v, b.bond_i, b.bond_j, b.bond_length, b.bond_volume, intact, lin, quad
    )
    visc_part = numba - f0
    scale = np.abs(visc_part).max()
    assert scale > 10 * np.abs(f0).max()  # the viscous term dominates what is compared
    np.testing.assert_allclose(got, numba, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(got, twin, rtol=0, atol=1e-12 * scale)
    # broken bonds carry nothing
    _put(ds.intact, np.zeros_like(intact))
    _put(ds.force, f0)
    visc.add(ds)
    np.testing.assert_array_equal(ds.force.numpy(), f0)


# ---------------------------------------------------------------------------------- SED
def _sed_model(dim: int, energy: str):
    dx = 5e-4
    cloud = _cloud(dim, dx)
    bonds = build_bonds(cloud, 3 * dx)
    soft = SEDSoftening(levels=6, k_c=3.0, residual=0.05, threshold_stretch=1e-3, energy=energy)
    model = Evaluator(
        cloud, bonds, BondBasedMaterial(4.71e9, 1810.0), CriticalStretch(0.00318),
        surface_correction=True, softening=soft,
    )  # fmt: skip
    return model


@pytest.mark.parametrize(("dim", "energy"), [(1, "total"), (2, "total"), (2, "tensile"),
                                             (3, "total"), (3, "tensile")])  # fmt: skip
def test_device_sed_follows_host_evaluations(dim: int, energy: str) -> None:
    model = _sed_model(dim, energy)
    assert supports(model) is None
    x = model.cloud.x
    n, nb = model.n_points, model.bonds.n_bonds
    host = model.new_state()
    dm = DeviceModel(model, DEVICE)
    ds = DeviceState(dm, model.new_state())
    sed = DeviceSED(model, dm)
    s0 = dm.upload("point_s0", np.asarray(model.point_s0, dtype=np.float64))
    stiffness0 = model._sed.stiffness0
    rng = np.random.default_rng(10 + dim)
    noise = rng.normal(size=x.shape)
    centre = x.mean(axis=0)
    seen = []
    for step in range(1, 9):
        eps = 5e-4 * step  # up to 4e-3: levels rise from ~1e-3 on, bonds break past s0
        u = eps * (x - centre) * np.where(np.arange(dim) == 0, 1.0, -0.3)
        u += 0.3 * eps * 5e-4 * noise  # stretches scattered around eps: mixed levels
        host.u[...] = u
        model.evaluate(host, commit=True)

        _put(ds.u, u)
        dm.launch(
            _pmb_force_break,
            n,
            [dm.x, ds.u, dm.offsets, dm.bond_j, sed.stiffness, ds.intact, s0, ds.force,
             ds.broken],
        )  # fmt: skip
        sed.update(ds)

        np.testing.assert_array_equal(ds.intact.numpy(), host.intact)
        np.testing.assert_array_equal(ds.fields["sed_level"].numpy(), host["sed_level"])
        f_host = host.force
        np.testing.assert_allclose(
            ds.force.numpy(), f_host, rtol=0, atol=1e-12 * np.abs(f_host).max()
        )
        w_host = model._sed.energy
        # the host sums with fast-math (FMA in s = r / |xi| - 1): round-off of s^2
        np.testing.assert_allclose(sed.energy.numpy(), w_host, rtol=0, atol=1e-12 * w_host.max())
        k_host = model.force_model.stiffness
        np.testing.assert_allclose(sed.stiffness.numpy(), k_host, rtol=1e-12, atol=0)
        np.testing.assert_allclose(sed.factor.numpy(), model._sed.factor, rtol=1e-15)
        seen.append(np.unique(host["sed_level"]))
    # the run exercised every branch: untouched, banded, residual levels side by side
    top = model._sed.params.levels + 1
    assert 0 in seen[0] and top in seen[-1]
    assert any(len(a) >= 3 and ((a > 0) & (a < top)).any() for a in seen)
    assert (host.intact == 0).any() and host.intact.any()
    assert not np.array_equal(sed.stiffness.numpy(), stiffness0)
    assert nb == len(host.intact)

    # restore: the stiffness follows from the levels alone (a resumed run)
    k_before = sed.stiffness.numpy().copy()
    f_before = sed.factor.numpy().copy()
    _put(sed.stiffness, np.full(nb, -1.0))
    _put(sed.factor, np.full(n, -1.0))
    sed.restore(ds)
    np.testing.assert_array_equal(sed.stiffness.numpy(), k_before)
    np.testing.assert_array_equal(sed.factor.numpy(), f_before)
    model.on_restore(host)  # the host's own rebuild: the same bits
    np.testing.assert_array_equal(model.force_model.stiffness, k_before)


def test_device_sed_shares_the_stiffness_array_with_the_family() -> None:
    """The force pass of a family that uploads the stiffness under "stiffness" reads the
    array DeviceSED softens; a fresh DeviceSED on a softened host model starts from the
    host stiffness, and to_host copies back."""
    model = _sed_model(2, "total")
    dm = DeviceModel(model, DEVICE)
    fam = dm.upload("stiffness", model.force_model.stiffness)
    sed = DeviceSED(model, dm)
    assert sed.stiffness is fam
    ds = DeviceState(dm, model.new_state())
    levels = np.random.default_rng(0).integers(0, 8, model.n_points).astype(np.int64)
    _put(ds.fields["sed_level"], levels)
    sed.restore(ds)
    host = model.new_state()
    host["sed_level"][...] = levels
    model.on_restore(host)
    np.testing.assert_array_equal(fam.numpy(), model.force_model.stiffness)
    model.force_model.stiffness[...] = 0.0
    sed.to_host(model)
    np.testing.assert_array_equal(model.force_model.stiffness, fam.numpy())


def test_supports_names_the_deck_key() -> None:
    model = _sed_model(2, "total")
    assert supports(model) is None
    model.force_model.set_precision("float32")
    why = supports(model)
    assert why is not None and why.startswith("solver.precision")
    plain = Evaluator(
        _cloud(2, 1e-3), build_bonds(_cloud(2, 1e-3), 3e-3), BondBasedMaterial(E, RHO)
    )
    assert supports(plain) is None
