"""Shared helpers for tests: run the CLI (in this process, or in a subprocess where a
process of its own is the point) against the copy of the package the tests import."""

from __future__ import annotations

import contextlib
import importlib.util
import io
import os
import shutil
import subprocess
import sys
import warnings
from collections.abc import Iterator, Mapping
from pathlib import Path
from types import ModuleType
from typing import Any

import peridynamics

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
#: the directory holding the imported ``peridynamics`` package (the installed copy, or
#: ``src/`` when the tests run with ``PYTHONPATH=src``): subprocesses import the same
#: copy as this process, so a cold run compiles the Numba kernels once
PACKAGE_PARENT = Path(peridynamics.__file__).resolve().parents[1]
#: overrides of the example runs that an example's test and its gallery test share
#: (``example_run`` of ``tests/conftest.py``): the bar at dx = 10 mm, dt = 2 us (101
#: points, the shipped Courant number), the plate at dx = 1 mm (1000 points, explicit and
#: ADR), crack branching at dx = 0.5 mm with delta = 4 dx (16 000 points)
BAR_WAVE = ("discretisation.spacing=0.01", "solver.time_step=2e-6")
PLATE = ("discretisation.spacing=1e-3",)
BRANCHING = ("discretisation.spacing=5e-4", "discretisation.horizon=2e-3", "output.vtk_every=0")
#: the research example (notched plate) at dx = 1 mm, delta = 3 dx (1000 points)
RESEARCH = ("discretisation.spacing=1e-3", "discretisation.horizon_factor=3")
#: the environment variable of the crash injection (the process ends by ``os._exit``)
CRASH = "PERIDYNAMICS_CRASH_AT_STEP"

#: a static 1-D bar of 11 points whose tip displacement a calibration fits (the
#: calibration tests, file and flag forms)
TINY_STATIC_BAR = """\
name: tiny_static_bar
geometry: {type: bar, length: 0.05, area: 1.0e-4}
discretisation: {spacing: 0.005, horizon_factor: 3.0}
material: {youngs_modulus: 20.0e9, density: 2620.0}
node_sets:
  left: {point: [0.0]}
  right: {point: [0.05]}
boundary_conditions:
  - {type: fixed, set: left}
  - {type: traction, set: right, value: [8.0e6]}
solver: {type: static, load_steps: 2}
output:
  history_every: 1
  plot: none
  fields: []
  probes:
    - {name: tip, quantity: displacement, set: right, component: x}
"""


def load_script(path: Path, name: str) -> ModuleType:
    """An example's script (``examples/<folder>/<script>.py``) imported as module ``name``."""
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def mpiexec() -> tuple[str | None, str]:
    """The mpiexec to use (beside this Python first, then on PATH) and, when there is
    none, why (for a skip reason)."""
    try:
        import mpi4py  # noqa: F401
    except ImportError:
        return None, "mpi4py cannot be imported (pip install '.[mpi]')"
    here = Path(sys.executable).parent / "mpiexec"
    found = str(here) if here.is_file() else shutil.which("mpiexec")
    return found, "no mpiexec beside sys.executable or on PATH (pip install '.[mpi]')"


def subprocess_env(extra: Mapping[str, str] | None = None) -> dict[str, str]:
    """This process's environment with the imported package's directory first on
    ``PYTHONPATH`` (and ``extra`` on top)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PACKAGE_PARENT), env.get("PYTHONPATH")]))
    env.update(extra or {})
    return env


@contextlib.contextmanager
def _environment(extra: Mapping[str, str] | None) -> Iterator[None]:
    """``os.environ`` with ``extra`` set, restored afterwards."""
    saved = {k: os.environ.get(k) for k in extra or {}}
    os.environ.update(extra or {})
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


@contextlib.contextmanager
def _numba_threads(n: int) -> Iterator[None]:
    """``n`` Numba threads while the block runs. In this process the count is set, not
    put into ``os.environ``: Numba reads the environment again at every compile and
    refuses a NUMBA_NUM_THREADS other than the one its thread pool started with (a kernel
    compiled after the variable was restored failed so)."""
    import numba

    before = numba.get_num_threads()
    numba.set_num_threads(max(1, min(n, int(numba.config.NUMBA_NUM_THREADS))))
    try:
        yield
    finally:
        numba.set_num_threads(before)


def _in_process(
    args: list[str], env: Mapping[str, str] | None, cwd: Path | None
) -> subprocess.CompletedProcess:
    """``peridynamics.cli.main(args)`` with stdout, stderr and warnings captured as a
    process of its own would show them (a fresh interpreter's warning filters)."""
    from peridynamics.cli import main

    out, err = io.StringIO(), io.StringIO()
    formatwarning = warnings.formatwarning
    env = dict(env or {})
    threads = env.pop("NUMBA_NUM_THREADS", None)
    with contextlib.ExitStack() as stack:
        stack.enter_context(_environment(env))
        if threads is not None:
            stack.enter_context(_numba_threads(int(threads)))
        if cwd is not None:
            stack.enter_context(contextlib.chdir(cwd))
        stack.enter_context(warnings.catch_warnings())
        warnings.resetwarnings()
        warnings.simplefilter("default")
        for quiet in _QUIET_BY_DEFAULT:
            warnings.simplefilter("ignore", quiet)
        warnings.showwarning = _show_on_stderr
        stack.enter_context(contextlib.redirect_stdout(out))
        stack.enter_context(contextlib.redirect_stderr(err))
        try:
            code: object = main(args)
        except SystemExit as exc:  # argparse errors, --help, --version
            code = exc.code
        finally:
            warnings.formatwarning = formatwarning
    if code is None:
        rc = 0
    elif isinstance(code, int):
        rc = code
    else:  # sys.exit("message"): printed on stderr, exit status 1
        err.write(f"{code}\n")
        rc = 1
    return subprocess.CompletedProcess(["peridynamics", *args], rc, out.getvalue(), err.getvalue())


#: the categories a fresh interpreter does not show
_QUIET_BY_DEFAULT = (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning)


def _show_on_stderr(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: object = None,
    line: str | None = None,
) -> None:
    """Print a warning on (the redirected) ``sys.stderr`` as the CLI formats it."""
    sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))


def cli(
    *args: str | Path,
    env: dict[str, str] | None = None,
    timeout: float = 600,
    check: bool = False,
    ranks: int = 1,
    cwd: Path | None = None,
    process: bool = False,
) -> subprocess.CompletedProcess:
    """The command line ``peridynamics ARGS``: in this process (``cli.main``) unless
    ``process`` is true or ``ranks`` > 1 (then ``python -m peridynamics ARGS`` in a
    subprocess, under ``mpiexec -n RANKS`` when ``ranks`` > 1). A subprocess is for what
    needs one: a signal, a kill, ``os._exit`` (the crash injection of
    ``PERIDYNAMICS_CRASH_AT_STEP``, always in a subprocess) or MPI. ``env`` is added to
    the environment (for the in-process call, only while it runs)."""
    argv = [str(a) for a in args]
    if process or ranks > 1 or CRASH in (env or {}):
        launch = [str(mpiexec()[0]), "-n", str(ranks)] if ranks > 1 else []
        proc = subprocess.run(
            [*launch, sys.executable, "-m", "peridynamics", *argv],
            capture_output=True,
            text=True,
            env=subprocess_env(env),
            timeout=timeout,
            cwd=cwd,
        )
    else:
        proc = _in_process(argv, env, cwd)
    if check and proc.returncode != 0:
        raise AssertionError(
            f"exit {proc.returncode}\nstdout:\n{proc.stdout}\nstderr:\n{proc.stderr}"
        )
    return proc


def popen(*args: str) -> subprocess.Popen:
    """Start ``python -m peridynamics ARGS`` in the background (to be signalled or
    killed)."""
    return subprocess.Popen(
        [sys.executable, "-m", "peridynamics", *args],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        env=subprocess_env(),
    )


def same_final_fields(a: Path, b: Path, keys: tuple[str, ...]) -> None:
    """The arrays ``keys`` of ``final_state.npz`` in run folders ``a`` and ``b`` are
    equal bit for bit."""
    import numpy as np

    from peridynamics.io.final_state import read_final_state

    fa, fb = read_final_state(a), read_final_state(b)
    for key in keys:
        assert np.array_equal(fa[key], fb[key]), key  # NaN is not equal to NaN


def sigint_at(sim: object, step: int) -> None:
    """Make ``sim``'s solver deliver a real SIGINT to this process while it computes
    ``step`` (mid-step: the run must still stop only after the step is complete)."""
    import signal

    solver = sim.solver  # type: ignore[attr-defined]
    inner = solver.step

    def step_and_interrupt(state):  # noqa: ANN001, ANN202
        if state.step == step - 1:
            signal.raise_signal(signal.SIGINT)
        return inner(state)

    solver.step = step_and_interrupt


def count_commits(force_model: Any) -> list[int]:
    """Wrap ``force_model.commit_history`` so that every call appends ``int(fresh)`` to
    the returned list (and still commits): how often, and how, a solver committed."""
    calls: list[int] = []
    original = force_model.commit_history

    def counting(state: Any, fresh: bool = False) -> None:
        calls.append(int(fresh))
        original(state, fresh)

    force_model.commit_history = counting
    return calls
