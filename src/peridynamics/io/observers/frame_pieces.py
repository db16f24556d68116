"""The frames of a decomposed run, written by their ranks: every rank writes the piece of
the points it owns, rank 0 the ``.pvtu`` file that joins them.

Rank 0 runs the frames observer (:class:`~peridynamics.io.observers.frames.VTKFrames`)
like every observer; for a frame it makes one request through the run's session
(:meth:`peridynamics.parallel.session.Session.call`) that every rank serves with
``_write_piece``: the rank computes the frame's point fields
(:func:`frame_fields`) from its own state, with the
point damage of its own bonds, keeps the rows of its owned points (in global id order,
as the gather put them) and writes them as piece ``r`` of the frame
(:func:`~peridynamics.io.pvtu.piece_name`) with the same precision and compression as a
serial frame. The ranks then tell rank 0 whether they wrote it (one small gather: the
pieces exist before the ``.pvtu`` file names them), and rank 0 writes the ``.pvtu``
file. No per-point field of the frame reaches rank 0: the files are those of the
former rank-0 writer, byte for byte.

The ``peak_load`` event frame is kept in memory while the load rises and written later:
every rank keeps its own piece (:func:`hold_frame`, in the session's cache) and writes
it when asked (:func:`write_frame` with ``held``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from peridynamics.io.observers.point_fields import point_fields
from peridynamics.io.options import Output
from peridynamics.io.pvtu import piece_name, pvtu_fields, write_pvtu
from peridynamics.io.vtk import write_vtu
from peridynamics.state import State


def frame_fields(
    output: Output, s: State, damage: NDArray, model: Any = None
) -> dict[str, NDArray]:
    """The point fields of a frame, as chosen by ``output.fields``; those computed from
    the ``model`` (stress, strain, ...:
    :data:`peridynamics.io.observers.point_fields.POINT_FIELDS`) when it is given."""
    fields = output.fields
    data: dict[str, NDArray] = {}
    if "displacement" in fields:
        data["displacement"] = s.u
    if "velocity" in fields:
        data["velocity"] = s.v
    if "damage" in fields:
        data["damage"] = damage
    if "force_density" in fields:
        data["force_density"] = s.force
    if "theta" in s:  # micropolar: point rotation (rad) and moment density (N m/m^3)
        if "rotation" in fields:
            data["rotation"] = s["theta"][:, 0]
        if "moment" in fields:
            data["moment_density"] = s["moment"][:, 0]
    if "temperature" in fields and "T" in s:  # a heat solver's temperature (K)
        data["temperature"] = s["T"]
    if model is not None:
        data.update(point_fields([f for f in fields if f != "temperature"], model, s))
    return data


__all__ = ["frame_fields", "hold_frame", "vtu_compression", "write_frame"]


def vtu_compression(output: Output) -> Literal["zlib"] | None:
    """The compression of a frame file (``output.frame_compression``; None for
    ``"none"``), serial frames and pieces alike."""
    return None if output.frame_compression == "none" else output.frame_compression


def write_frame(session: Any, path: Path, output: Output, held: str | None = None) -> str:
    """Rank 0 of a decomposed run: every rank writes its piece of a frame of the state
    of this step (or the one it holds as ``held``), rank 0 the ``.pvtu`` file.

    Parameters
    ----------
    session : :class:`~peridynamics.parallel.session.Session`
        The run's session (rank 0's; the other ranks serve the request).
    path : Path
        The frame's file name as a serial run names it (``frame_0000010.vtu``); the
        pieces are ``frame_0000010_p0000.vtu``, ... beside it.
    output : Output
        The deck's output options (fields, frame precision and compression).
    held : str, optional
        The key of a piece every rank keeps (:func:`hold_frame`) to write instead of
        the state of this step.

    Returns
    -------
    str
        The name of the ``.pvtu`` file written.

    Raises
    ------
    OSError
        If a rank could not write its piece (the message names the ranks).
    """
    got = session.call("call", _write_piece, str(path), output, held)
    assert got is not None
    return str(got)


def hold_frame(session: Any, key: str, output: Output) -> None:
    """Rank 0 of a decomposed run: every rank keeps its piece of the frame of the state
    of this step under ``key`` (cast to the frame precision), for :func:`write_frame`."""
    session.call("call", _hold_piece, key, output)


# -- every rank ---------------------------------------------------------------------------
def _piece_fields(session: Any, output: Output) -> dict[str, NDArray]:
    """The frame's point fields of this rank's owned points (n_owned, ...)."""
    n = session.comm.n_owned
    data = frame_fields(output, session.state, session.local_damage(), session.model)
    return {k: v[:n] for k, v in data.items()}


def _hold_piece(session: Any, key: str, output: Output) -> None:
    dtype = np.float32 if output.frame_precision == "float32" else np.float64
    data = _piece_fields(session, output)
    session.cache[f"frame:{key}"] = {k: np.array(v, dtype=dtype) for k, v in data.items()}


def _write_piece(session: Any, path: str, output: Output, held: str | None) -> str | None:
    """Every rank: write this rank's piece of the frame ``path``; rank 0 also the
    ``.pvtu`` file once every piece is written (its name; ``None`` on the others)."""
    target = Path(path)
    comm = session.comm
    error = None
    data: dict[str, NDArray] = {}
    try:
        data = session.cache[f"frame:{held}"] if held else _piece_fields(session, output)
        x = session.model.cloud.x[: comm.n_owned]
        write_vtu(target.parent / piece_name(target.name, comm.rank), x, data,
                  precision=output.frame_precision,
                  compression=vtu_compression(output))  # fmt: skip
    except Exception as exc:  # told to rank 0, which raises: no rank waits forever
        error = f"rank {comm.rank}: {type(exc).__name__}: {exc}"
    errors = comm.gather_root(error)
    if errors is None:
        return None
    failed = [e for e in errors if e]
    if failed:
        raise OSError(f"frame {target.name}: pieces not written: {'; '.join(failed)}")
    pieces = [piece_name(target.name, r) for r in range(comm.size)]
    pvtu = target.with_suffix(".pvtu")
    fields = pvtu_fields(data, output.frame_precision)
    write_pvtu(pvtu, pieces, output.frame_precision, fields)
    return pvtu.name
