"""Where Numba's cache of compiled kernels goes (:mod:`peridynamics.kernels.cache`):
the user's ``NUMBA_CACHE_DIR`` wins, then ``PERIDYNAMICS_CACHE_DIR``, then the
platform's user cache directory; a temporary directory when that is not writable; a
folder per digest of the kernel sources; set before the kernels import Numba."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from peridynamics.kernels import cache

SRC = Path(cache.__file__).resolve().parents[1]


@pytest.fixture
def env(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> dict[str, str]:
    """An environment without the cache variables, and a private temporary directory."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "tmp"))
    (tmp_path / "tmp").mkdir()
    return {"HOME": str(tmp_path / "home")}


def test_user_numba_cache_dir_is_left_alone(env: dict[str, str], tmp_path: Path) -> None:
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "mine")
    env["PERIDYNAMICS_CACHE_DIR"] = str(tmp_path / "ours")
    assert cache.configure(env) == str(tmp_path / "mine")
    assert env["NUMBA_CACHE_DIR"] == str(tmp_path / "mine")
    assert cache.numba_cache_dir(env) is None
    assert not (tmp_path / "ours").exists()


def test_package_variable_is_used_and_created(env: dict[str, str], tmp_path: Path) -> None:
    env["PERIDYNAMICS_CACHE_DIR"] = str(tmp_path / "ours")
    got = cache.configure(env)
    want = tmp_path / "ours" / "numba" / cache.kernel_digest()
    assert got == str(want) == env["NUMBA_CACHE_DIR"]
    assert want.is_dir()


@pytest.mark.parametrize(
    ("platform", "extra", "base"),
    [
        ("linux", {"XDG_CACHE_HOME": "{t}/xdg"}, "{t}/xdg/peridynamics"),
        ("linux", {}, "{t}/home/.cache/peridynamics"),
        ("darwin", {}, "{t}/home/Library/Caches/peridynamics"),
        ("win32", {"LOCALAPPDATA": "{t}/local"}, "{t}/local/peridynamics"),
    ],
)
def test_platform_user_cache_root(
    env: dict[str, str],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    platform: str,
    extra: dict[str, str],
    base: str,
) -> None:
    monkeypatch.setenv("HOME", env["HOME"])  # what expanduser("~") reads on POSIX
    env.update({k: v.format(t=tmp_path) for k, v in extra.items()})
    got = cache.user_cache_root(env, platform=platform)
    assert Path(got) == Path(base.format(t=tmp_path))


def test_default_is_the_xdg_cache_home(env: dict[str, str], tmp_path: Path) -> None:
    if not sys.platform.startswith("linux"):
        pytest.skip("XDG_CACHE_HOME is the Linux rule")
    env["XDG_CACHE_HOME"] = str(tmp_path / "xdg")
    want = tmp_path / "xdg" / "peridynamics" / "numba" / cache.kernel_digest()
    assert cache.configure(env) == str(want)
    assert want.is_dir()


def test_unwritable_directory_falls_back_to_temp(env: dict[str, str], tmp_path: Path) -> None:
    blocker = tmp_path / "a-file"  # a file where the directory should go: even root fails
    blocker.write_text("")
    env["PERIDYNAMICS_CACHE_DIR"] = str(blocker)
    got = cache.configure(env)
    assert got is not None and got == env["NUMBA_CACHE_DIR"]
    assert Path(got).is_dir()
    assert Path(got).is_relative_to(tmp_path / "tmp")
    assert Path(got).name == cache.kernel_digest()


def test_nothing_writable_leaves_numba_its_default(
    env: dict[str, str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    env["PERIDYNAMICS_CACHE_DIR"] = str(blocker)
    monkeypatch.setattr(tempfile, "tempdir", str(blocker))
    assert cache.configure(env) is None
    assert "NUMBA_CACHE_DIR" not in env


def test_read_only_directory_is_not_writable(tmp_path: Path) -> None:
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        if os.access(ro, os.W_OK):
            pytest.skip("running as a user who may write anywhere (root)")
        assert not cache._writable(str(ro / "numba"))
        assert not cache._writable(str(ro))
    finally:
        ro.chmod(0o700)
    assert cache._writable(str(tmp_path / "rw" / "numba"))


def test_digest_follows_every_kernel_source(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    copy = tmp_path / "pkg"
    shutil.copytree(SRC / "kernels", copy / "kernels", ignore=shutil.ignore_patterns("__pycache__"))
    for name in cache.SOURCES:
        (copy / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(SRC / name, copy / name)
    monkeypatch.setattr(cache, "_PACKAGE", str(copy))
    digests = []
    for edit in [None, "kernels/integrators.py", *cache.SOURCES]:
        if edit is not None:
            with open(copy / edit, "a") as f:
                f.write("\n# edited\n")
        monkeypatch.setattr(cache, "_digest", None)
        digests.append(cache.kernel_digest())
    monkeypatch.setattr(cache, "_digest", None)
    monkeypatch.setattr(cache, "_PACKAGE", str(SRC))
    assert digests[0] == cache.kernel_digest()  # a copy of the same sources: the same
    assert len(set(digests)) == len(digests)  # each edit: a new folder


def test_every_numba_source_is_in_the_digest() -> None:
    kinds = "jit|vectorize|guvectorize|stencil|cfunc"
    compiles = re.compile(rf"\bnjit\b|\bnumba\.({kinds})\b|@({kinds})\b")
    covered = {SRC / name for name in cache.SOURCES}
    missing = [
        str(p.relative_to(SRC))
        for p in SRC.rglob("*.py")
        if compiles.search(p.read_text(encoding="utf-8"))
        and p.parent != SRC / "kernels"
        and p not in covered
    ]
    assert not missing, f"Numba code outside kernels/: add to cache.SOURCES: {missing}"


CHILD = """
import os, sys
{first}
import numpy as np
from peridynamics.kernels.fdm import fdm_force_1d
import numba
fdm_force_1d(np.zeros((3, 1)), 1.0, 1.0, np.zeros((3, 1)), np.zeros(3))
print(numba.config.CACHE_DIR)
"""


@pytest.mark.parametrize("first", ["import peridynamics", "import numba; import peridynamics"])
def test_kernels_cache_into_the_chosen_directory(tmp_path: Path, first: str) -> None:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["PERIDYNAMICS_CACHE_DIR"] = str(tmp_path / "ours")
    proc = subprocess.run(
        [sys.executable, "-c", CHILD.format(first=first)],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    want = tmp_path / "ours" / "numba" / cache.kernel_digest()
    assert proc.stdout.strip() == str(want)
    saved = [p.name for p in want.rglob("*") if p.suffix in (".nbi", ".nbc")]
    assert any(name.startswith("fdm.fdm_force_1d") for name in saved), saved
