"""OpenBLAS's thread count, set for the duration of a block (:func:`blas_threads`).

The static solver's linear algebra (SuperLU's triangular solves, the dense Woodbury
products) calls BLAS many times on small blocks, between Numba force passes. With
OpenBLAS's default of one thread per core, each call wakes its worker threads, which
then spin for a while after the call, competing with Numba's workers (and the
reverse): on a 2-core machine shared with other jobs, a block of SuperLU solves ran
6x slower with two BLAS threads than with one, and the Numba force pass after a BLAS
call 3-4x slower (``docs/performance.md``). :class:`peridynamics.solvers.static.StaticSolver`
therefore runs each solve with one BLAS thread.

The OpenBLAS libraries loaded in the process (NumPy's and SciPy's wheels each bundle
one, with the ``scipy_openblas`` symbol prefix and the ``64_`` suffix of their 64-bit
integer builds; a system OpenBLAS has neither) are found once in
``/proc/self/maps`` (Linux) and driven through ``openblas_set_num_threads`` by
``ctypes``; elsewhere, or with another BLAS (MKL, Accelerate), this does nothing.
"""

from __future__ import annotations

import ctypes
from collections.abc import Callable, Iterator
from contextlib import contextmanager

_Getter = Callable[[], int]
_Setter = Callable[[int], None]

_found: list[tuple[_Getter, _Setter]] | None = None


def _loaded_paths() -> list[str]:
    """Paths of the shared libraries with ``openblas`` in their name mapped into this
    process (empty where ``/proc/self/maps`` does not exist)."""
    paths: set[str] = set()
    try:
        with open("/proc/self/maps") as fh:
            for line in fh:
                parts = line.split(maxsplit=5)
                if len(parts) == 6:
                    path = parts[5].strip()
                    name = path.rsplit("/", 1)[-1].lower()
                    if "openblas" in name and ".so" in name:
                        paths.add(path)
    except OSError:
        return []
    return sorted(paths)


def _controls(path: str) -> tuple[_Getter, _Setter] | None:
    """(get, set) of the thread count of the OpenBLAS at ``path``, or None."""
    try:
        lib = ctypes.CDLL(path)
    except OSError:
        return None
    for prefix in ("scipy_openblas", "openblas"):
        for suffix in ("64_", ""):
            get = getattr(lib, f"{prefix}_get_num_threads{suffix}", None)
            put = getattr(lib, f"{prefix}_set_num_threads{suffix}", None)
            if get is not None and put is not None:
                get.restype = ctypes.c_int
                put.argtypes = [ctypes.c_int]
                put.restype = None
                return get, put
    return None


def openblas_controls() -> list[tuple[_Getter, _Setter]]:
    """(get, set) of every OpenBLAS loaded in the process, found on first use."""
    global _found
    if _found is None:
        found = [c for c in map(_controls, _loaded_paths()) if c is not None]
        _found = found
    return _found


@contextmanager
def blas_threads(n: int) -> Iterator[None]:
    """Run the block with ``n`` OpenBLAS threads (>= 1), then restore the counts.

    Parameters
    ----------
    n : int
        Threads of every loaded OpenBLAS inside the block.
    """
    controls = openblas_controls()
    before = [get() for get, _ in controls]
    for _, put in controls:
        put(n)
    try:
        yield
    finally:
        for (_, put), k in zip(controls, before, strict=True):
            put(k)
