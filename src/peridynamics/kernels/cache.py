"""Where Numba keeps the compiled kernels: a user cache directory, not site-packages.

Every kernel is ``@njit(cache=True)``, compiled on its first call. By default Numba
writes its cache next to the source, into ``__pycache__`` inside site-packages, which
may be read-only (Numba then falls back to its own ``~/.cache/numba``) and which pip
leaves behind on a reinstall, where an entry is checked against its own file only.
:func:`configure`, called by ``peridynamics/__init__.py`` before anything imports
Numba, points ``NUMBA_CACHE_DIR`` at a documented user cache directory instead:

1. ``NUMBA_CACHE_DIR`` when the user has set it (left as it is);
2. else ``$PERIDYNAMICS_CACHE_DIR/numba/<digest>``;
3. else the platform's user cache directory: ``$XDG_CACHE_HOME/peridynamics/numba/
   <digest>`` or ``~/.cache/peridynamics/numba/<digest>`` (Linux and other POSIX),
   ``~/Library/Caches/peridynamics/numba/<digest>`` (macOS),
   ``%LOCALAPPDATA%\\peridynamics\\numba\\<digest>`` (Windows);
4. when that cannot be created or written: ``<tempdir>/peridynamics-<user>/numba/
   <digest>``; when neither can, nothing is set and Numba keeps its own choice.

The directory ends in a digest of the sources of every Numba kernel (the ``.py`` files
of this package folder and :data:`SOURCES`): a kernel inlines the helpers it calls
from other files, and Numba checks only the file of the function it loads, so a cache
shared by versions could hand out a kernel built with an old helper. A reinstall of the
same sources finds the kernels compiled before (Numba 0.68 and later stamp an entry with
a hash of its file's contents; earlier versions with the file's modification time,
which pip renews on every install, so there a reinstall recompiles once); a new version
or an edited kernel compiles afresh into its own folder, and the old folders stay until
the cache is deleted (a few MB each). Setting
``NUMBA_CACHE_DIR`` in ``os.environ`` also moves the cache of any other Numba code run
in this process and its children (their entries stay apart, under their own paths).

Standard library only and no Numba import: it runs on every ``import peridynamics``,
the command line's light start included.
"""

from __future__ import annotations

import hashlib
import os
import sys

#: the environment variables read here
NUMBA_VAR = "NUMBA_CACHE_DIR"
PACKAGE_VAR = "PERIDYNAMICS_CACHE_DIR"

#: Numba code outside this folder (relative to the package), part of the digest
SOURCES = (os.path.join("parallel", "local.py"),)

_PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_digest: str | None = None


def kernel_digest() -> str:
    """16 hex digits of the SHA-256 of every Numba source file of the package (their
    names and contents): the ``.py`` files of ``kernels/`` and :data:`SOURCES`."""
    global _digest
    if _digest is None:
        kernels = os.path.join(_PACKAGE, "kernels")
        names = sorted(
            os.path.join("kernels", e.name) for e in os.scandir(kernels) if e.name.endswith(".py")
        )
        h = hashlib.sha256()
        for name in [*names, *SOURCES]:
            h.update(name.replace(os.sep, "/").encode() + b"\0")
            try:
                with open(os.path.join(_PACKAGE, name), "rb") as f:
                    h.update(f.read())
            except OSError:
                h.update(b"-")
        _digest = h.hexdigest()[:16]
    return _digest


def user_cache_root(
    environ: os._Environ[str] | dict[str, str] | None = None, platform: str | None = None
) -> str:
    """The package's cache directory: ``$PERIDYNAMICS_CACHE_DIR``, else the platform's
    user cache directory with ``peridynamics`` appended (not created here)."""
    env = os.environ if environ is None else environ
    plat = sys.platform if platform is None else platform
    if env.get(PACKAGE_VAR):
        return os.path.expanduser(env[PACKAGE_VAR])
    home = os.path.expanduser("~")
    if plat.startswith("win"):
        base = env.get("LOCALAPPDATA") or os.path.join(home, "AppData", "Local")
    elif plat == "darwin":
        base = os.path.join(home, "Library", "Caches")
    else:
        base = env.get("XDG_CACHE_HOME") or os.path.join(home, ".cache")
    return os.path.join(base, "peridynamics")


def _writable(path: str) -> bool:
    """Whether ``path`` is (made) a directory this process can write to."""
    try:
        os.makedirs(path, exist_ok=True)
    except OSError:
        return False
    return os.path.isdir(path) and os.access(path, os.W_OK | os.X_OK)


def _temp_dir() -> str:
    import getpass
    import tempfile

    try:
        user = getpass.getuser()
    except Exception:  # no user name (a container without passwd entry)
        user = str(os.getuid()) if hasattr(os, "getuid") else "user"
    return os.path.join(tempfile.gettempdir(), f"peridynamics-{user}", "numba")


def numba_cache_dir(environ: os._Environ[str] | dict[str, str] | None = None) -> str | None:
    """The directory for Numba's cache by the rules of the module docstring; ``None``
    when ``NUMBA_CACHE_DIR`` is set by the user or no candidate is writable."""
    env = os.environ if environ is None else environ
    if env.get(NUMBA_VAR):
        return None
    path = os.path.join(user_cache_root(env), "numba", kernel_digest())
    if _writable(path):
        return path
    path = os.path.join(_temp_dir(), kernel_digest())
    return path if _writable(path) else None


def configure(environ: os._Environ[str] | dict[str, str] | None = None) -> str | None:
    """Set ``NUMBA_CACHE_DIR`` (in ``environ``, default ``os.environ``) to
    :func:`numba_cache_dir` unless the user has set it; return the directory Numba will
    use (the user's, the one chosen, or ``None`` for Numba's own default).

    Called before Numba is imported; if it already is, its configuration is reloaded so
    that kernels decorated from now on cache there too."""
    env = os.environ if environ is None else environ
    if env.get(NUMBA_VAR):
        return env[NUMBA_VAR]
    path = numba_cache_dir(env)
    if path is None:
        return None
    env[NUMBA_VAR] = path
    config = sys.modules.get("numba.core.config")
    if config is not None and env is os.environ:
        config.reload_config()  # type: ignore[attr-defined]
    return path
