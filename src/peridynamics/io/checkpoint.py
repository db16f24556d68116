"""Checkpoints you can trust: the solver state plus the observers' records in one .npz
file, with a SHA-256 checksum, written atomically and kept in two generations.

A checkpoint holds ``state_<field>`` for every field of the State, ``records_json``,
``fingerprint``, ``meta_json`` (when given), ``extra_<name>`` (arrays about the State
that are not State fields, when given: the partition of a decomposed run's rank,
:mod:`peridynamics.io.rank_checkpoints`) and ``checksum``: the SHA-256 of the other
arrays (each one's name, dtype, shape and bytes, in sorted name order). Reading checks
the zip, every array header against its size (no pickled data, no array larger than
the file) and the checksum; any failure is a :class:`DamagedCheckpoint` naming the file
and the reason. Before ``checkpoint.npz`` is replaced, the one it holds (when it reads
back intact, belongs to the same deck and holds an earlier step) becomes
``checkpoint.prev.npz``; both steps are ``os.replace`` calls, so at every instant at
least one good checkpoint exists.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

import numpy as np

from peridynamics.state import State

CHECKPOINT_NAME = "checkpoint.npz"
#: the generation before ``checkpoint.npz`` (what ``--resume`` falls back to)
PREVIOUS_NAME = "checkpoint.prev.npz"
#: what the checksum starts from (a new layout of the checksum gets a new tag)
_TAG = b"peridynamics checkpoint sha256 v1"


class DamagedCheckpoint(ValueError):
    """A checkpoint file that cannot be read back as written.

    Parameters
    ----------
    path : Path
        The file.
    reason : str
        Why it cannot be used (a short phrase).
    """

    def __init__(self, path: Path, reason: str) -> None:
        self.path = Path(path)
        self.reason = reason
        super().__init__(f"checkpoint {self.path} is damaged ({reason})")


class CheckpointWarning(UserWarning):
    """A damaged checkpoint was passed over for the previous one."""


class NoUsableCheckpoint(ValueError):
    """No generation of a run's checkpoint can be resumed (the message names each file
    with its reason)."""


@dataclass
class Checkpoint:
    """A checkpoint read back and verified.

    Attributes
    ----------
    path : Path
        The file it was read from.
    state : State
        The solver state.
    records : dict
        The observers' records.
    fingerprint : str
        The fingerprint of the deck that wrote it.
    meta : dict
        The small mapping about the run (``{"finished": true}``; ``{}`` when none).
    extra : dict of str to ndarray
        The ``extra`` arrays it was written with (``{}`` when none).
    """

    path: Path
    state: State
    records: dict[str, Any]
    fingerprint: str
    meta: dict[str, Any]
    extra: dict[str, np.ndarray] = field(default_factory=dict)


def _digest(arrays: dict[str, np.ndarray]) -> np.ndarray:
    """SHA-256 of ``arrays`` but ``checksum`` (names, dtypes, shapes, bytes; sorted
    names) as 32 ``uint8``."""
    h = hashlib.sha256(_TAG)
    for name in sorted(k for k in arrays if k != "checksum"):
        a = np.asarray(arrays[name])
        h.update(json.dumps([name, a.dtype.str, list(a.shape)]).encode())
        h.update(np.ascontiguousarray(a).reshape(-1).view(np.uint8).data)
    return np.frombuffer(h.digest(), dtype=np.uint8)


def _text(value: Any) -> np.ndarray:
    return np.frombuffer(str(value).encode(), dtype=np.uint8)


def _drop_previous(path: Path, fingerprint: str, step: int) -> bool | None:
    """What becomes of the checkpoint ``path`` that a checkpoint of ``step`` replaces:
    ``False`` when it is the previous generation (intact, of ``fingerprint``, of an
    earlier step), ``True`` when it and the previous one are left by another run (of
    another deck, or of a later step), ``None`` when it is missing, damaged or of the
    same step (the previous generation stays)."""
    try:
        ck = load_checkpoint(path)
    except (FileNotFoundError, DamagedCheckpoint):
        return None
    if ck.fingerprint == fingerprint and ck.state.step == step:
        return None
    return ck.fingerprint != fingerprint or ck.state.step > step


def _sync_folder(folder: Path) -> None:
    """fsync a folder so that the renames in it survive a power cut (where a folder can
    be opened: not on Windows)."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def write_checkpoint(
    out_dir: Path,
    state: State,
    records: dict[str, Any],
    fingerprint: str,
    meta: dict[str, Any] | None = None,
    name: str = CHECKPOINT_NAME,
    extra: dict[str, np.ndarray] | None = None,
) -> Path:
    """Write ``out_dir/name`` atomically; its path.

    Every field of the State is stored, whatever the model family declared (history
    fields such as the SED levels included), as ``state_<name>``, with the records, the
    deck fingerprint, ``meta`` (a small JSON mapping, ``{"finished": true}`` on the final
    checkpoint of a run; :func:`read_checkpoint_meta`), the ``extra`` arrays (as
    ``extra_<name>``; ``Checkpoint.extra``) and the checksum. The file is
    written to ``name + ".tmp"``, fsynced and renamed (a crash leaves at most the
    ``.tmp``, which the next run removes).

    For ``checkpoint.npz`` the file it replaces is kept as ``checkpoint.prev.npz`` when
    it reads back intact, was written for the same ``fingerprint`` and holds an earlier
    step. A damaged one, or one of the same step, is replaced and the older
    ``checkpoint.prev.npz`` kept; one of another deck or of a later step was left by
    another run and goes with the ``checkpoint.prev.npz`` beside it (as does a lone
    ``checkpoint.prev.npz`` of another deck or a later step). Other names (the per-rank
    files of :mod:`peridynamics.io.rank_checkpoints`) keep no previous generation here.
    """
    path = out_dir / name
    tmp = out_dir / (name + ".tmp")
    arrays: dict[str, Any] = {f"state_{k}": v for k, v in state.to_arrays().items()}
    arrays["records_json"] = _text(json.dumps(records))
    arrays["fingerprint"] = _text(fingerprint)
    if meta:
        arrays["meta_json"] = _text(json.dumps(meta))
    arrays.update({f"extra_{k}": np.asarray(v) for k, v in (extra or {}).items()})
    arrays["checksum"] = _digest(arrays)
    with open(tmp, "wb") as fh:
        np.savez(fh, **arrays)
        fh.flush()
        os.fsync(fh.fileno())
    drop = None
    if name == CHECKPOINT_NAME and path.exists():
        drop = _drop_previous(path, fingerprint, state.step)
        if drop is False:  # the new one is complete: rotate, then rename
            os.replace(path, out_dir / PREVIOUS_NAME)
    elif name == CHECKPOINT_NAME:  # the first of this run: is a previous one stale?
        drop = _drop_previous(out_dir / PREVIOUS_NAME, fingerprint, state.step) is True
    os.replace(tmp, path)
    if drop:  # left by an earlier run in this folder
        (out_dir / PREVIOUS_NAME).unlink(missing_ok=True)
    _sync_folder(out_dir)
    return path


def _read_member(fh: IO[bytes], size: int, limit: int) -> np.ndarray:
    """One ``.npy`` member of the zip: its header checked against ``size`` (the member's
    bytes) and ``limit`` (the file's bytes) before any data is read; no pickles."""
    version = np.lib.format.read_magic(fh)
    if version == (1, 0):
        shape, fortran, dtype = np.lib.format.read_array_header_1_0(fh)
    elif version == (2, 0):
        shape, fortran, dtype = np.lib.format.read_array_header_2_0(fh)
    else:
        raise ValueError(f"unsupported .npy version {version}")
    if dtype.hasobject:
        raise ValueError("an array holds pickled objects")
    n = math.prod(shape) * dtype.itemsize
    if n > limit or fh.tell() + n != size:
        raise ValueError("an array header does not match its size")
    data = fh.read(n)  # reading to the end checks the zip's CRC-32
    if len(data) != n:
        raise EOFError("an array is cut short")
    return np.frombuffer(data, dtype=dtype).reshape(shape, order="F" if fortran else "C")


def _read_arrays(path: Path) -> dict[str, np.ndarray]:
    """Every array of the ``.npz`` at ``path`` (raises what damaged bytes raise)."""
    limit = path.stat().st_size
    arrays: dict[str, np.ndarray] = {}
    with zipfile.ZipFile(path) as zf:
        for info in zf.infolist():
            key = info.filename.removesuffix(".npy")
            if key == info.filename or key in arrays:
                raise ValueError(f"unexpected member {info.filename!r}")
            with zf.open(info) as fh:
                arrays[key] = _read_member(fh, info.file_size, limit)
    return arrays


def _decode(path: Path, arrays: dict[str, np.ndarray]) -> Checkpoint:
    """The checkpoint held by verified ``arrays``."""
    for key in ("state_t", "state_step", "state_u", "records_json", "fingerprint"):
        arrays[key]  # noqa: B018 - a KeyError names the missing array
    state = State.from_arrays({k[6:]: v for k, v in arrays.items() if k.startswith("state_")})
    records = json.loads(bytes(arrays["records_json"]).decode())
    fingerprint = bytes(arrays["fingerprint"]).decode()
    meta = json.loads(bytes(arrays["meta_json"]).decode()) if "meta_json" in arrays else {}
    if not isinstance(records, dict) or not isinstance(meta, dict):
        raise DamagedCheckpoint(path, "its records are not a mapping")
    extra = {k[6:]: v for k, v in arrays.items() if k.startswith("extra_")}
    return Checkpoint(path, state, records, fingerprint, meta, extra)


def _reason(exc: BaseException) -> str:
    """A one-line reason for a read failure."""
    if isinstance(exc, KeyError):
        return f"missing array {exc}"
    text = " ".join(str(exc).split()) or "no detail"
    return f"{type(exc).__name__}: {text[:200]}"


def load_checkpoint(path: Path) -> Checkpoint:
    """Read and verify the checkpoint file ``path``.

    Raises
    ------
    FileNotFoundError
        When there is no such file.
    DamagedCheckpoint
        When it cannot be read back as written (not a zip, cut short, an array missing
        or of another size than its header says, pickled data, a checksum mismatch).
    """
    # zipfile raises BadZipFile, NotImplementedError (a flag bit), RuntimeError
    # ("encrypted"), OSError, EOFError; numpy's .npy header parser ValueError,
    # SyntaxError or tokenize.TokenError; json and the text UnicodeDecodeError, ...
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no checkpoint {str(path)!r}")
    try:
        arrays = _read_arrays(path)
        if "checksum" not in arrays:
            raise DamagedCheckpoint(path, "no checksum")
        if not np.array_equal(arrays["checksum"], _digest(arrays)):
            raise DamagedCheckpoint(path, "checksum mismatch")
        return _decode(path, arrays)
    except DamagedCheckpoint:
        raise
    except Exception as exc:  # damaged bytes raise many kinds (see above): all mean damaged
        raise DamagedCheckpoint(path, _reason(exc)) from None


def read_checkpoint(
    out_dir: Path, name: str = CHECKPOINT_NAME
) -> tuple[State, dict[str, Any], str]:
    """Read the checkpoint ``name`` in ``out_dir``: (state, records, deck fingerprint).
    Raises FileNotFoundError (no such file) or :class:`DamagedCheckpoint`."""
    path = Path(out_dir) / name
    if not path.exists():
        raise FileNotFoundError(f"no checkpoint in {str(out_dir)!r} (expected {name})")
    ck = load_checkpoint(path)
    return ck.state, ck.records, ck.fingerprint


def read_checkpoint_meta(out_dir: Path, name: str = CHECKPOINT_NAME) -> dict[str, Any]:
    """The ``meta`` mapping of the checkpoint ``name`` in ``out_dir`` (``{}`` if it has
    none). Raises as :func:`read_checkpoint`."""
    return load_checkpoint(Path(out_dir) / name).meta


def read_usable(out_dir: Path) -> tuple[Checkpoint, str | None]:
    """The newest usable checkpoint in ``out_dir`` and, when it is the previous
    generation, why the newest was not used (``"checkpoint ... is damaged (...)"``).

    Raises
    ------
    FileNotFoundError
        When neither ``checkpoint.npz`` nor ``checkpoint.prev.npz`` exists.
    NoUsableCheckpoint
        When none is usable; the message names each file with its reason.
    """
    out = Path(out_dir)
    problems: list[str] = []
    for name in (CHECKPOINT_NAME, PREVIOUS_NAME):
        try:
            ck = load_checkpoint(out / name)
        except FileNotFoundError:
            problems.append(f"checkpoint {out / name} is missing")
            continue
        except DamagedCheckpoint as exc:
            problems.append(str(exc))
            continue
        return ck, problems[0] if problems else None
    if not (out / CHECKPOINT_NAME).exists() and not (out / PREVIOUS_NAME).exists():
        raise FileNotFoundError(f"no checkpoint in {str(out)!r} (expected {CHECKPOINT_NAME})")
    raise NoUsableCheckpoint("; ".join(problems) + f"; no usable checkpoint in {str(out)!r}")
