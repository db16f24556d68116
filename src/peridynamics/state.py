"""Solver state: named fields, everything needed to continue a run bit for bit."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

#: scalar entries of a checkpoint (everything else is a field)
_SCALARS = {"t": float, "step": int, "bonds_broken": int, "phase": int}


def _field(name: str, doc: str) -> Any:
    """A property reading and writing ``fields[name]``."""

    def get(self: State) -> NDArray:
        return self.fields[name]

    def put(self: State, value: NDArray) -> None:
        self.fields[name] = value

    return property(get, put, doc=doc)


class State:
    """Named per-point and per-bond arrays plus time and counters.

    Arrays are updated in place by the solvers for speed. Any number of fields with any
    number of components per point can be held; a model family declares the ones it
    needs (:meth:`peridynamics.families.base.ForceModel.state_fields`). The common ones
    have attributes:

    Attributes
    ----------
    t : float
        Time (s); pseudo-time (load-step fraction) for static solvers.
    step : int
        Completed steps (explicit) or iterations (dynamic relaxation).
    u, v : (n, dim) displacement (m) and velocity (m/s).
    force : (n, dim) internal force density at ``t`` (N/m^3).
    body : (n, dim) external force density at ``t`` (N/m^3).
    u_prev : (n, dim) displacement at ``t - dt`` (central difference only).
    intact : (n_bonds,) uint8 bond status (history: decided by the damage law,
        committed by the solver).
    max_stretch : (n,) largest stretch of an intact bond per point.
    bonds_broken : int
        Directed bonds broken since t = 0 (pre-cracks excluded).
    phase : int
        Hybrid solvers: 0 before the switch to the second model, 1 after.

    Further fields (for example ``sed_level``, a history field of SED softening, or a
    model's rotations) are reached with ``state["name"]``.

    Examples
    --------
    >>> import numpy as np
    >>> import peridynamics as pd
    >>> s = pd.State(u=np.zeros((4, 2)), v=np.zeros((4, 2)))
    >>> s["u"].shape, s.t, s.step
    ((4, 2), 0.0, 0)
    """

    __slots__ = ("t", "step", "bonds_broken", "phase", "fields")

    def __init__(
        self,
        t: float = 0.0,
        step: int = 0,
        bonds_broken: int = 0,
        phase: int = 0,
        **fields: NDArray,
    ) -> None:
        self.t = float(t)
        self.step = int(step)
        self.bonds_broken = int(bonds_broken)
        self.phase = int(phase)
        self.fields: dict[str, NDArray] = dict(fields)

    # -- named access ---------------------------------------------------------------
    def __getitem__(self, name: str) -> NDArray:
        return self.fields[name]

    def __setitem__(self, name: str, value: NDArray) -> None:
        self.fields[name] = value

    def __contains__(self, name: object) -> bool:
        return name in self.fields

    def __iter__(self) -> Iterator[str]:
        return iter(self.fields)

    u = _field("u", "displacement (n, dim), m")
    v = _field("v", "velocity (n, dim), m/s")
    force = _field("force", "internal force density (n, dim), N/m^3")
    body = _field("body", "external force density (n, dim), N/m^3")
    u_prev = _field("u_prev", "displacement at t - dt (n, dim), m")
    intact = _field("intact", "bond status (n_bonds,), uint8")
    max_stretch = _field("max_stretch", "largest stretch of an intact bond (n,)")

    # -- copies and checkpoints -----------------------------------------------------
    def copy(self) -> State:
        """Deep copy."""
        return State(
            self.t,
            self.step,
            self.bonds_broken,
            self.phase,
            **{k: a.copy() for k, a in self.fields.items()},
        )

    def copy_into(self, other: State) -> None:
        """Copy every field and scalar into ``other`` (same fields and shapes): a snapshot
        without allocation."""
        for k, a in self.fields.items():
            other.fields[k][...] = a
        other.t, other.step = self.t, self.step
        other.bonds_broken, other.phase = self.bonds_broken, self.phase

    def snapshot(self, keep: State | None) -> State:
        """A copy of this state in ``keep``'s arrays when it has the same layout (no
        allocation in a time loop), else a new copy; returns the snapshot."""
        if keep is None or not self.same_layout(keep):
            return self.copy()
        self.copy_into(keep)
        return keep

    def same_layout(self, other: State) -> bool:
        """True when ``other`` holds the same field names with the same shapes."""
        return self.fields.keys() == other.fields.keys() and all(
            other.fields[k].shape == a.shape for k, a in self.fields.items()
        )

    def to_arrays(self) -> dict[str, np.ndarray]:
        """Flat dict of arrays (scalars as 0-d arrays) for checkpoints: every field,
        whatever the model family declared."""
        out = {k: np.asarray(getattr(self, k)) for k in _SCALARS}
        out.update(self.fields)
        return out

    @classmethod
    def from_arrays(cls, data: dict[str, np.ndarray]) -> State:
        """Inverse of :meth:`to_arrays`."""
        scalars = {k: kind(data[k]) for k, kind in _SCALARS.items() if k in data}
        fields = {k: np.array(a) for k, a in data.items() if k not in _SCALARS}
        return cls(**scalars, **fields)  # type: ignore[arg-type]
