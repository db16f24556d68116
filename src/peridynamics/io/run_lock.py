"""An output folder is owned by one run at a time: a lock file held while the run writes.

``DIR/.peridynamics.lock`` names the process that holds the folder (host, process id,
its start time, the command). It is created whole and at once (written to a temporary
file, then hard-linked to its name: the link fails if another run holds the folder),
and removed when the run ends, however it ends short of SIGKILL. A lock left by a run
that was killed is stale: on the same host, when its process no longer exists (or the
process id now belongs to a process started at another time), the next run takes the
folder over and says so. A lock from another host cannot be checked from here: the run
is refused, and the message says how to release the folder.
"""

from __future__ import annotations

import json
import os
import socket
import sys
import time
import warnings
from pathlib import Path
from types import TracebackType
from typing import Any

LOCK_NAME = ".peridynamics.lock"


class FolderLocked(RuntimeError):
    """Another run holds the output folder (the message names it)."""


def _start_ticks(pid: int) -> str | None:
    """The start time of process ``pid`` in clock ticks since boot (Linux
    ``/proc/PID/stat`` field 22), ``None`` where it cannot be read."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = stat[stat.rfind(")") + 2 :].split()  # the name may hold spaces
    return fields[19] if len(fields) > 19 else None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, another user's
        return True
    except OSError:
        return False
    return True


def _holder_alive(info: dict[str, Any]) -> bool | None:
    """Whether the process that wrote ``info`` still runs: ``None`` when it cannot be
    told from here (another host)."""
    if info.get("host") != socket.gethostname():
        return None
    pid = int(info.get("pid", -1))
    if pid <= 0 or not _alive(pid):
        return False
    started = info.get("start_ticks")
    now = _start_ticks(pid)
    return not (started is not None and now is not None and started != now)


def _describe(info: dict[str, Any]) -> str:
    when = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(float(info.get("started", 0))))
    return (
        f"process {info.get('pid', '?')} on {info.get('host', '?')} (started {when}: "
        f"{info.get('command', '?')})"
    )


class RunLock:
    """Hold ``folder`` for this process while the context is open.

    Parameters
    ----------
    folder : Path
        The output folder (created if missing).
    what : str
        The option that named the folder (``--out``, ``--resume``), for messages.

    Raises
    ------
    FolderLocked
        When a live run (or one on another host) holds the folder.
    """

    def __init__(self, folder: Path, what: str = "--out") -> None:
        self.folder = Path(folder)
        self.what = what
        self.path = self.folder / LOCK_NAME
        self.held = False

    def _info(self) -> dict[str, Any]:
        return {
            "host": socket.gethostname(),
            "pid": os.getpid(),
            "start_ticks": _start_ticks(os.getpid()),
            "started": time.time(),
            "command": " ".join(["peridynamics", *sys.argv[1:]])[:300],
        }

    def _try_create(self) -> bool:
        """Create the lock whole (a temporary file hard-linked to its name); ``False``
        when a lock exists."""
        tmp = self.folder / f"{LOCK_NAME}.{os.getpid()}.tmp"
        tmp.write_text(json.dumps(self._info()))
        try:
            os.link(tmp, self.path)
            return True
        except FileExistsError:
            return False
        finally:
            tmp.unlink(missing_ok=True)

    def _read(self) -> dict[str, Any] | None:
        try:
            info = json.loads(self.path.read_text())
        except FileNotFoundError:
            return {}
        except (OSError, ValueError):
            return None
        return info if isinstance(info, dict) else None

    def acquire(self) -> RunLock:
        """Take the folder (see the class)."""
        self.folder.mkdir(parents=True, exist_ok=True)
        for _ in range(3):  # a lock released or taken between the tries: look again
            if self._try_create():
                self.held = True
                return self
            info = self._read()
            if info == {}:
                continue  # released in between
            alive = None if info is None else _holder_alive(info)
            if alive is False or info is None:
                holder = "an unreadable lock" if info is None else _describe(info)
                warnings.warn(
                    f"{self.what} {str(self.folder)!r}: taking over the folder from a run "
                    f"that no longer exists ({holder}); its outputs may be incomplete",
                    stacklevel=2,
                )
                self.path.unlink(missing_ok=True)
                continue
            reason = "is running" if alive else "may still be running (another host)"
            raise FolderLocked(
                f"{self.what} {str(self.folder)!r} is in use: {_describe(info)} {reason}. "
                f"Give another folder with --out, wait for that run to end, or, if it is "
                f"certainly not running, delete {str(self.path)!r}"
            )
        raise FolderLocked(f"{self.what} {str(self.folder)!r}: could not take the folder")

    def release(self) -> None:
        """Give the folder back (only a lock this process holds is removed)."""
        if not self.held:
            return
        self.held = False
        info = self._read()
        if info and info.get("pid") == os.getpid() and info.get("host") == socket.gethostname():
            self.path.unlink(missing_ok=True)

    def __enter__(self) -> RunLock:
        return self.acquire()

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.release()
