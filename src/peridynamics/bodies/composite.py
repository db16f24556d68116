"""Several deformable bodies in one model: each body its own force model and damage law.

The points of each body are contiguous (``start:stop``) and bonds join points of one
body only, so the directed CSR bond list of the whole model is the concatenation of
the bodies' lists and every per-point or per-bond array of a body is a *slice* (a view,
no copy) of the model's. :class:`CompositeForceModel` runs each body's force model on
a :func:`part_view` of the State, so any model family (PMB, LPS, correspondence, a
softening bond law) can be mixed, and each body keeps its own surface correction,
pre-pass and history fields. Bonded interfaces between bodies are
:class:`~peridynamics.bodies.interface.InterfaceBonds`: PMB bonds with their own
stiffness and strength, kept in a separate list (State field ``interface_intact``).

Same idea as Peridigm's blocks (one material and damage model per block; Parks et al.
(2012)); the interface bonds are the aggregate-mortar interface of mesoscale concrete
models: bonds across the interface with their own micromodulus and critical stretch.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bodies.composite_damage import CompositeDamageLaw
from peridynamics.bodies.interface import InterfaceBonds
from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import DamageLaw, FieldSpec, ForceModel, FusedStep
from peridynamics.families.pmb.tangent import pmb_tangent
from peridynamics.families.registry import build_force_model
from peridynamics.families.tangent import finite_difference_tangent
from peridynamics.geometry.cloud import PointCloud
from peridynamics.state import State

#: per-point fields every State has (``intact`` is the per-bond one)
CORE_POINT_FIELDS = ("u", "v", "force", "body", "u_prev", "max_stretch")


@dataclass(frozen=True)
class BodyPart:
    """One deformable body of a composite model.

    Attributes
    ----------
    name : str
    start, stop : int
        Its points are ``start:stop`` of the model's.
    material : object with ``force_model(cloud, bonds, surface_correction)`` and
        ``density`` (kg/m^3).
    damage : object with ``law(x, bonds, global_ids)`` (criterion), indices of its
        ``no_fail`` points (if any) local to the body.
    """

    name: str
    start: int
    stop: int
    material: Any
    damage: Any


def sub_cloud(cloud: PointCloud, start: int, stop: int) -> PointCloud:
    """Points ``start:stop`` of ``cloud`` as a cloud of their own (no node sets)."""
    return PointCloud(
        cloud.x[start:stop],
        cloud.volume[start:stop],
        cloud.spacing,
        cloud.cross_section,
        cloud.plane,
        irregular=cloud.irregular,
    )


def sub_bonds(bonds: Bonds, start: int, stop: int) -> Bonds:
    """The bonds of points ``start:stop`` renumbered from 0; raises if one leaves the
    range (bonds must join points of one body)."""
    a, b = int(bonds.offsets[start]), int(bonds.offsets[stop])
    j = bonds.bond_j[a:b]
    if j.size and (int(j.min()) < start or int(j.max()) >= stop):
        raise ValueError(f"bonds of points {start}:{stop} reach outside them")
    return bonds.replace(
        offsets=np.ascontiguousarray(bonds.offsets[start : stop + 1] - a),
        bond_i=np.ascontiguousarray(bonds.bond_i[a:b] - start, dtype=np.int32),
        bond_j=np.ascontiguousarray(j - start, dtype=np.int32),
        bond_xi=bonds.bond_xi[a:b],
        bond_length=bonds.bond_length[a:b],
        bond_volume=bonds.bond_volume[a:b],
        bond_correction=bonds.bond_correction[a:b],
        bond_intact=bonds.bond_intact[a:b],
        x=None if bonds.x is None else bonds.x[start:stop],
        point_volume=None if bonds.point_volume is None else bonds.point_volume[start:stop],
    )


def concat_bonds(parts: Sequence[Bonds], starts: Sequence[int], template: Bonds) -> Bonds:
    """The bond list of the whole model from its bodies' lists (inverse of
    :func:`sub_bonds`)."""
    offsets = [np.zeros(1, dtype=np.int64)]
    shift = 0
    for b in parts:
        offsets.append(b.offsets[1:] + shift)
        shift += b.n_bonds
    return template.replace(
        offsets=np.concatenate(offsets),
        bond_i=np.concatenate([b.bond_i + s for b, s in zip(parts, starts, strict=True)]).astype(
            np.int32
        ),
        bond_j=np.concatenate([b.bond_j + s for b, s in zip(parts, starts, strict=True)]).astype(
            np.int32
        ),
        bond_xi=np.concatenate([b.bond_xi for b in parts]),
        bond_length=np.concatenate([b.bond_length for b in parts]),
        bond_volume=np.concatenate([b.bond_volume for b in parts]),
        bond_correction=np.concatenate([b.bond_correction for b in parts]),
        bond_intact=np.concatenate([b.bond_intact for b in parts]),
    )


def part_view(
    state: State, points: slice, bonds: slice, fields: Sequence[FieldSpec], t_step: State
) -> State:
    """A State whose arrays are views of ``state``'s rows of one body (writes go through).

    ``t_step`` supplies the scalars (time, step)."""
    view = State(t_step.t, t_step.step, 0, t_step.phase)
    for name in CORE_POINT_FIELDS:
        if name in state:
            view[name] = state[name][points]
    view["intact"] = state["intact"][bonds]
    for spec in fields:
        if spec.name in state:
            view[spec.name] = state[spec.name][points if spec.where == "point" else bonds]
    return view


class CompositeForceModel(ForceModel):
    """The force models of several bodies (and their bonded interfaces) as one.

    Parameters
    ----------
    cloud : PointCloud
        All deformable points, each body's contiguous.
    bonds : Bonds
        Bonds within bodies only (none across bodies).
    parts : sequence of BodyPart
        The bodies in point order, covering ``0:n_points``.
    surface_correction : bool
        Passed to every body's force model.
    interfaces : sequence of InterfaceBonds
        Bonded interfaces (their own bond lists, State field ``interface_intact``).
    """

    name = "bodies"

    def __init__(
        self,
        cloud: PointCloud,
        bonds: Bonds,
        parts: Sequence[BodyPart],
        surface_correction: bool = False,
        interfaces: Sequence[InterfaceBonds] = (),
    ) -> None:
        self.cloud = cloud
        self.parts = tuple(parts)
        if not self.parts or self.parts[0].start != 0 or self.parts[-1].stop != cloud.n_points:
            raise ValueError("the bodies must cover the points 0:n_points in order")
        for p, q in zip(self.parts, self.parts[1:], strict=False):
            if p.stop != q.start:
                raise ValueError(f"bodies {p.name!r} and {q.name!r} are not contiguous")
        self.models: list[ForceModel] = []
        for p in self.parts:
            sub = sub_cloud(cloud, p.start, p.stop)
            own = sub_bonds(bonds, p.start, p.stop)
            fm = build_force_model(p.material, p.damage, sub, own, surface_correction)
            if len(fm.dofs()) != 1:
                raise ValueError(
                    f"body {p.name!r}: the {fm.name!r} model has rotational degrees of "
                    "freedom; several bodies need displacement-only models"
                )
            self.models.append(fm)
        self.bonds = concat_bonds(
            [m.bonds for m in self.models], [p.start for p in self.parts], bonds
        )
        self.point_slices = [slice(p.start, p.stop) for p in self.parts]
        off = self.bonds.offsets
        self.bond_slices = [slice(int(off[p.start]), int(off[p.stop])) for p in self.parts]
        self.interfaces = tuple(interfaces)
        #: whether each body's last fused pass counted its broken bonds per point
        self.counted: dict[str, bool] = {}
        self._fields = self._merge_fields()
        self.linear = all(getattr(m, "linear", False) for m in self.models)

    def _merge_fields(self) -> tuple[FieldSpec, ...]:
        seen: dict[str, FieldSpec] = {}
        for p, m in zip(self.parts, self.models, strict=True):
            for spec in m.state_fields():
                other = seen.get(spec.name)
                if other is not None and other != spec:
                    raise ValueError(
                        f"body {p.name!r}: state field {spec.name!r} differs between model "
                        f"families ({other} vs {spec})"
                    )
                seen[spec.name] = spec
        return tuple(seen.values())

    def views(self, state: State) -> list[State]:
        """One :func:`part_view` per body."""
        return [
            part_view(state, ps, bs, m.state_fields(), state)
            for ps, bs, m in zip(self.point_slices, self.bond_slices, self.models, strict=True)
        ]

    # -- ForceModel --------------------------------------------------------------------
    def state_fields(self) -> tuple[FieldSpec, ...]:
        out = list(self._fields)
        if self.interfaces:
            n = sum(f.n_bonds for f in self.interfaces)
            out.append(FieldSpec("interface_intact", "interface", 0, "uint8", True, rows=n))
        return tuple(out)

    def prepass(self, state: State) -> None:
        for m, view in zip(self.models, self.views(state), strict=True):
            m.prepass(view)

    def force(self, state: State) -> None:
        for m, view in zip(self.models, self.views(state), strict=True):
            m.force(view)
        self.add_interface_force(state)

    def fused_step(self, state: State, law: DamageLaw, sed: Any = None) -> FusedStep:
        """Explicit path (:meth:`force_and_commit`); the bonds broken are not counted per
        point (``counted`` False)."""
        assert isinstance(law, CompositeDamageLaw), "several bodies need their composite law"
        return FusedStep(self.force_and_commit(state, law), counted=False)

    def force_and_commit(self, state: State, law: CompositeDamageLaw) -> int:
        """Explicit path: each body's damage committed and its force computed the way a
        single-body model does it (one fused pass where its force model declares one:
        PMB, the softening bond laws), then the interface bonds. Returns the bonds
        broken."""
        broken = 0
        for p, m, part_law, view in zip(
            self.parts, self.models, law.laws, self.views(state), strict=True
        ):
            step = m.fused_step(view, part_law)
            self.counted[p.name] = step is not None and step.counted
            if step is not None:
                broken += step.broken
            else:
                if part_law.active:
                    part_law.trial(view)
                    broken += part_law.commit(view)
                m.prepass(view)
                m.force(view)
        k = 0
        for f in self.interfaces:
            intact = state["interface_intact"][k : k + f.n_bonds]
            f.trial(self.cloud.x, state.u, intact)
            broken += f.commit(intact)
            k += f.n_bonds
        self.add_interface_force(state)
        return broken

    def point_damage(
        self, intact: NDArray[np.uint8], interface_intact: NDArray[np.uint8] | None
    ) -> NDArray[np.float64] | None:
        """Local damage phi_i (n,): the broken share of the partial volumes of all bonds
        of point i, interface bonds included (a debonded inclusion shows as damaged;
        ``interface_intact`` None: as built). None without interfaces (the evaluator's
        damage from ``bonds`` is the same)."""
        if not self.interfaces:
            return None
        if interface_intact is None:
            interface_intact = np.concatenate([f.bonds.bond_intact for f in self.interfaces])
        b = self.bonds
        n = self.n_points
        rows = np.flatnonzero(np.diff(b.offsets) > 0)  # a ghost (MPI) may have no family
        starts = b.offsets[rows]
        total, lost = np.zeros(n), np.zeros(n)
        if rows.size:
            total[rows] = np.add.reduceat(b.bond_volume, starts)
            lost[rows] = np.add.reduceat(b.bond_volume * (intact == 0), starts)
        k = 0
        for f in self.interfaces:
            fb = f.bonds
            total += np.bincount(fb.bond_i, weights=fb.bond_volume, minlength=n)
            if interface_intact is not None:
                broken = interface_intact[k : k + f.n_bonds] == 0
                lost += np.bincount(fb.bond_i, weights=fb.bond_volume * broken, minlength=n)
            k += f.n_bonds
        return np.divide(lost, total, out=np.zeros(n), where=total > 0)

    def init_state(self, state: State) -> None:
        """Interface bonds start as built (pre-cracks cut them too)."""
        k = 0
        for f in self.interfaces:
            state["interface_intact"][k : k + f.n_bonds] = f.bonds.bond_intact
            k += f.n_bonds

    def add_interface_force(self, state: State) -> None:
        """Add the force density (N/m^3) of the interface bonds to ``state.force``."""
        k = 0
        for f in self.interfaces:
            intact = state["interface_intact"][k : k + f.n_bonds]
            f.add_force(self.cloud.x, state.u, intact, state.force, state.max_stretch)
            k += f.n_bonds

    def update_max_stretch(self, state: State, above: float = 0.0) -> None:
        for m, view in zip(self.models, self.views(state), strict=True):
            m.update_max_stretch(view, above)
        k = 0
        for f in self.interfaces:
            intact = state["interface_intact"][k : k + f.n_bonds]
            f.raise_max_stretch(self.cloud.x, state.u, intact, state.max_stretch)
            k += f.n_bonds

    def energy_density(self, state: State) -> NDArray[np.float64]:
        out = np.empty(self.n_points)
        for ps, m, view in zip(self.point_slices, self.models, self.views(state), strict=True):
            out[ps] = m.energy_density(view)
        k = 0
        for f in self.interfaces:
            intact = state["interface_intact"][k : k + f.n_bonds]
            out += f.energy_density(self.cloud.x, state.u, intact)
            k += f.n_bonds
        return out

    def stiffness_bound(self) -> NDArray[np.float64]:
        out = np.concatenate([m.stiffness_bound() for m in self.models])
        for f in self.interfaces:
            out += f.stiffness_bound()
        return out

    def bond_stretch(self, state: State) -> NDArray[np.float64]:
        return np.concatenate(
            [m.bond_stretch(v) for m, v in zip(self.models, self.views(state), strict=True)]
        )

    def tangent(self, state: State) -> sp.csr_matrix | None:
        """Tangent K = -d(V f)/du (N/m): block-diagonal over the bodies (finite
        differences for a body without an analytic one) plus the analytic PMB tangent
        of the interface bonds (:func:`~peridynamics.families.pmb.tangent.pmb_tangent`).
        (A finite-difference tangent of the whole model would colour the points by the
        bodies' bonds only and mix the columns of points joined by interface bonds.)"""
        from types import SimpleNamespace

        blocks = []
        for m, view in zip(self.models, self.views(state), strict=True):
            k = m.tangent(view)
            blocks.append(finite_difference_tangent(m, view) if k is None else k)
        out = sp.csr_matrix(sp.block_diag(blocks, format="csr"))
        k0 = 0
        for f in self.interfaces:
            if f.n_bonds:
                law = SimpleNamespace(
                    bonds=f.bonds, cloud=self.cloud, stiffness=f.stiffness, inv_length=f.inv_length
                )
                at = SimpleNamespace(
                    u=state.u, intact=state["interface_intact"][k0 : k0 + f.n_bonds]
                )
                out = out + pmb_tangent(law, at)  # type: ignore[arg-type]
            k0 += f.n_bonds
        return sp.csr_matrix(out)

    def on_restore(self, state: State) -> None:
        for m, view in zip(self.models, self.views(state), strict=True):
            m.on_restore(view)


@dataclass(frozen=True)
class BodiesMaterial:
    """The materials of several bodies, as the evaluator sees one material.

    ``density`` is per point (kg/m^3, shape (n,)); the scalar properties the extras read
    (``youngs_modulus``, ``micromodulus_constant``: contact stiffness) are the main
    body's."""

    parts: tuple[BodyPart, ...]
    interfaces: tuple[InterfaceBonds, ...] = ()
    #: the deck's main body's material (None: the first part's; a rank of a decomposed
    #: run may hold another body first)
    main_material: Any = None

    @property
    def main(self) -> Any:
        return self.parts[0].material if self.main_material is None else self.main_material

    @property
    def density(self) -> NDArray[np.float64]:
        return np.concatenate(
            [np.full(p.stop - p.start, float(p.material.density)) for p in self.parts]
        )

    @property
    def youngs_modulus(self) -> float:
        return float(self.main.youngs_modulus)

    def micromodulus_constant(
        self, dim: int, horizon: float, cross_section: float, plane: str | None
    ) -> float:
        return float(self.main.micromodulus_constant(dim, horizon, cross_section, plane))

    def force_model(
        self, cloud: PointCloud, bonds: Bonds, surface_correction: bool = False
    ) -> CompositeForceModel:
        return CompositeForceModel(cloud, bonds, self.parts, surface_correction, self.interfaces)
