"""Atomic checkpoints: the solver state plus the observers' records in one .npz file."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from peridynamics.state import State

CHECKPOINT_NAME = "checkpoint.npz"


def write_checkpoint(
    out_dir: Path,
    state: State,
    records: dict[str, Any],
    fingerprint: str,
    meta: dict[str, Any] | None = None,
    name: str = CHECKPOINT_NAME,
) -> Path:
    """Write ``out_dir/checkpoint.npz`` atomically (write a temporary file, fsync, then
    rename; a crash leaves at most ``checkpoint.npz.tmp``, which the next run removes).

    Every field of the State is stored, whatever the model family declared (history
    fields such as the SED levels included), as ``state_<name>``. ``meta`` is a small
    JSON mapping about the run (``{"finished": true}`` on the final checkpoint of a
    run); :func:`read_checkpoint_meta` reads it back (``{}`` when absent)."""
    path = out_dir / name
    tmp = out_dir / (name + ".tmp")
    arrays: dict[str, Any] = {f"state_{k}": v for k, v in state.to_arrays().items()}
    arrays["records_json"] = np.frombuffer(json.dumps(records).encode(), dtype=np.uint8)
    arrays["fingerprint"] = np.frombuffer(fingerprint.encode(), dtype=np.uint8)
    if meta:
        arrays["meta_json"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    with open(tmp, "wb") as fh:
        np.savez(fh, **arrays)
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, path)
    return path


def read_checkpoint(
    out_dir: Path, name: str = CHECKPOINT_NAME
) -> tuple[State, dict[str, Any], str]:
    """Read the checkpoint in ``out_dir``: (state, records, deck fingerprint)."""
    path = out_dir / name
    if not path.exists():
        raise FileNotFoundError(f"no checkpoint in {str(out_dir)!r} (expected {name})")
    with np.load(path) as data:
        state = State.from_arrays({k[6:]: data[k] for k in data.files if k.startswith("state_")})
        records = json.loads(bytes(data["records_json"]).decode())
        fingerprint = bytes(data["fingerprint"]).decode()
    return state, records, fingerprint


def read_checkpoint_meta(out_dir: Path) -> dict[str, Any]:
    """The ``meta`` mapping of the checkpoint in ``out_dir`` (``{}`` if it has none)."""
    with np.load(out_dir / CHECKPOINT_NAME) as data:
        if "meta_json" not in data.files:
            return {}
        meta = json.loads(bytes(data["meta_json"]).decode())
    return meta if isinstance(meta, dict) else {}
