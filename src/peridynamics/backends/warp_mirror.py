"""The fields of a State whose arrays live on a Warp device, mirrored lazily on the host
(:class:`MirrorFields`): a field is copied back the first time it is read after a step,
so observers copy back only at their interval
(:class:`peridynamics.backends.warp_solver.WarpExplicitSolver`).
"""

from __future__ import annotations

from typing import Any

from numpy.typing import NDArray

from peridynamics.backends.warp_device import DeviceState

__all__ = ["MirrorFields"]


class MirrorFields(dict):  # type: ignore[type-arg]
    """The fields of a State whose arrays live on a device: host arrays refreshed from
    the device on first read after :meth:`mark_stale` (a step)."""

    def __init__(self, host: dict[str, NDArray], ds: DeviceState, on_read: Any = None) -> None:
        super().__init__(host)
        self._ds = ds
        self._stale: set[str] = set()
        #: called once on the first read after a step (the host model's SED stiffness
        #: follows the levels then, for outputs that read the stiffness)
        self._on_read = on_read
        self._pending = False
        #: device-to-host copies made (bytes), for the summary
        self.copied_bytes = 0

    def mark_stale(self) -> None:
        """Every device field changed (after a step)."""
        self._stale = set(self._ds.fields)
        self._pending = self._on_read is not None

    def __getitem__(self, name: str) -> Any:
        if self._pending:
            self._pending = False
            self._on_read()
        a = super().__getitem__(name)
        if name in self._stale:
            self._ds.download(name, a)
            self.copied_bytes += a.nbytes
            self._stale.discard(name)
        return a

    def get(self, name: str, default: Any = None) -> Any:
        return self[name] if name in self else default

    def __iter__(self) -> Any:  # a Python-level iterator: dict(m) goes through []
        return iter(list(super().keys()))

    def items(self) -> Any:
        return [(name, self[name]) for name in list(super().keys())]

    def values(self) -> Any:
        return [self[name] for name in list(super().keys())]
