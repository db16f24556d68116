"""How a decomposed run talks to its observers: rank 0 runs them, the other ranks serve.

Every rank steps its part of the body. After each step rank 0 runs the observers (the
same code as a serial run) on a :class:`GlobalModel` and a :class:`GlobalState`: views
of the whole body whose per-point fields are gathered from the ranks when an observer
first reads them in that step (``Gatherv`` to rank 0), and whose bond quantities
(damage, energies, bond counts; the crack measures of
:mod:`peridynamics.io.observers.crack_bonds`) are computed by every rank on its own
bonds and reduced. Each request is broadcast by rank 0 (:meth:`Session.call`); the
other ranks wait in :meth:`Session.serve` and answer it until rank 0 ends the step. All
decisions that depend on observer results (stop, events) are taken by rank 0 alone, so
the ranks cannot disagree and no observer needs to know it runs distributed.

Outputs that every rank can write from its own part do so through a ``"call"`` request
instead of a gather: the frames (:mod:`peridynamics.io.observers.frame_pieces`: every
rank writes its piece), the checkpoints and the bond list. Rank 0 counts the requests
it makes and the bytes gathered onto it for each (:meth:`Session.to_root`, reported as
``timing.to_root`` in ``summary.json``: the audit of docs/mpi.md).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bodies.rigid import RIGID_FIELDS
from peridynamics.communicator import SERIAL
from peridynamics.geometry.cloud import PointCloud
from peridynamics.parallel.decompose import find_sorted
from peridynamics.parallel.global_cloud import CloudMeta, GlobalCloud
from peridynamics.parallel.mpi import MPICommunicator
from peridynamics.state import State

#: State fields with one entry per directed bond (not gathered: bonds stay on their rank)
BOND_FIELDS = ("intact", "interface_intact", "bond_kappa")


class BondFlags:
    """Stands for a rank-local per-bond array in the global views (``s.intact``,
    ``model.bonds.bond_intact``): model methods of :class:`GlobalModel` accept it,
    anything else that would index it fails loudly instead of reading wrong bonds."""

    def __init__(self, which: str) -> None:
        self.which = which

    def __repr__(self) -> str:
        return f"BondFlags({self.which!r})"


class Session:
    """The collective side of a decomposed run (one per rank).

    Parameters
    ----------
    comm : the run's :class:`MPICommunicator`.
    model : this rank's model (its part of the body).
    global_cloud : the whole body, when every rank built it, or what every rank knows
        of it (:class:`~peridynamics.parallel.global_cloud.CloudMeta`) when the ranks
        made only their own points: observers then read a
        :class:`~peridynamics.parallel.global_cloud.GlobalCloud`.
    """

    def __init__(
        self, comm: MPICommunicator, model: Any, global_cloud: PointCloud | CloudMeta
    ) -> None:
        self.comm = comm
        self.model = model
        self.global_cloud: PointCloud | GlobalCloud = (
            GlobalCloud(self, global_cloud) if isinstance(global_cloud, CloudMeta) else global_cloud
        )
        self.root = comm.rank == 0
        self.state: State | None = None
        self._handlers: dict[str, Callable[..., Any]] = {
            "gather": self._gather,
            "damage": self._damage,
            "energies": lambda: self.model.state_energies(self._local()),
            "bond_counts": lambda: self.model.bond_counts(self._local()),
            "sed_field": self._sed_field,
            "attr": self._attr,
            "cloud_field": lambda name: self._to_root(getattr(self.model.cloud, name)),
            "node_set": self._node_set,
            "rows": self._rows,
            "max_damage": lambda: self.comm.max(
                float(self.local_damage()[: self.comm.n_owned].max(initial=0.0))
            ),
            "call": self._callable,
        }
        #: what requests keep between steps (the crack meter of the crack outputs)
        self.cache: dict[str, Any] = {}
        #: rank 0: requests made, by label (:func:`request_label`)
        self.requests: dict[str, int] = {}
        #: how the ranks were set up (``how``: windowed or replicated, and the bytes every
        #: rank holds whatever its share), reported in ``summary.json``
        self.set_up: dict[str, Any] = {}

    # -- the protocol --------------------------------------------------------------------
    def call(self, name: str, *args: Any) -> Any:
        """Rank 0: run request ``name`` on every rank; its result (rank 0's part)."""
        self.comm.comm.bcast((name, args), root=0)
        label = request_label(name, args)
        self.requests[label] = self.requests.get(label, 0) + 1
        self.comm.to_root_label = label
        try:
            return self._handlers[name](*args)
        finally:
            self.comm.to_root_label = "other"

    def to_root(self) -> dict[str, dict[str, int]]:
        """Rank 0: what its requests gathered onto it so far, by request label: the
        number of requests and the bytes of the arrays received (the audit of
        ``timing.to_root`` in ``summary.json``)."""
        got = self.comm.to_root_bytes
        return {
            k: {"requests": self.requests.get(k, 0), "bytes": int(got.get(k, 0))}
            for k in sorted(set(self.requests) | set(got))
        }

    def end_step(self, payload: Any = None) -> Any:
        """Rank 0: release the serving ranks; they return ``payload``."""
        return self.comm.comm.bcast(("__end__", payload), root=0)[1]

    def serve(self) -> Any:
        """Ranks > 0: answer rank 0's requests until it ends the step; the payload."""
        while True:
            name, args = self.comm.comm.bcast(None, root=0)
            if name == "__end__":
                return args
            self._handlers[name](*args)

    def _local(self) -> State:
        assert self.state is not None, "the session has no state yet"
        return self.state

    # -- handlers (every rank) ------------------------------------------------------------
    def _to_root(self, field: NDArray) -> NDArray | None:
        return self.comm.gather_points_root(field)

    def _gather(self, name: str) -> NDArray | None:
        return self._to_root(self._local()[name])

    def local_damage(self) -> NDArray:
        """This rank's point damage of its state (local points), computed once per
        step for the requests that read it (the gather of ``damage``, the frames)."""
        s = self._local()
        key = (id(s), s.step, s.t)
        got = self.cache.get("damage")
        if got is None or got[0] != key:
            m = self.model
            got = self.cache["damage"] = (
                key,
                m.point_damage(s.intact, s.fields.get("interface_intact")),
            )
        return got[1]

    def _damage(self, initial: bool) -> NDArray | None:
        m, s = self.model, self._local()
        if not initial:
            return self._to_root(self.local_damage())
        return self._to_root(m.point_damage(m.bonds.bond_intact, s.fields.get("interface_intact")))

    def _sed_field(self, u_global: NDArray) -> NDArray | None:
        """Strain-energy density of a whole-body displacement (every rank got it with
        the request), gathered on rank 0."""
        ids = self.model.cloud.global_ids
        w = self.model.strain_energy_density(
            np.ascontiguousarray(u_global[ids]), self.model.bonds.bond_intact
        )
        return self._to_root(w)

    def _attr(self, name: str) -> NDArray | AttributeError | None:
        """A per-point attribute of the model gathered on rank 0; the AttributeError
        (the same on every rank: the same model) when the model has none."""
        try:
            value = getattr(self.model, name)
        except AttributeError as exc:
            return exc
        return self._to_root(np.asarray(value))

    def _rows(self, what: Any, ids: NDArray[np.int64]) -> NDArray | None:
        """The rows of the points ``ids`` (global, sorted) of a per-point quantity
        (:meth:`peridynamics.io.observers.base.RunContext.rows`: a State field's name,
        ``damage``, ``volume``, ``max_stretch``, or a function of (model, state) giving
        every local point's value), each from its owner, on rank 0 in the order of
        ``ids``."""
        m, s, n = self.model, self._local(), self.comm.n_owned
        owned = np.asarray(m.cloud.global_ids)[:n]
        pos, hit = find_sorted(owned, ids)
        local = pos[hit]
        if what == "damage":
            values = self.local_damage()[local]
        elif what == "volume":
            values = np.asarray(m.cloud.volume)[local]
        elif what == "max_stretch":
            values = np.asarray(m.largest_stretch(s))[local]
        elif callable(what):  # a field computed from (model, state): stress, strain
            values = np.asarray(what(m, s))[local]
        else:
            values = np.asarray(s[what])[local]
        parts = self.comm.gather_root((ids[hit], values))
        if parts is None:
            return None
        got = np.concatenate([p[0] for p in parts])
        rows = np.concatenate([p[1] for p in parts])
        out = np.empty_like(rows)
        out[np.searchsorted(ids, got)] = rows
        return out

    def _node_set(self, name: str) -> NDArray[np.intp] | None:
        """The global ids of a node set's owned members of every rank, sorted, on rank 0."""
        cloud = self.model.cloud
        local = cloud.node_sets[name]
        mine = np.asarray(cloud.global_ids)[local[local < self.comm.n_owned]]
        parts = self.comm.gather_root(mine)
        return None if parts is None else np.sort(np.concatenate(parts))

    def _callable(self, fn: Callable[..., Any], *args: Any) -> Any:
        return fn(self, *args)


def request_label(name: str, args: tuple[Any, ...]) -> str:
    """The label of a request in the gather audit: ``gather:<field>``,
    ``attr:<name>``, ``call:<function>`` or the request's name."""
    if name in ("gather", "attr") and args:
        return f"{name}:{args[0]}"
    if name == "call" and args:
        return f"call:{getattr(args[0], '__name__', type(args[0]).__name__)}"
    return name


class _LazyFields(dict):  # type: ignore[type-arg]
    """Fields of a :class:`GlobalState`: gathered from the ranks on first access."""

    def __init__(self, session: Session, local: State) -> None:
        super().__init__()
        self._session = session
        self._local = local

    def __missing__(self, name: str) -> Any:
        if name not in self._local.fields:
            raise KeyError(name)
        if name in BOND_FIELDS:
            value: Any = BondFlags(name)
        elif name in RIGID_FIELDS:  # every rank holds every rigid body alike
            value = self._local[name]
        elif name == "friction_work":
            value = np.array([self._session.call("call", _friction_sum)])
        else:
            value = self._session.call("gather", name)
        self[name] = value
        return value

    def __contains__(self, name: object) -> bool:
        return name in self._local.fields

    def get(self, name: str, default: Any = None) -> Any:  # type: ignore[override]
        return self[name] if name in self else default

    def keys(self) -> Any:  # type: ignore[override]
        return self._local.fields.keys()

    def __iter__(self) -> Any:
        return iter(self._local.fields)

    def items(self) -> Any:  # type: ignore[override]
        return [(k, self[k]) for k in self._local.fields]


def _largest_stretch(session: Session) -> NDArray | None:
    """Every rank's largest bond stretch per owned point, gathered on rank 0."""
    return session._to_root(session.model.largest_stretch(session._local()))


def _friction_sum(session: Session) -> float:
    s = session._local()
    return session.comm.sum(float(s["friction_work"][0]) if "friction_work" in s else 0.0)


class GlobalState(State):
    """The whole body's State as rank 0's observers see it (fields gathered lazily)."""

    def __init__(self, session: Session, local: State, bonds_broken: int) -> None:
        super().__init__(local.t, local.step, bonds_broken, local.phase)
        self.fields = _LazyFields(session, local)

    def copy(self) -> State:
        """A plain State with every per-point field gathered."""
        return State(
            self.t,
            self.step,
            self.bonds_broken,
            self.phase,
            **{k: np.array(v) for k, v in self.fields.items() if not isinstance(v, BondFlags)},
        )


class _BondsView:
    """What observers read of the bond list: totals over ranks, the horizon."""

    def __init__(self, session: Session, n_bonds: int) -> None:
        local = session.model.bonds
        self.horizon = local.horizon
        self.partial_volume = local.partial_volume
        self.n_bonds = n_bonds
        self.bond_intact = BondFlags("bond_intact")


class GlobalModel:
    """The whole body's model as rank 0's observers see it: the global cloud, serial
    reductions over gathered arrays (``comm`` is serial: the arrays are global), and the
    bond quantities computed by every rank on its own bonds."""

    def __init__(self, session: Session, n_bonds: int) -> None:
        self._session = session
        self._local = session.model
        self.cloud = session.global_cloud
        self.comm = SERIAL
        self.bonds = _BondsView(session, n_bonds)

    def __getattr__(self, name: str) -> Any:  # material, force_model, rigid, ...
        return getattr(self._local, name)

    @property
    def dim(self) -> int:
        return self.cloud.dim

    @property
    def n_points(self) -> int:
        return self.cloud.n_points

    def largest_stretch(self, s: State) -> NDArray[np.float64]:
        """The whole body's largest bond stretch per point (every rank computes its
        own points')."""
        got = self._session.call("call", _largest_stretch)
        assert got is not None
        return np.asarray(got)

    def _point_attr(self, name: str) -> NDArray[np.float64]:
        got = self._session.call("attr", name)
        if isinstance(got, AttributeError):
            raise got
        return got

    @property
    def point_s0(self) -> NDArray[np.float64]:
        return self._point_attr("point_s0")

    @property
    def density(self) -> NDArray[np.float64]:
        return self._point_attr("density")

    def point_damage(self, intact: Any, interface_intact: Any = None) -> NDArray:
        initial = isinstance(intact, BondFlags) and intact.which == "bond_intact"
        return self._session.call("damage", initial)

    def state_energies(self, s: State) -> tuple[float, float]:
        return self._session.call("energies")

    def bond_counts(self, s: State) -> tuple[float, float]:
        """(bonds broken during the run, bonds), every rank's owned bonds."""
        return self._session.call("bond_counts")

    def strain_energy_density(self, u: NDArray, intact: Any) -> NDArray:
        return self._session.call("sed_field", u)

    def section_stress(self, u: NDArray, intact: Any, position: float) -> float:
        raise ValueError("section_stress probes are 1-D; 1-D runs are not decomposed")


def rank_dir(out: Path, rank: int) -> Path:
    """The folder of one rank's own files (checkpoint) inside a run's output folder."""
    return Path(out) / "ranks" / f"rank{rank:04d}"
