"""NVIDIA Warp kernels of the explicit PMB step (optional extra ``[gpu]``: warp-lang).

One thread per point, as the Numba kernels (:mod:`peridynamics.kernels.bond_based`):
a thread breaks its own family's bonds whose stretch reaches (s0_i + s0_j)/2 and sums
the force of the intact ones; bond (j, i) takes the same decision on thread j because
the bond vector is formed as (x_j - x_i) + (u_j - u_i) and the squares are summed in
component order (exactly antisymmetric, the same bits). Nothing is written to another
point's data, so no atomics. Float64 throughout.

These host-in/host-out wrappers serve tests and scripts; the solver keeps the arrays on
the device (:mod:`peridynamics.backends.warp_solver`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from peridynamics.backends._warp_dsl import wp
from peridynamics.backends.warp_device import require_warp, to_device

if wp is not None:
    from peridynamics.backends._warp_dsl import _damage, _pmb_force_break


def available() -> bool:
    """True when warp-lang can be imported."""
    return wp is not None


def pmb_force_break(
    x: NDArray[np.float64],
    u: NDArray[np.float64],
    offsets: NDArray[np.int64],
    bond_j: NDArray[np.int32],
    stiffness: NDArray[np.float64],
    intact: NDArray[np.uint8],
    s0: NDArray[np.float64],
    device: str = "cpu",
) -> tuple[NDArray[np.float64], NDArray[np.uint8], int]:
    """PMB force density (N/m^3) with critical-stretch breaking on a Warp device.

    Parameters are those of :func:`peridynamics.kernels.bond_based.force_2d` (x, u
    (n, dim) m; CSR ``offsets`` (n + 1,), ``bond_j`` (n_bonds,) int32; ``stiffness``
    (n_bonds,) c beta V_j lambda; ``intact`` (n_bonds,) uint8; ``s0`` (n,)). Host arrays
    in, host arrays out (a device-resident solver keeps them on the device).

    Returns
    -------
    force : (n, dim) force density; intact : (n_bonds,) flags after breaking;
    broken : directed bonds broken by this call.
    """
    w = require_warp()
    n, dim = x.shape
    md = to_device(np.asarray(intact, dtype=np.uint8), device)
    fd = w.zeros((n, dim), dtype=w.float64, device=device)
    bd = w.zeros(n, dtype=w.int64, device=device)
    args: list[NDArray] = [x, u, np.asarray(offsets, dtype=np.int64),
                           np.asarray(bond_j, dtype=np.int32), stiffness]  # fmt: skip
    w.launch(_pmb_force_break, dim=n,
             inputs=[*(to_device(a, device) for a in args), md, to_device(s0, device), fd, bd],
             device=device)  # fmt: skip
    return fd.numpy(), md.numpy(), int(bd.numpy().sum())


def point_damage(
    offsets: NDArray[np.int64],
    bond_volume: NDArray[np.float64],
    intact: NDArray[np.uint8],
    device: str = "cpu",
) -> NDArray[np.float64]:
    """Local damage 1 - (intact partial volume)/(partial volume) per point, shape (n,)
    (Lu & Wang (2016), eq. 7), on a Warp device."""
    w = require_warp()
    n = len(offsets) - 1
    out = w.zeros(n, dtype=w.float64, device=device)
    flags = np.asarray(intact, dtype=np.uint8)
    args: list[NDArray] = [np.asarray(offsets, dtype=np.int64), bond_volume, flags]
    w.launch(_damage, dim=n, inputs=[*(to_device(a, device) for a in args), out], device=device)
    return out.numpy()
