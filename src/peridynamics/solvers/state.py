"""Solver state: everything needed to continue a run bit-for-bit."""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np
from numpy.typing import NDArray


@dataclass
class State:
    """Explicit-dynamics state. Arrays are updated in place by the solver for speed.

    Attributes
    ----------
    t : float
        Time (s).
    step : int
        Completed steps.
    u, v : (n, dim) displacement (m) and velocity (m/s).
    force : (n, dim) internal force density at ``t`` (N/m^3).
    body : (n, dim) external force density at ``t`` (N/m^3).
    u_prev : (n, dim) displacement at ``t - dt`` (central difference only).
    intact : (n_bonds,) uint8 bond status.
    max_stretch : (n,) largest stretch of an intact bond per point.
    bonds_broken : int
        Directed bonds broken since t = 0 (pre-cracks excluded).
    phase : int
        Hybrid solvers: 0 before the switch to the second model, 1 after.
    """

    t: float
    step: int
    u: NDArray[np.float64]
    v: NDArray[np.float64]
    force: NDArray[np.float64]
    body: NDArray[np.float64]
    u_prev: NDArray[np.float64]
    intact: NDArray[np.uint8]
    max_stretch: NDArray[np.float64]
    bonds_broken: int = 0
    phase: int = 0

    def copy(self) -> State:
        """Deep copy."""
        return State(
            **{
                f.name: (
                    getattr(self, f.name).copy()
                    if isinstance(getattr(self, f.name), np.ndarray)
                    else getattr(self, f.name)
                )
                for f in fields(self)
            }
        )

    def to_arrays(self) -> dict[str, np.ndarray]:
        """Flat dict of arrays (scalars as 0-d arrays) for checkpoints."""
        return {f.name: np.asarray(getattr(self, f.name)) for f in fields(self)}

    @classmethod
    def from_arrays(cls, data: dict[str, np.ndarray]) -> State:
        """Inverse of :meth:`to_arrays`."""
        kw: dict[str, Any] = {}
        for f in fields(cls):
            if f.name not in data:  # checkpoints written before the field existed
                continue
            a = data[f.name]
            if f.name == "t":
                kw[f.name] = float(a)
            elif f.name in ("step", "bonds_broken", "phase"):
                kw[f.name] = int(a)
            else:
                kw[f.name] = np.array(a)
        return cls(**kw)
