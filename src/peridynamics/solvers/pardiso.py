"""MKL PARDISO (Schenk & Gärtner 2004) for the static solver's direct factorisation: a
thin ``ctypes`` binding to ``libmkl_rt`` from the ``mkl`` wheel (the optional extra
``pip install peridynamics[pardiso]``; about 0.9 GB installed with its OpenMP and TBB
runtimes, so not a dependency).

:class:`PardisoCholesky` factors a symmetric positive definite matrix (``mtype`` 2,
supernodal Cholesky with a METIS nested-dissection ordering, OpenMP-parallel) and solves
with one or many right-hand sides; the factorisation lives in MKL's memory until
:meth:`PardisoCholesky.free` (or garbage collection). Measured on the paper-size
micropolar L-panel (90 000 dofs, ``benchmarks/static_solvers.py``): factors of 1.1e8
entries against SuperLU's 2.4e8, the factorisation 5x faster, and a block of many
right-hand sides far cheaper per column than SuperLU's (see ``docs/performance.md``).

:func:`available` says whether the library can be loaded; nothing here raises at
import time.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import glob
import os
import site
import sys
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

_LIB: Any = None
_TRIED = False


def _candidates() -> list[str]:
    """Paths of libmkl_rt to try: ``PERIDYNAMICS_MKL_RT``, the linker's search, the
    ``lib`` folders of this environment and of the user site (where the wheel puts it)."""
    out = []
    env = os.environ.get("PERIDYNAMICS_MKL_RT")
    if env:
        out.append(env)
    found = ctypes.util.find_library("mkl_rt")
    if found:
        out.append(found)
    for base in (sys.prefix, getattr(site, "USER_BASE", None) or ""):
        if base:
            out += sorted(glob.glob(os.path.join(base, "lib", "libmkl_rt.so*")), key=len)
    return out


def _library() -> Any:
    """The loaded libmkl_rt, or None."""
    global _LIB, _TRIED
    if _TRIED:
        return _LIB
    _TRIED = True
    for path in _candidates():
        try:
            lib = ctypes.CDLL(path)
            lib.pardiso.restype = None
            lib.pardiso_getdiag.restype = None
        except (OSError, AttributeError):
            continue
        _LIB = lib
        break
    return _LIB


def available() -> bool:
    """True when MKL PARDISO can be loaded (the ``mkl`` wheel or a system MKL)."""
    return _library() is not None


class PardisoError(RuntimeError):
    """PARDISO returned an error code (-4: zero pivot, the matrix is not positive
    definite)."""


_I32 = ctypes.POINTER(ctypes.c_int32)
_F64 = ctypes.POINTER(ctypes.c_double)


class PardisoCholesky:
    """Cholesky factorisation of a symmetric positive definite sparse matrix by PARDISO.

    Parameters
    ----------
    a : sparse (n, n), symmetric positive definite; only its upper triangle is read.

    Attributes
    ----------
    n : int
    fill : int
        Entries of the factor L (PARDISO's count).
    """

    def __init__(self, a: sp.spmatrix) -> None:
        lib = _library()
        if lib is None:
            raise ImportError("MKL PARDISO not found: pip install mkl (or peridynamics[pardiso])")
        self._lib = lib
        up = sp.csr_matrix(sp.triu(a, format="csr"))
        up.sort_indices()
        self.n = int(up.shape[0])
        self._ia = up.indptr.astype(np.int32)
        self._ja = up.indices.astype(np.int32)
        self._a = np.ascontiguousarray(up.data, dtype=np.float64)
        self._pt = np.zeros(64, dtype=np.int64)
        self._perm = np.zeros(self.n, dtype=np.int32)
        iparm = np.zeros(64, dtype=np.int32)
        iparm[0] = 1  # the values below, not MKL's defaults
        iparm[1] = 2  # METIS nested dissection
        iparm[7] = 0  # no iterative refinement: the Newton loop refines
        iparm[9] = 8  # pivot perturbation 1e-8 (not used for mtype 2)
        iparm[10] = 0  # no scaling: the caller scales the matrix by its diagonal
        iparm[12] = 0  # no weighted matching
        iparm[17] = -1  # report the entries of the factor
        iparm[34] = 1  # zero-based indexing
        iparm[55] = 1  # keep the diagonal for pardiso_getdiag
        self._iparm = iparm
        self._factored = False
        self._call(12, np.zeros(self.n), np.zeros(self.n), 1)
        self._factored = True
        self.fill = int(iparm[17])

    def _call(self, phase: int, b: NDArray[np.float64], x: NDArray[np.float64], nrhs: int) -> None:
        err = ctypes.c_int32(0)
        one = ctypes.c_int32(1)
        self._lib.pardiso(
            self._pt.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)),
            ctypes.byref(one), ctypes.byref(one), ctypes.byref(ctypes.c_int32(2)),
            ctypes.byref(ctypes.c_int32(phase)), ctypes.byref(ctypes.c_int32(self.n)),
            self._a.ctypes.data_as(_F64), self._ia.ctypes.data_as(_I32),
            self._ja.ctypes.data_as(_I32), self._perm.ctypes.data_as(_I32),
            ctypes.byref(ctypes.c_int32(nrhs)), self._iparm.ctypes.data_as(_I32),
            ctypes.byref(ctypes.c_int32(0)), b.ctypes.data_as(_F64), x.ctypes.data_as(_F64),
            ctypes.byref(err),
        )  # fmt: skip
        if err.value != 0:
            raise PardisoError(f"PARDISO error {err.value} in phase {phase}")

    def pivots(self) -> NDArray[np.float64]:
        """The pivots d of the factorisation A = L D L^T (in elimination order): a
        pivot many orders below the diagonal it came from means a (numerically)
        singular matrix."""
        df = np.zeros(self.n)
        da = np.zeros(self.n)
        err = ctypes.c_int32(0)
        self._lib.pardiso_getdiag(
            self._pt.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)),
            df.ctypes.data_as(_F64), da.ctypes.data_as(_F64),
            ctypes.byref(ctypes.c_int32(1)), ctypes.byref(err),
        )  # fmt: skip
        if err.value != 0:
            raise PardisoError(f"PARDISO error {err.value} in getdiag")
        return df

    def solve(self, b: NDArray[np.float64]) -> NDArray[np.float64]:
        """A^-1 b for b of shape (n,) or (n, k)."""
        if b.ndim == 1:
            rhs = np.ascontiguousarray(b, dtype=np.float64)
            x = np.empty_like(rhs)
            self._call(33, rhs, x, 1)
            return x
        rhs = np.asfortranarray(b, dtype=np.float64)
        x = np.empty_like(rhs, order="F")
        self._call(33, rhs, x, rhs.shape[1])
        return x

    def free(self) -> None:
        """Release MKL's memory of the factorisation."""
        if self._factored:
            self._factored = False
            try:
                self._call(-1, np.zeros(1), np.zeros(1), 1)
            except PardisoError:  # pragma: no cover - nothing to do at tear-down
                pass

    def __del__(self) -> None:
        try:
            self.free()
        except Exception:  # pragma: no cover - at interpreter shutdown ctypes may be gone
            pass
