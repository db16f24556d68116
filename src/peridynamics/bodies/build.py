"""Assemble the points, bonds and bodies of a deck with ``bodies`` / ``interfaces``.

The order of points is: the main geometry's points that no body claims, then each body
of ``bodies`` in deck order (points carved out of the main geometry by its ``region``,
or the points of its own ``geometry``). Every body's points are therefore contiguous
(:mod:`peridynamics.bodies.composite`). A deck without ``bodies`` keeps the main
geometry's order, so its results are those of a single-body run bit for bit.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bodies.interface import InterfaceBonds, interface_pairs
from peridynamics.bonds.bonds import Bonds
from peridynamics.families.pmb.material import BondBasedMaterial
from peridynamics.geometry.cloud import PointCloud


@dataclass(frozen=True)
class BodyLayout:
    """Where each body's points are.

    Attributes
    ----------
    names : tuple of str
        Body names, ``main`` first.
    starts : (n_bodies + 1,) int
        Body k owns points ``starts[k]:starts[k + 1]``.
    """

    names: tuple[str, ...]
    starts: tuple[int, ...]

    def body_of_points(self) -> NDArray[np.int64]:
        """Body index of every point, shape (n,)."""
        sizes = np.diff(np.asarray(self.starts))
        return np.repeat(np.arange(len(self.names), dtype=np.int64), sizes)

    def range_of(self, k: int) -> tuple[int, int]:
        return self.starts[k], self.starts[k + 1]

    def node_sets(self) -> dict[str, NDArray[np.intp]]:
        """One node set per body (its name)."""
        return {
            name: np.arange(self.starts[k], self.starts[k + 1], dtype=np.intp)
            for k, name in enumerate(self.names)
        }


def assemble_points(
    main: PointCloud,
    bodies: Sequence[Any],
    geometry_cloud: Callable[[Any], PointCloud],
    select: Callable[[PointCloud, Any], NDArray[np.intp]],
) -> tuple[PointCloud, BodyLayout]:
    """The points of all deformable bodies, each body's contiguous.

    Parameters
    ----------
    main : PointCloud
        The deck's geometry; its node sets (those a geometry brings: an image's phases,
        a mesh's groups) are carried over to the new order.
    bodies : sequence of BodySpec
        ``region`` bodies claim points of ``main`` (a later body wins where regions
        overlap); ``geometry`` bodies bring their own points.
    geometry_cloud : callable
        Geometry section -> PointCloud (same spacing as the main one).
    select : callable
        (cloud, region spec) -> indices of the points inside.
    """
    owner = np.zeros(main.n_points, dtype=np.int64)
    extra: list[tuple[int, PointCloud]] = []
    for k, spec in enumerate(bodies, start=1):
        if spec.region is not None:
            owner[select(main, spec.region)] = k
        else:
            cloud = geometry_cloud(spec.geometry)
            if cloud.dim != main.dim or cloud.plane != main.plane:
                raise ValueError(
                    f"bodies.{k - 1}.geometry: a {cloud.dim}-D body in a {main.dim}-D model"
                )
            extra.append((k, cloud))
    xs, vols, starts, names = [], [], [0], ["main"]
    new_index = np.full(main.n_points, -1, dtype=np.intp)  # main's point -> its new index
    for k in range(len(bodies) + 1):
        if k == 0 or bodies[k - 1].region is not None:
            idx = np.flatnonzero(owner == k)
            x, vol = main.x[idx], main.volume[idx]
            new_index[idx] = starts[-1] + np.arange(len(idx))
        else:
            cloud = next(c for kk, c in extra if kk == k)
            x, vol = cloud.x, cloud.volume
        if k:
            names.append(bodies[k - 1].name)
        if len(x) == 0:
            where = "the main geometry" if k == 0 else f"bodies.{k - 1}"
            raise ValueError(
                f"{where}: body {names[-1]!r} has no point (its region claims none, or "
                "the other bodies claim all of it)"
            )
        xs.append(x)
        vols.append(vol)
        starts.append(starts[-1] + len(x))
    cloud = PointCloud(
        np.concatenate(xs),
        np.concatenate(vols),
        main.spacing,
        main.cross_section,
        main.plane,
        irregular=main.irregular or any(c.irregular for _, c in extra),
        node_sets={name: np.sort(new_index[idx]) for name, idx in main.node_sets.items()},
    )
    return cloud, BodyLayout(tuple(names), tuple(starts))


def select_bonds(bonds: Bonds, keep: NDArray[np.bool_]) -> Bonds:
    """The bonds where ``keep`` is true, still in directed CSR order."""
    n = bonds.n_points
    offsets = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(bonds.bond_i[keep], minlength=n), out=offsets[1:])
    return bonds.replace(
        offsets=offsets,
        bond_i=np.ascontiguousarray(bonds.bond_i[keep]),
        bond_j=np.ascontiguousarray(bonds.bond_j[keep]),
        bond_xi=np.ascontiguousarray(bonds.bond_xi[keep]),
        bond_length=np.ascontiguousarray(bonds.bond_length[keep]),
        bond_volume=np.ascontiguousarray(bonds.bond_volume[keep]),
        bond_correction=np.ascontiguousarray(bonds.bond_correction[keep]),
        bond_intact=np.ascontiguousarray(bonds.bond_intact[keep]),
    )


def split_bonds(
    cloud: PointCloud, bonds: Bonds, layout: BodyLayout, n_checked: int | None = None
) -> tuple[Bonds, NDArray[np.int64]]:
    """(bonds within bodies, body index of every point). Raises when a point of some
    body has no bond to its own body (of the first ``n_checked`` points: a rank of a
    decomposed run checks its owned points, not its ghosts)."""
    body = layout.body_of_points()
    within = select_bonds(bonds, body[bonds.bond_i] == body[bonds.bond_j])
    lonely = np.flatnonzero(np.diff(within.offsets)[:n_checked] == 0)
    if lonely.size:
        k = int(lonely[0])
        raise ValueError(
            f"{lonely.size} point(s) have no bond within their own body, e.g. point {k} "
            f"at {cloud.x[k].tolist()} of body {layout.names[body[k]]!r}; make the body "
            "thicker than the grid spacing or increase the horizon"
        )
    return within, body


def interface_micromodulus(material_a: Any, material_b: Any, factor: float) -> BondBasedMaterial:
    """The PMB material of an interface: E_I = factor x 2 E_A E_B / (E_A + E_B) (two
    half-bonds in series), density unused."""
    ea, eb = float(material_a.youngs_modulus), float(material_b.youngs_modulus)
    return BondBasedMaterial(youngs_modulus=factor * 2.0 * ea * eb / (ea + eb), density=1.0)


def build_interfaces(
    specs: Sequence[Any],
    cloud: PointCloud,
    bonds_all: Bonds,
    body: NDArray[np.int64],
    layout: BodyLayout,
    materials: dict[str, Any],
    any_rank: Callable[[bool], bool] = bool,
) -> list[InterfaceBonds]:
    """Bonded interfaces from the deck's ``interfaces`` (``contact`` ones add nothing).

    ``materials`` maps every body's name to its material; ``layout`` holds the bodies
    with points here (a rank of a decomposed run may hold none of a body: its interface
    bonds there are none); ``any_rank`` tells whether a condition holds on any rank."""
    out = []
    seen: set[tuple[str, str]] = set()
    for k, spec in enumerate(specs):
        path = f"interfaces.{k}"
        unknown = [n for n in spec.bodies if n not in materials]
        if unknown:
            raise ValueError(
                f"{path}.bodies: {spec.bodies} names an unknown body; bodies are {list(materials)}"
            )
        pair = (min(spec.bodies), max(spec.bodies))
        if pair in seen:
            raise ValueError(f"{path}.bodies: the interface {spec.bodies} is given twice")
        seen.add(pair)
        if spec.type == "contact":
            continue
        if all(n in layout.names for n in spec.bodies):
            a, b = (layout.names.index(n) for n in spec.bodies)
            mask = interface_pairs(bonds_all, body, a, b)
        else:
            mask = np.zeros(bonds_all.n_bonds, dtype=bool)
        if not any_rank(bool(mask.any())):
            raise ValueError(
                f"{path}: bodies {spec.bodies[0]!r} and {spec.bodies[1]!r} are farther apart "
                "than the horizon: no interface bond; use type 'contact' or move them"
            )
        ma, mb = (materials[n] for n in spec.bodies)
        mat = interface_micromodulus(ma, mb, spec.stiffness_factor)
        c_i = mat.micromodulus_constant(
            cloud.dim, bonds_all.horizon, cloud.cross_section, cloud.plane
        )
        if spec.critical_stretch is not None:
            s_i = float(spec.critical_stretch)
        elif spec.fracture_energy is not None:
            s_i = mat.critical_stretch(
                spec.fracture_energy, cloud.dim, bonds_all.horizon, cloud.cross_section,
                cloud.plane,
            )  # fmt: skip
        else:
            s_i = float("inf")
        out.append(
            InterfaceBonds(
                f"{spec.bodies[0]}/{spec.bodies[1]}", select_bonds(bonds_all, mask), c_i, s_i
            )
        )
    return out
