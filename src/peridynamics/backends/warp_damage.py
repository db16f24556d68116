"""Critical-stretch breaking on the Warp device for model families whose force pass does
not break bonds itself (LPS, correspondence): the trial and commit of
:class:`~peridynamics.damage.critical_stretch.CriticalStretchLaw` in one pass (an
explicit step commits every trial), and the largest stretch of the stability check."""

from __future__ import annotations

from typing import Any

import numpy as np

from peridynamics.backends.warp_device import DeviceModel, DeviceState

try:
    from peridynamics.backends._warp_damage_dsl import break_by_stretch, largest_stretch
except ImportError:  # pragma: no cover - warp-lang absent
    pass


class DeviceCriticalStretch:
    """Bonds whose stretch reaches (s0_i + s0_j)/2 break for good (per-point counts into
    ``ds.broken``): the same decisions as ``break_trial`` + ``commit`` on the host.

    Parameters
    ----------
    model : Evaluator
        Its damage law must have ``point_s0`` (n,) (a critical-stretch law); a model
        without damage (every s0 infinite) breaks nothing and launches nothing.
    dm : DeviceModel
    """

    def __init__(self, model: Any, dm: DeviceModel) -> None:
        self.dm = dm
        s0 = np.asarray(model.damage_law.point_s0, dtype=np.float64)
        self.active = bool(np.isfinite(s0).any())
        self.s0 = dm.upload("point_s0", s0)

    def commit(self, ds: DeviceState) -> None:
        """Break the bonds at ``ds.u`` (``ds.broken`` set per point)."""
        dm = self.dm
        if not self.active:
            ds.broken.zero_()
            return
        dm.launch(
            break_by_stretch,
            dm.n,
            [dm.x, ds.u, dm.offsets, dm.bond_j, ds.intact, self.s0, ds.broken],
        )


def device_max_stretch(dm: DeviceModel, ds: DeviceState, out: Any) -> None:
    """Largest stretch of an intact bond per point (0 when none is stretched) into
    ``out`` (wp float64 (n,))."""
    dm.launch(largest_stretch, dm.n, [dm.x, ds.u, dm.offsets, dm.bond_j, ds.intact, out])
