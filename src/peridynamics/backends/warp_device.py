"""The device side of the Warp backend: a model's constant arrays and the State's fields
as Warp arrays, resident on one Warp device (``"cuda:0"`` or ``"cpu"``).

The seam every device model family implements (:class:`DeviceFamily`): built from the
host :class:`~peridynamics.evaluation.evaluator.Evaluator` (whose arrays are uploaded once, by
name, through
:meth:`DeviceModel.upload`), it overwrites ``ds.force`` with the internal force density
at ``ds.u`` (``ds.v``) and, with ``commit``, first breaks the bonds its damage law
breaks, counting them per point in ``ds.broken``. Extras (viscosity, contact, damping)
add to ``ds.force`` afterwards (:class:`DeviceExtra`). Nothing is copied to the host in
a step except the number of bonds broken.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from peridynamics.backends._warp_dsl import wp

#: Warp dtypes of the NumPy dtypes the backend uploads
_WP_TYPES = {
    np.dtype(np.float64): "float64",
    np.dtype(np.float32): "float32",
    np.dtype(np.int64): "int64",
    np.dtype(np.int32): "int32",
    np.dtype(np.uint8): "uint8",
}


def require_warp() -> Any:
    """The ``warp`` module, initialised; ImportError naming the extra without it."""
    if wp is None:
        raise ImportError(
            "solver.backend: warp needs warp-lang: pip install 'peridynamics[gpu]' "
            "(or set solver.backend: numba)"
        )
    wp.init()
    return wp


def pick_device(requested: str = "auto", rank: int = 0) -> str:
    """The Warp device name of MPI rank ``rank`` (0 in a serial run).

    ``auto`` takes CUDA when Warp finds a CUDA device, else Warp's ``"cpu"``; ``cuda``
    insists on CUDA (ValueError without a CUDA device); ``cpu`` is Warp's CPU device.
    With ``k`` CUDA devices visible, rank r drives ``"cuda:{r % k}"``: one device per
    rank when the ranks of a node are numbered consecutively and as many as its GPUs
    (a serial run gets ``"cuda:0"``); a launcher that gives every rank its own GPU
    (``CUDA_VISIBLE_DEVICES`` per rank) makes ``k`` = 1 and every rank ``"cuda:0"``.
    """
    w = require_warp()
    count = int(w.get_cuda_device_count())
    cuda = f"cuda:{int(rank) % count}" if count > 0 else ""
    if requested == "cpu":
        return "cpu"
    if requested == "cuda":
        if not cuda:
            raise ValueError(
                "solver.device: cuda, but Warp finds no CUDA device on this machine; use "
                "solver.device: cpu (Warp's CPU device) or auto"
            )
        return cuda
    if requested != "auto":
        raise ValueError(f"solver.device must be auto, cuda or cpu, got {requested!r}")
    return cuda or "cpu"


def to_device(host: NDArray, device: str) -> Any:
    """A Warp array holding a copy of ``host`` (C-contiguous; float64, float32, int64,
    int32 or uint8; 1-D or 2-D)."""
    w = require_warp()
    a = np.ascontiguousarray(host)
    dtype = getattr(w, _WP_TYPES[a.dtype])
    return w.array(a, dtype=dtype, device=device)


class DeviceModel:
    """A model's constant arrays on the device.

    Attributes
    ----------
    device : str
        The Warp device.
    n, dim : int
        Points (rows of the State: in a decomposed run this rank's owned points and
        ghosts) and dimension.
    x : wp.array2d(float64) (n, dim), reference positions (m).
    offsets : wp.array(int64) (n + 1,), CSR offsets of the families.
    bond_j : wp.array(int32) (n_bonds,), the other end of each directed bond.
    """

    def __init__(self, model: Any, device: str) -> None:
        self.model = model
        self.device = device
        self.wp = require_warp()
        b = model.bonds
        self.n = int(model.cloud.n_points)
        self.dim = int(model.cloud.dim)
        self.n_bonds = int(b.n_bonds)
        self._arrays: dict[str, Any] = {}
        self.x = self.upload("x", model.cloud.x)
        self.offsets = self.upload("offsets", np.asarray(b.offsets, dtype=np.int64))
        self.bond_j = self.upload("bond_j", np.asarray(b.bond_j, dtype=np.int32))

    def upload(self, name: str, host: NDArray) -> Any:
        """The device copy of ``host`` kept under ``name`` (uploaded on the first call;
        later calls return the kept copy)."""
        got = self._arrays.get(name)
        if got is None:
            got = to_device(host, self.device)
            self._arrays[name] = got
        return got

    def replace(self, name: str, host: NDArray) -> Any:
        """Upload ``host`` again under ``name`` (a constant the host changed)."""
        self._arrays.pop(name, None)
        return self.upload(name, host)

    def zeros(self, shape: int | tuple[int, ...], dtype: Any) -> Any:
        """A zero Warp array on the device."""
        return self.wp.zeros(shape, dtype=dtype, device=self.device)

    def launch(self, kernel: Any, dim: int, inputs: list[Any]) -> None:
        """``wp.launch`` on this device."""
        self.wp.launch(kernel, dim=dim, inputs=inputs, device=self.device)


class DeviceState:
    """The State's fields on the device (the host State mirrors them lazily).

    Attributes
    ----------
    u, v, force, body, u_prev : wp.array2d(float64) (n, dim)
    intact : wp.array(uint8) (n_bonds,)
    broken : wp.array(int64) (n,)
        Bonds broken per point by the last committing evaluation (zeroed by it).
    fields : dict of str -> wp.array
        Further State fields (the force model's, SED levels, ...), by State name.
    """

    CORE = ("u", "v", "force", "body", "u_prev", "intact")

    def __init__(self, dm: DeviceModel, host: Any) -> None:
        self.dm = dm
        self.fields: dict[str, Any] = {}
        for name in host.fields:
            a = np.asarray(host.fields[name])
            if a.dtype in _WP_TYPES and a.ndim in (1, 2):
                self.fields[name] = to_device(a, dm.device)
        self.broken = dm.zeros(dm.n, dm.wp.int64)

    def __getattr__(self, name: str) -> Any:
        try:
            return self.__dict__["fields"][name]
        except KeyError:
            raise AttributeError(name) from None

    def upload(self, host: Any) -> None:
        """Copy every field of the host State to the device (after a resume)."""
        for name, dev in self.fields.items():
            self.dm.wp.copy(dev, to_device(np.asarray(host.fields[name]), self.dm.device))

    def download(self, name: str, out: NDArray) -> None:
        """Copy field ``name`` into the host array ``out`` (same shape and dtype)."""
        out[...] = self.fields[name].numpy()


class DeviceFamily(Protocol):
    """A model family's explicit force evaluation on the device."""

    def evaluate(self, ds: DeviceState, commit: bool) -> None:
        """Overwrite ``ds.force`` (N/m^3) at ``ds.u``; with ``commit`` first break the
        bonds the damage law breaks (per-point counts into ``ds.broken``, which this
        call zeroes first)."""
        ...

    def max_stretch(self, ds: DeviceState, out: Any) -> None:
        """Largest stretch of an intact bond per point into ``out`` (wp float64 (n,))."""
        ...


class DeviceExtra(Protocol):
    """A term added to the force after the family's pass (viscosity, contact, ...)."""

    def add(self, ds: DeviceState) -> None:
        """Add this term's force density to ``ds.force``."""
        ...


#: device bytes per directed bond of a PMB run: neighbour index 4, stiffness 8, flags 1,
#: the last good flags 1, partial volume 8 (damage of outputs); other families add theirs
DEVICE_BYTES_PER_BOND = 22
#: device bytes per point and component: u, v, force, body, u_prev, their last good
#: copies, positions, loads
DEVICE_BYTES_PER_POINT_COMPONENT = 8 * 12


def device_bytes(model: Any) -> int:
    """Estimated device memory of a run (bytes), before anything is allocated."""
    n, d = model.cloud.n_points, model.cloud.dim
    return int(
        model.bonds.n_bonds * DEVICE_BYTES_PER_BOND + n * d * DEVICE_BYTES_PER_POINT_COMPONENT
    )


def check_device_memory(model: Any, device: str) -> None:
    """ValueError naming ``solver.device`` when the model cannot fit the GPU's free
    memory (the CPU device shares the host's memory, which the command line checks)."""
    if not device.startswith("cuda"):
        return
    import warp as wp

    free = getattr(wp.get_device(device), "free_memory", None)
    need = device_bytes(model)
    if free is not None and need > 0.9 * free:
        raise ValueError(
            f"the model needs about {need / 2**30:.1f} GiB on {device} "
            f"({model.bonds.n_bonds:,} directed bonds), {free / 2**30:.1f} GiB are free; "
            "use a coarser discretisation.spacing, or solver.device: cpu / "
            "solver.backend: numba"
        )
