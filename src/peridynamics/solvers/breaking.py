"""Bond breaking between static solves: which bonds fail at an equilibrium.

Zhou, Zhu & Li (n.d.), section 3.3, compare three schemes of the sequentially linear
kind (Rots et al. 2008; Ni, Zhu, Zhao & Li 2018): after each solve the axial stretch
l of every intact bond is compared with its critical value l_c, and

* scheme ``A`` breaks every violating bond at once,
* scheme ``B`` breaks only the one with the largest l / l_c,
* scheme ``C`` (the paper's choice) breaks the N_b bonds with the largest l / l_c among
  the violating ones (N_b = 4 there),

then the system is solved again at the same load; the load is raised only when a
solve breaks nothing. Bonds are pairs here: breaking the directed bond (i, j) breaks
(j, i) too. The critical value of a bond is (s0_i + s0_j) / 2 of the critical-stretch
law (Weibull fields and no-fail sets included); ``inf`` never breaks.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds

SCHEMES: tuple[str, ...] = ("A", "B", "C")


class PairBreaker:
    """Selects the pairs to break at an equilibrium by scheme A, B or C.

    Parameters
    ----------
    bonds : Bonds
    point_s0 : (n,) critical stretch per point (inf: never breaks).
    scheme : {"A", "B", "C"}
    per_event : int
        N_b of scheme C (>= 1).
    """

    def __init__(
        self, bonds: Bonds, point_s0: NDArray[np.float64], scheme: str = "C", per_event: int = 4
    ) -> None:
        if scheme not in SCHEMES:
            raise ValueError(f"solver.breaking must be one of {SCHEMES}, got {scheme!r}")
        if int(per_event) != per_event or per_event < 1:
            raise ValueError(f"solver.bonds_per_event must be an integer >= 1, got {per_event}")
        self.scheme = scheme
        self.per_event = int(per_event)
        self.reverse = bonds.reverse_index()
        # one directed bond represents each pair; pairs that can never break are left out
        threshold = 0.5 * (point_s0[bonds.bond_i] + point_s0[bonds.bond_j])
        rep = (bonds.bond_i < bonds.bond_j) & np.isfinite(threshold)
        self.candidates = np.flatnonzero(rep)
        self.inv_threshold = 1.0 / threshold[self.candidates]

    @property
    def active(self) -> bool:
        """False when no bond can ever break."""
        return len(self.candidates) > 0

    def pair_ratios(
        self, stretch: NDArray[np.float64], intact: NDArray[np.uint8]
    ) -> NDArray[np.float64]:
        """l / l_c of every candidate pair, 0 for broken ones, shape (n_candidates,);
        ``stretch`` of the candidates only (n_candidates,), ``intact`` of every
        directed bond."""
        c = self.candidates
        return stretch * self.inv_threshold * (intact[c] != 0)

    def pick(self, r: NDArray[np.float64]) -> NDArray[np.int64]:
        """Directed bonds (one per pair) to break now by the scheme, (m,), from the
        candidates' ratios ``r`` (:meth:`pair_ratios`); empty when no intact bond
        reaches its critical stretch."""
        violating = np.flatnonzero(r >= 1.0)
        if len(violating) == 0:
            return violating
        if self.scheme == "A":
            pick = violating
        else:
            n = 1 if self.scheme == "B" else self.per_event
            if len(violating) > n:
                top = np.argpartition(-r[violating], n - 1)[:n]
                pick = violating[top]
            else:
                pick = violating
        return self.candidates[np.sort(pick)]

    @staticmethod
    def factor(r: NDArray[np.float64]) -> float:
        """Factor by which a displacement field proportional to the stretch behind the
        candidates' ratios ``r`` can be scaled before the first intact candidate reaches
        its critical stretch (inf when no candidate is in tension)."""
        peak = float(r.max(initial=0.0))
        return 1.0 / peak if peak > 0 else np.inf

    def both_directions(self, bonds: NDArray[np.int64]) -> NDArray[np.int64]:
        """The directed bonds (i, j) and (j, i) of the pairs ``bonds``."""
        return np.concatenate([bonds, self.reverse[bonds]])
