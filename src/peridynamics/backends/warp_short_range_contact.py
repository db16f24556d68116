"""Short-range contact on the Warp device:
:class:`~peridynamics.evaluation.short_range_contact.ShortRangeContact`
as a :class:`~peridynamics.backends.warp_device.DeviceExtra`.

The host's design, kept on the device: a directed CSR Verlet list of the pairs closer
than ``d_c + skin`` (each row sorted by the global point id, with the index of bond
(i, j) and of bond (j, i), -1 when not bonded), rebuilt only when some point has moved
by more than ``skin / 2`` since the last build; the force pass gathers over each point's
own row (one thread per point, no atomics), with the host's arithmetic and summation
order. The candidate search runs on the device on a float64 :class:`warp.HashGrid`
(cells of side ``cutoff (1 + 1e-5)``, the query returns a superset; each candidate is
then kept by the host's exact test ``|y_j - y_i|^2 <= (d_c + skin)^2``), so the list
holds the same pairs as the host's. Per step the only copy to the host is the rebuild
test's two flags (8 bytes); a rebuild also reads back the list length.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from peridynamics.backends.warp_device import DeviceModel, DeviceState

try:
    from peridynamics.backends._warp_short_range_contact_dsl import (
        contact_check,
        contact_count,
        contact_fill,
        contact_force,
        contact_force_friction,
        contact_load,
        contact_positions,
    )
except ImportError:  # pragma: no cover - warp-lang absent
    pass

#: grid cells and the query radius exceed the cutoff by this fraction: the float64
#: cell coordinates of ``x + u`` (rounded) never miss a pair within the cutoff
_GRID_MARGIN = 1e-5
#: hash-grid cells per point
_CELLS_PER_POINT = 2
_MAX_CELLS = 2**31 - 1


def supports(model: Any) -> str | None:
    """None when :class:`DeviceContact` runs ``model.contact`` (or there is no contact),
    else a one-line reason naming the deck key."""
    contact = getattr(model, "contact", None)
    if contact is None:
        return None
    from peridynamics.evaluation.short_range_contact import ShortRangeContact

    if not isinstance(contact, ShortRangeContact):
        return f"contact: {type(contact).__name__} has no Warp device version"
    return None


def _grid_dims(n: int, dim: int) -> tuple[int, int, int]:
    """Hash-grid shape, about ``_CELLS_PER_POINT n`` cells over the axes in use."""
    cells = min(max(_CELLS_PER_POINT * n, 8), _MAX_CELLS)
    if dim == 1:
        return cells, 1, 1
    if dim == 2:
        s = math.isqrt(cells - 1) + 1
        return s, s, 1
    s = 1
    while (s + 1) ** 3 <= cells:
        s += 1
    return s + 1, s + 1, s + 1


class DeviceContact:
    """The contact force of ``model.contact`` (a ShortRangeContact) added on the device.

    Parameters
    ----------
    model : Evaluator
        Its ``contact`` supplies x, volumes, d_c, c_s, the skin, the friction
        coefficients and the global ids (the row order); ``density`` and ``time_step``
        are read for the friction.
    dm : DeviceModel

    Attributes
    ----------
    n_rebuilds : int
        Verlet-list builds so far (the first :meth:`add` builds it).
    n_candidate_pairs : int
        Unordered pairs in the current list.
    pair_offsets : wp.array(int64) (n + 1,), pair_j : wp.array(int32),
    pair_bond_ij, pair_bond_ji : wp.array(int64)
        The directed CSR Verlet list (arrays may be longer than ``pair_offsets[n]``).
    power : wp.array(float64) (n,)
        With friction: each point's share of the friction power of the last
        :meth:`add` (W, <= 0); zeros without.
    """

    def __init__(self, model: Any, dm: DeviceModel) -> None:
        reason = supports(model)
        contact = model.contact
        if reason is not None or contact is None:
            raise ValueError(reason or "the model has no contact")
        n, dim = dm.n, dm.dim
        if contact.x.shape != (n, dim):
            raise ValueError(
                f"the contact is for {contact.x.shape[0]} points, the device model has {n}"
            )
        wp = dm.wp
        self.model = model
        self.dm = dm
        self.contact = contact
        self.d_c = float(contact.contact_distance)
        self.c_s = float(contact.stiffness)
        self.cutoff = float(contact.cutoff)
        self.cutoff_sq = self.cutoff * self.cutoff
        self.limit_sq = (0.5 * float(contact.skin)) ** 2
        self.radius = self.cutoff * (1.0 + _GRID_MARGIN)
        self.volume = dm.upload("volume", np.asarray(contact.volume, dtype=np.float64))
        # the host's row order: global ids (private to ShortRangeContact, arange in serial)
        key = getattr(contact, "_key", None)
        key = np.arange(n, dtype=np.int64) if key is None else key
        self.key = dm.upload("global_ids", np.asarray(key, dtype=np.int64))
        self.friction = bool(contact.has_friction)
        self.mu_s = float(contact.friction_static)
        self.mu_k = float(contact.friction_kinetic)
        if self.friction:
            rho = np.asarray(model.density, dtype=np.float64)
            if rho.shape != (n,) or not np.all(rho > 0):
                raise ValueError(f"density must be > 0 with shape ({n},)")
            self.density = dm.upload("density", rho)
        self.grid = wp.HashGrid(*_grid_dims(n, dim), device=dm.device, dtype=wp.float64)
        self.pts = dm.zeros(n, wp.vec3d)
        self.counts = dm.zeros(n + 1, wp.int64)  # counts[n] stays 0: exclusive scan
        self.pair_offsets = dm.zeros(n + 1, wp.int64)
        self._capacity = 0
        self._alloc(1)
        self.u_ref = dm.zeros((n, dim), wp.float64)
        self.flag = dm.zeros(2, wp.int32)
        self.load = dm.zeros(n, wp.float64)
        self.power = dm.zeros(n, wp.float64)
        self.n_rebuilds = 0
        self.n_candidate_pairs = 0

    def _alloc(self, m: int) -> None:
        if m <= self._capacity:
            return
        wp, dm = self.dm.wp, self.dm
        cap = max(m, self._capacity + self._capacity // 2)
        self.pair_j = dm.zeros(cap, wp.int32)
        self.pair_bond_ij = dm.zeros(cap, wp.int64)
        self.pair_bond_ji = dm.zeros(cap, wp.int64)
        self._capacity = cap

    # -- Verlet list ------------------------------------------------------------------------
    def _check(self, u: Any) -> tuple[bool, bool]:
        """(moved beyond skin / 2 since the last build, a position is not finite)."""
        dm = self.dm
        self.flag.zero_()
        dm.launch(contact_check, dm.n, [dm.x, u, self.u_ref, self.limit_sq, self.flag])
        f = self.flag.numpy()
        return bool(f[0]), bool(f[1])

    def needs_rebuild(self, u: Any) -> bool:
        """True if no list was built yet or some point moved by more than skin / 2 (the
        host's rule); one 8-byte copy to the host."""
        return self.n_rebuilds == 0 or self._check(u)[0]

    def rebuild(self, u: Any) -> None:
        """Build the Verlet list at the displacements ``u`` (wp (n, dim)) now."""
        self._rebuild(u, self._check(u)[1])

    def _rebuild(self, u: Any, not_finite: bool) -> None:
        if not_finite:
            raise ValueError("displacements contain NaN or inf: cannot search for contacts")
        dm = self.dm
        wp = dm.wp
        n = dm.n
        dm.launch(contact_positions, n, [dm.x, u, self.pts])
        self.grid.build(self.pts, self.radius)
        grid = self.grid.id
        dm.launch(
            contact_count,
            n,
            [grid, self.pts, dm.x, u, self.radius, self.cutoff_sq, self.counts],
        )
        wp.utils.array_scan(self.counts, self.pair_offsets, inclusive=False)
        m = int(self.pair_offsets[n : n + 1].numpy()[0])
        self._alloc(m)
        dm.launch(
            contact_fill,
            n,
            [
                grid,
                self.pts,
                dm.x,
                u,
                self.radius,
                self.cutoff_sq,
                self.pair_offsets,
                self.key,
                dm.offsets,
                dm.bond_j,
                self.pair_j,
                self.pair_bond_ij,
                self.pair_bond_ji,
            ],
        )
        wp.copy(self.u_ref, u)
        self.n_rebuilds += 1
        self.n_candidate_pairs = m // 2

    def update(self, u: Any) -> None:
        """Rebuild the list if the host's rule asks for it."""
        if self.n_rebuilds == 0:
            self.rebuild(u)
            return
        moved, not_finite = self._check(u)
        if moved:
            self._rebuild(u, not_finite)

    def lists(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Host copies of the Verlet list: pair_offsets, pair_j, pair_bond_ij, pair_bond_ji
        (as ShortRangeContact's; diagnostics and tests)."""
        off = self.pair_offsets.numpy()
        m = int(off[-1])
        return (
            off,
            self.pair_j.numpy()[:m],
            self.pair_bond_ij.numpy()[:m],
            self.pair_bond_ji.numpy()[:m],
        )

    # -- force --------------------------------------------------------------------------------
    def add(self, ds: DeviceState) -> None:
        """Add the contact force density (N/m^3) at ``ds.u`` to ``ds.force`` (pairs joined
        by a bond intact in ``ds.intact`` excluded); with friction also reads ``ds.v``,
        the model's density and ``model.time_step``, and writes ``power``."""
        dm = self.dm
        self.update(ds.u)
        args = [self.pair_offsets, self.pair_j, self.pair_bond_ij, self.pair_bond_ji]
        args.append(ds.intact)
        if not self.friction:
            dm.launch(
                contact_force,
                dm.n,
                [dm.x, ds.u, self.volume, *args, self.d_c, self.c_s, ds.force],
            )
            return
        dt = float(self.model.time_step)
        if not (math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be a finite value > 0 s, got {dt}")
        dm.launch(
            contact_load, dm.n, [dm.x, ds.u, self.volume, *args, self.d_c, self.c_s, self.load]
        )
        dm.launch(
            contact_force_friction,
            dm.n,
            [
                dm.x,
                ds.u,
                ds.v,
                self.volume,
                self.density,
                *args,
                self.d_c,
                self.c_s,
                self.mu_s,
                self.mu_k,
                dt,
                self.load,
                ds.force,
                self.power,
            ],
        )

    def friction_power(self) -> float:
        """The friction power of the last :meth:`add` (W, <= 0; a copy of ``power``)."""
        return float(np.sum(self.power.numpy()))
