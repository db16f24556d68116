"""Notches: slots of finite width cut from a body, which also cut the bonds across them.

A notch is the slot of width ``w`` around the segment ``start -> end`` in the x-y plane
(a rectangle ``L x w``; with ``tip="round"`` a half-disc of radius ``w/2`` is added
beyond ``end``). In 3-D it is the prism of that slot along z, over ``z = (z_min, z_max)``
or through the whole body. It acts twice:

* :meth:`Notch.region` removes the points strictly inside the slot (a point on its
  boundary is kept), like a hole;
* :meth:`Notch.crack` is a pre-crack along the slot's centre line, from ``start`` to the
  end of the slot (``end``, or ``end + w/2`` along the notch for a round tip): every bond
  that crosses it starts broken, so a notch narrower than the spacing, which removes no
  point, still separates its two faces.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from peridynamics.bonds.precrack import Crack, RectangleCrack, SegmentCrack
from peridynamics.geometry.regions import BoolArray, Region

NotchTip = Literal["flat", "round"]


@dataclass(frozen=True, init=False)
class Notch:
    """A slot of width ``width`` (m) along ``start -> end`` (m, x-y plane).

    Parameters
    ----------
    start, end : array_like, shape (2,)
        Ends of the slot's centre line (m). ``start`` is the mouth (flat), ``end`` the
        tip.
    width : float
        Slot width w (m), > 0; it may be smaller than the grid spacing.
    tip : {"flat", "round"}
        ``"flat"``: the slot ends square at ``end``; ``"round"``: a half-disc of radius
        w/2 centred at ``end`` closes it.
    z : (z_min, z_max) or None
        3-D only: the slot's extent along z (m); ``None``: through the whole body.
    """

    start: tuple[float, float]
    end: tuple[float, float]
    width: float
    tip: NotchTip
    z: tuple[float, float] | None

    def __init__(
        self,
        start: ArrayLike,
        end: ArrayLike,
        width: float,
        tip: NotchTip = "flat",
        z: tuple[float, float] | None = None,
    ) -> None:
        a = np.asarray(start, dtype=np.float64)
        b = np.asarray(end, dtype=np.float64)
        if a.shape != (2,) or b.shape != (2,):
            raise ValueError("a notch's start and end are [x, y] (the slot runs along z in 3-D)")
        if not np.all(np.isfinite(a)) or not np.all(np.isfinite(b)):
            raise ValueError("a notch's start and end must be finite")
        if not np.linalg.norm(b - a) > 0:
            raise ValueError("a notch needs two different end points (zero length)")
        if not (np.isfinite(width) and width > 0):
            raise ValueError(f"a notch's width must be > 0 m, got {width}")
        if tip not in ("flat", "round"):
            raise ValueError(f"a notch's tip is 'flat' or 'round', got {tip!r}")
        if z is not None and not float(z[0]) < float(z[1]):
            raise ValueError(f"a notch's z-range needs z_min < z_max, got {list(z)}")
        object.__setattr__(self, "start", (float(a[0]), float(a[1])))
        object.__setattr__(self, "end", (float(b[0]), float(b[1])))
        object.__setattr__(self, "width", float(width))
        object.__setattr__(self, "tip", tip)
        object.__setattr__(self, "z", None if z is None else (float(z[0]), float(z[1])))

    @property
    def length(self) -> float:
        """Length of the centre line ``|end - start|`` (m)."""
        return float(np.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1]))

    @property
    def direction(self) -> NDArray[np.float64]:
        """Unit vector from ``start`` to ``end``, shape (2,)."""
        return (np.asarray(self.end) - np.asarray(self.start)) / self.length

    @property
    def tip_point(self) -> NDArray[np.float64]:
        """The far end of the slot (m), shape (2,): ``end``, or ``end + w/2`` along the
        notch for a round tip."""
        extra = 0.5 * self.width if self.tip == "round" else 0.0
        return np.asarray(self.end) + extra * self.direction

    def region(self) -> Region:
        """The points strictly inside the slot (the ones the notch removes)."""
        return SlotRegion(self)

    def crack(self, z_bounds: tuple[float, float] | None = None) -> Crack:
        """The pre-crack along the centre line, from ``start`` to :attr:`tip_point`.

        2-D (``z_bounds`` ``None``): a segment. 3-D: the rectangle over ``self.z``, or
        over ``z_bounds`` (m, the body's extent along z) when the notch has no z-range.
        """
        a = np.asarray(self.start)
        tip = self.tip_point
        if z_bounds is None and self.z is None:
            return SegmentCrack((float(a[0]), float(a[1])), (float(tip[0]), float(tip[1])))
        z0, z1 = self.z if self.z is not None else z_bounds  # type: ignore[misc]
        d = tip - a
        return RectangleCrack(
            (float(a[0]), float(a[1]), float(z0)),
            (float(d[0]), float(d[1]), 0.0),
            (0.0, 0.0, float(z1) - float(z0)),
        )


@dataclass(frozen=True)
class SlotRegion(Region):
    """The open slot of a :class:`Notch` (2-D, or 3-D with its z-range)."""

    notch: Notch

    def mask(self, x: NDArray[np.float64]) -> BoolArray:
        """Points strictly inside the slot, shape (n_points,)."""
        if x.shape[1] not in (2, 3):
            raise ValueError(f"notches are 2-D or 3-D, got {x.shape[1]}-D points")
        n = self.notch
        t = n.direction
        normal = np.array([-t[1], t[0]])
        rel = x[:, :2] - np.asarray(n.start)
        s = rel @ t
        half = 0.5 * n.width
        tol = 1e-9 * max(n.width, n.length)
        inside = (np.abs(rel @ normal) < half - tol) & (s > tol) & (s < n.length - tol)
        if n.tip == "round":
            inside |= np.sum((x[:, :2] - np.asarray(n.end)) ** 2, axis=1) < (half - tol) ** 2
        if x.shape[1] == 3 and n.z is not None:
            inside &= (x[:, 2] > n.z[0] + tol) & (x[:, 2] < n.z[1] - tol)
        return np.asarray(inside, dtype=bool)
