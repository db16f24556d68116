"""Explicit dynamics on a Warp device (``solver.backend: warp``).

:class:`WarpExplicitSolver` is the :class:`~peridynamics.solvers.explicit.ExplicitSolver`
(same time step, stability limit, run length, checks and messages) with the step done
on the device: the integrator, the kinematic conditions, the body-force loads, the model
family's force pass with its damage law (:mod:`peridynamics.backends.warp_families`),
contact, mass damping and viscosity run as Warp kernels on arrays that stay on the
device. The State the run loop and the observers hold mirrors the device lazily
(:class:`~peridynamics.backends.warp_mirror.MirrorFields`): a field is copied back the
first time it is read after a step, so observers copy back only at their interval. Per
step the host reads one integer (bonds broken); every ``check_every`` steps one more (the
first unsound point).

The set-up (bond list, stiffness, surface correction, first force evaluation) is the
host's; the state at t = 0 is uploaded once.

Under ``mpiexec -n N`` every rank steps its part of the body on its own device
(:func:`~peridynamics.backends.warp_device.pick_device`: rank r takes CUDA device
r mod the devices it sees), the ghost rows of u and v are exchanged before each force
evaluation (:class:`~peridynamics.backends.warp_halo.DeviceHalo`) and the reductions
count the owned points and bonds only (:mod:`peridynamics.backends.warp_halo`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.backends import _warp_step_dsl as k
from peridynamics.backends.warp_device import (
    DeviceModel,
    DeviceState,
    check_device_memory,
    pick_device,
    to_device,
)
from peridynamics.backends.warp_families import device_terms
from peridynamics.backends.warp_halo import (
    decomposed,
    devices_per_rank,
    halo_for,
    mean_shift,
    owned_rows,
)
from peridynamics.backends.warp_mirror import MirrorFields
from peridynamics.loading.conditions import (
    Fixed,
    PrescribedDisplacement,
    PrescribedVelocity,
    _components,
)
from peridynamics.solvers.base import StepResult
from peridynamics.solvers.explicit import ExplicitSolver
from peridynamics.state import State

try:
    from peridynamics.backends._warp_dsl import _damage
except ImportError:  # pragma: no cover - warp-lang absent: importable, not runnable
    _damage = None


@dataclass
class WarpExplicitSolver(ExplicitSolver):
    """:class:`ExplicitSolver` stepping on a Warp device.

    Parameters
    ----------
    device : {"auto", "cuda", "cpu"}
        Warp's CUDA device when there is one (``auto``), else its CPU device; under MPI
        rank r takes CUDA device r mod the number of CUDA devices it sees.
    Other parameters: :class:`~peridynamics.solvers.explicit.ExplicitSolver`.
    """

    device: str = "auto"

    def __post_init__(self) -> None:
        super().__post_init__()
        comm = self.model.comm
        self.device_name = pick_device(self.device, comm.rank)
        #: the device of every rank (a decomposed run), in rank order
        self.devices = devices_per_rank(comm, self.device_name)
        check_device_memory(self.model, self.device_name)
        self.dm = DeviceModel(self.model, self.device_name)
        self.halo = halo_for(self.model, self.dm)  # None when serial
        self._n_own = owned_rows(self.model, self.dm.n)  # the rows reductions count
        self.family, self.extras = device_terms(self.model, self.dm)
        inv = 1.0 / np.asarray(self.model.density, dtype=np.float64)
        self._inv_mass_d = self.dm.upload("inv_mass", inv)
        w = self.dm.wp
        self._total = self.dm.zeros(1, w.int64)
        self._loads = [
            (
                self.dm.upload(f"load{n}_nodes", np.asarray(b.nodes, dtype=np.int32)),
                self.dm.upload(f"load{n}_value", _per_node(b, self.model.dim)),
                b.function,
            )
            for n, b in enumerate(self.model.body_forces)
        ]
        self._kinematic = [
            (c, self.dm.upload(f"bc{n}_nodes", np.asarray(c.nodes, dtype=np.int32)))
            for n, c in enumerate(self.constraints)
        ]
        self._stretch = self.dm.zeros(self.dm.n, w.float64)
        self._shift = self.dm.zeros(self.model.dim, w.float64)
        self._first = self.dm.zeros(1, w.int32)
        self.ds: DeviceState | None = None
        self._damage: Any = None
        self._energy: Any = None
        from peridynamics.backends import warp_energy

        if warp_energy.supports(self.model):
            stiffness = getattr(self.family, "stiffness", None)
            self._energy = warp_energy.DeviceEnergy(self.model, self.dm, stiffness=stiffness)
        self._good: dict[str, Any] | None = None
        self._good_scalars: tuple[float, int, int, int] = (0.0, 0, 0, 0)

    # -- life cycle --------------------------------------------------------------
    def init(self) -> State:
        """The host's state at t = 0 (initial velocities, constraints, forces), uploaded;
        the returned State mirrors the device."""
        s = super().init()
        self._attach(s)
        return s

    def resume(self, state: State) -> None:
        """Continue from a State read from a checkpoint (uploaded to the device)."""
        super().resume(state)
        self._attach(state)

    def _attach(self, s: State) -> None:
        host = dict(s.fields)
        self.ds = DeviceState(self.dm, s)
        sed = self.model.sed_stiffness
        on_read = None if sed is None else (lambda: sed.restore(s))
        s.fields = MirrorFields(host, self.ds, on_read)
        self.family.attach(self.ds)
        self._keep_good(s)

    def describe(self) -> str:
        """dt, stable limit, steps and the device (of every rank under MPI)."""
        if len(self.devices) > 1:
            return f"{super().describe()}, Warp devices {', '.join(self.devices)} (by rank)"
        return f"{super().describe()}, Warp device {self.device_name}"

    def summary_fields(self, state: State) -> dict[str, Any]:
        """Time step, stable limit, backend and device."""
        out = super().summary_fields(state)
        out["backend"] = "warp"
        out["device"] = self.device_name
        if len(self.devices) > 1:
            out["devices_per_rank"] = list(self.devices)
        fields = state.fields
        if isinstance(fields, MirrorFields):
            out["device_to_host_bytes"] = int(fields.copied_bytes)
        return out

    def warm_up(self, d: int) -> None:
        """Nothing to compile on the host for the stepping (Warp compiles on first
        launch, or loads its kernel cache)."""

    # -- one step ------------------------------------------------------------------
    def step(self, s: State) -> StepResult:
        """Advance one step on the device (the order of :meth:`ExplicitSolver.step`)."""
        ds, dm, dt = self.ds, self.dm, self.dt
        assert ds is not None, "init() or resume() first"
        n = dm.n
        t_new = (s.step + 1) * dt
        wdt = dm.wp.float64(dt)
        vv = self.integrator == "velocity_verlet"
        if vv:
            dm.launch(k.kick_drift, n, [ds.u, ds.v, ds.force, ds.body, self._inv_mass_d, wdt])
        else:
            dm.launch(
                k.central_difference,
                n,
                [ds.u, ds.u_prev, ds.v, ds.force, ds.body, self._inv_mass_d, wdt],
            )
        self._constrain(t_new, velocities_only=False)
        if self.halo is not None:  # the ghosts' u and v, as Evaluator.exchange_dofs
            self.halo.exchange(ds)
        self.family.evaluate(ds, True)
        for extra in self.extras:
            extra.add(ds)
        self._loads_at(t_new)
        if self._friction:  # the State's friction work (J), as Evaluator.add_friction_work
            for extra in self.extras:
                power = getattr(extra, "power", None)
                if power is not None:
                    dm.launch(k.add_friction_work, n, [power, wdt, ds.friction_work])
        if vv:
            dm.launch(k.kick, n, [ds.v, ds.force, ds.body, self._inv_mass_d, wdt])
        else:
            dm.launch(
                k.end_of_step_velocity,
                n,
                [ds.u, ds.u_prev, ds.v, ds.force, ds.body, self._inv_mass_d, wdt],
            )
        self._constrain(t_new, velocities_only=True)
        broken = self._broken_count()
        s.bonds_broken += broken
        s.step += 1
        s.t = t_new
        fields = s.fields
        assert isinstance(fields, MirrorFields)
        fields.mark_stale()
        if s.step % self.check_every == 0:
            self.check(s)
        return StepResult(broken=broken)

    def _broken_count(self) -> int:
        if not self.family.breaks:
            return 0
        ds, dm = self.ds, self.dm
        assert ds is not None
        self._total.zero_()  # the owned families' bonds (all points when serial)
        dm.launch(k.count_broken, self._n_own, [ds.broken, self._total])
        return int(self._total.numpy()[0])

    def _loads_at(self, t: float) -> None:
        """Body-force loads at t (host: :meth:`Evaluator.external_force`)."""
        ds, dm = self.ds, self.dm
        assert ds is not None
        if not self._loads:
            return
        ds.body.zero_()
        for nodes, value, function in self._loads:
            dm.launch(k.add_load, len(nodes), [nodes, value, dm.wp.float64(function(t)), ds.body])

    def _constrain(self, t: float, velocities_only: bool) -> None:
        """The kinematic conditions after the drift (positions at t) or after the second
        kick (velocities at t), as :meth:`ExplicitSolver.step`."""
        ds, dm, dt = self.ds, self.dm, self.dt
        assert ds is not None
        f64 = dm.wp.float64
        for c, nodes in self._kinematic:
            m = len(nodes)
            if m == 0:
                continue
            if isinstance(c, PrescribedVelocity):
                if velocities_only:
                    now = c.function(t)
                    for comp, val in _components(c.values, dm.dim, "condition"):
                        dm.launch(k.set_velocity, m, [nodes, comp, f64(val * now), ds.v])
                else:
                    mid, now = c.function(t - 0.5 * dt), c.function(t)
                    for comp, val in _components(c.values, dm.dim, "condition"):
                        dm.launch(
                            k.drive_velocity,
                            m,
                            [nodes, comp, f64(val * mid), f64(val * now), f64(dt), ds.u, ds.v],
                        )
            elif isinstance(c, PrescribedDisplacement):
                f_now, f_old = c.function(t), c.function(t - dt)
                for comp, val in _components(c.values, dm.dim, "condition"):
                    dm.launch(
                        k.set_displacement,
                        m,
                        [
                            nodes,
                            comp,
                            f64(val * f_now),
                            f64(val * (f_now - f_old) / dt),
                            ds.u,
                            ds.v,
                        ],
                    )
            elif isinstance(c, Fixed):
                for comp in c.indices(dm.dim):
                    dm.launch(
                        k.set_displacement,
                        m,
                        [nodes, comp, f64(0.0), f64(0.0), ds.u, ds.v],
                    )

    def point_damage(self, s: State) -> NDArray[np.float64] | None:
        """Local damage (n,) reduced on the device (the bond flags stay there), the
        bits of :meth:`~peridynamics.evaluation.measures.Measures.point_damage` (every
        local row under MPI, as there: callers read the owned ones); None before
        :meth:`init`, and under MPI for a State other than this rank's own (rank 0's
        observers see the whole body, whose damage the ranks reduce through the run's
        session)."""
        ds, dm = self.ds, self.dm
        if ds is None or not self._own_state(s):
            return None
        if self._damage is None:
            self._damage = dm.zeros(dm.n, dm.wp.float64)
        volume = dm.upload("bond_volume", np.asarray(self.model.bonds.bond_volume))
        dm.launch(_damage, dm.n, [dm.offsets, volume, ds.intact, self._damage])
        out: NDArray[np.float64] = self._damage.numpy().copy()
        fields = s.fields
        if isinstance(fields, MirrorFields):
            fields.copied_bytes += out.nbytes
        return out

    def state_energies(self, s: State) -> tuple[float, float] | None:
        """(kinetic, strain) energy (J) with the strain energy density reduced on the
        device (n floats back, not u and the bond flags); the sums are the host's
        (:meth:`~peridynamics.evaluation.measures.Measures.state_energies`). None when the
        family has no device energy, or under MPI for a State other than this rank's
        own; then over the owned points of every rank (collective)."""
        ds = self.ds
        if ds is None or self._energy is None or not self._own_state(s):
            return None
        m = self.model
        w = self._energy.strain_energy_density(ds).numpy()
        fields = s.fields
        if isinstance(fields, MirrorFields):
            fields.copied_bytes += w.nbytes
        own = m.comm.owned  # every row when serial
        strain = m.comm.sum(float(np.sum(w[own] * m.cloud.volume[own])))
        return m.kinetic_energy(s.v), strain

    def _own_state(self, s: State) -> bool:
        """True unless decomposed and ``s`` is not the State this rank steps (its fields
        mirror the device)."""
        return not decomposed(self.model) or isinstance(s.fields, MirrorFields)

    # -- checks --------------------------------------------------------------------
    def check(self, s: State) -> None:
        """The stability check of :meth:`ExplicitSolver.check` on the device: one
        reduction to the host; only an unsound state is copied back (then the host's
        check words the error). Under MPI over the owned points, the verdict agreed by
        every rank (collective)."""
        ds, dm = self.ds, self.dm
        if ds is None:
            super().check(s)
            return
        w, n, comm = dm.wp, self._n_own, self.model.comm
        self._shift.zero_()
        dm.launch(k.sum_columns, n, [ds.u, self._shift])
        self.family.max_stretch(ds, self._stretch)
        self._first.fill_(np.iinfo(np.int32).max)
        limit = w.float64(self._blowup_limit)
        shift = to_device(mean_shift(comm, self._shift.numpy(), n), dm.device)
        dm.launch(
            k.first_bad_point,
            n,
            [ds.u, ds.v, shift, limit, self._stretch, w.float64(self.max_stretch), self._first],
        )
        bad = int(self._first.numpy()[0]) != np.iinfo(np.int32).max
        if comm.size > 1:
            bad = comm.any(bad)
        if bad:
            self.last_good = self._good_state(s)
            super().check(s)  # reads the mirrored fields, raises with the host's message
        self._keep_good(s)

    def _keep_good(self, s: State) -> None:
        """A device copy of the state (the last good one, turned into a host State only
        when the run goes unstable)."""
        ds = self.ds
        assert ds is not None
        w = self.dm.wp
        if self._good is None:
            self._good = {name: w.clone(a) for name, a in ds.fields.items()}
        else:
            for name, a in ds.fields.items():
                w.copy(self._good[name], a)
        self._good_scalars = (s.t, s.step, s.bonds_broken, s.phase)

    def _good_state(self, s: State) -> State:
        assert self._good is not None
        t, step, broken, phase = self._good_scalars
        fields = {name: a.numpy().copy() for name, a in self._good.items()}
        for name, a in s.fields.items():  # host-only fields (none in practice)
            fields.setdefault(name, np.array(a))
        return State(t, step, broken, phase, **fields)


def _per_node(load: Any, dim: int) -> NDArray[np.float64]:
    """A body force's value as one row per node, (len(nodes), dim)."""
    val = load.checked_value(dim)
    return np.ascontiguousarray(np.broadcast_to(val, (len(load.nodes), dim)))
