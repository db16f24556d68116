"""The damage of several bodies: each body's own law on its points and bonds, and the
breaking of the bonded interfaces (:mod:`peridynamics.bodies.composite`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from peridynamics.families.base import DamageLaw, ForceModel
from peridynamics.state import State


class CompositeDamageLaw(DamageLaw):
    """The damage laws of several bodies and the breaking of interface bonds.

    ``model`` is the :class:`~peridynamics.bodies.composite.CompositeForceModel` (its
    ``parts``, ``models``, ``interfaces``, ``views`` and ``counted``); ``laws`` one law
    per body, in its order."""

    name = "bodies"

    def __init__(self, model: Any, laws: Sequence[DamageLaw]) -> None:
        self.model = model
        self.laws = tuple(laws)

    @property
    def active(self) -> bool:
        return any(law.active for law in self.laws) or any(
            f.breakable for f in self.model.interfaces
        )

    def bind(self, force_model: ForceModel) -> None:
        """Bind each body's law to its body's force model (laws that read stresses)."""
        for law, m in zip(self.laws, self.model.models, strict=True):
            law.bind(m)

    def trial(self, state: State) -> int:
        n = 0
        for law, view in zip(self.laws, self.model.views(state), strict=True):
            if law.active:
                n += law.trial(view)
        k = 0
        for f in self.model.interfaces:
            n += f.trial(self.model.cloud.x, state.u, state["interface_intact"][k : k + f.n_bonds])
            k += f.n_bonds
        return n

    def commit(self, state: State) -> int:
        n = 0
        for law, view in zip(self.laws, self.model.views(state), strict=True):
            if law.active:
                n += law.commit(view)
        k = 0
        for f in self.model.interfaces:
            n += f.commit(state["interface_intact"][k : k + f.n_bonds])
            k += f.n_bonds
        state.bonds_broken += n
        return n

    def owned_broken(self, n_owned: int) -> int:
        """Bonds of the first ``n_owned`` points (a rank's owned points, the first of its
        first body) that the last trial proposed: each body's law's proposal (a body
        whose force pass broke its bonds counts them per point) and the interfaces'."""
        n = 0
        for law, p, m in zip(self.laws, self.model.parts, self.model.models, strict=True):
            k = min(max(n_owned - p.start, 0), p.stop - p.start)  # owned points of the body
            if k == 0 or not law.active:
                continue
            counts = m.broken_counts if self.model.counted.get(p.name, False) else None
            if counts is not None:
                n += int(counts[:k].sum())
            elif law.proposed is None:
                raise RuntimeError(f"the damage law {law.name!r} cannot count owned bonds")
            else:
                n += int(np.count_nonzero(law.proposed[: int(m.bonds.offsets[k])]))
        for f in self.model.interfaces:
            if f.breakable:
                n += int(np.count_nonzero(f.proposed[: int(f.bonds.offsets[n_owned])]))
        return n


@dataclass(frozen=True)
class BodiesDamage:
    """The damage criteria of several bodies. Their law needs the composite model, so
    the evaluator builds it after the force model (:meth:`law_for`, not ``law``)."""

    parts: tuple[Any, ...]  # BodyPart of peridynamics.bodies.composite

    def law_for(self, model: Any) -> CompositeDamageLaw:
        """One law per body of the composite ``model`` on its own points and bonds
        (random fields drawn by the model-wide point id, the global id on a rank)."""
        laws = []
        gid = model.cloud.global_ids  # a rank's points of a decomposed run
        for p, m in zip(self.parts, model.models, strict=True):
            ids = np.arange(p.start, p.stop, dtype=np.int64)
            if gid is not None:
                ids = gid[p.start : p.stop]
            laws.append(p.damage.law(m.cloud.x, m.bonds, ids))
        return CompositeDamageLaw(model, laws)
