"""Checks and messages shared by the commands that run decks (``run``, ``check``,
``ensemble``, ``sweep``): loading a deck with its overrides, refusing a model too large
for this machine or a run of absurd length, and the messages of those refusals.

Messages go to stderr; each check returns why it refuses (``None`` when it does not).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path
from typing import Any

from peridynamics.app.exit_codes import EXIT_INVALID
from peridynamics.build.estimates import estimate_size
from peridynamics.deck import DeckError, load_deck
from peridynamics.deck.help import hint

#: bond updates per second assumed for the wall-time estimate (README: 3.5e8 measured)
BOND_UPDATES_PER_S = 3e8
#: more bond updates than this (steps x bonds) is refused without --allow-large
MAX_BOND_UPDATES = 1e15


def err(msg: str) -> None:
    """Print a message to stderr."""
    print(msg, file=sys.stderr, flush=True)


def invalid_deck(exc: Any) -> str:
    """A set-up error (``SetupError``) as a deck error prints: the key path and
    message, then the help topic of its section."""
    return f"invalid deck:\n  {exc}\n{hint([exc.path])}".rstrip()


def load_from_args(args: argparse.Namespace) -> Any:
    """The deck of ``args.deck`` with the overrides ``args.set``, or ``None`` after
    printing why it is invalid."""
    try:
        return load_deck(args.deck, overrides=args.set or [])
    except DeckError as exc:
        err(str(exc))
        return None


def available_memory() -> tuple[float, str]:
    """Bytes of memory a run may use here, and where the figure comes from: the smaller
    of MemAvailable (/proc/meminfo) and the room left under a cgroup limit; else the
    free physical pages (os.sysconf); else 8 GiB, assumed."""
    found: list[tuple[float, str]] = []
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                found.append((float(line.split()[1]) * 1024.0, "MemAvailable"))
    except (OSError, ValueError, IndexError):
        pass
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        used = Path("/sys/fs/cgroup/memory.current").read_text().strip()
        if limit != "max":
            found.append((float(limit) - float(used), "the cgroup memory limit"))
    except (OSError, ValueError):
        pass
    if not found:
        try:
            pages = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
            found.append((float(pages), "free physical memory"))
        except (ValueError, OSError, AttributeError):
            found.append((8.0 * 2**30, "assumed: the available memory could not be read"))
    return min(found)


def human_time(seconds: float) -> str:
    """A duration in the largest unit that fits (years, days, hours, s)."""
    for unit, size in (("years", 3.15e7), ("days", 86400.0), ("hours", 3600.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


def size_problem(
    deck: Any, allow_large: bool, n_points: float | None = None, share: float = 1.0
) -> str | None:
    """Why the model is too large for this machine (``None`` when it fits, when the size
    cannot be estimated yet, or with ``allow_large``). ``share``: the part of the model
    this machine holds (under MPI: its ranks / all ranks)."""
    est = estimate_size(deck, n_points)
    if est is None or allow_large:
        return None
    avail, source = available_memory()
    if est.points >= 2**31 - 1:
        why = "more points than the 32-bit point index holds"
    elif est.bytes * share > avail:
        why = f"more than the {avail / 1e9:.3g} GB available ({source})"
    else:
        return None
    d = deck.discretisation
    points_only = est.BASE_BYTES + est.BYTES_PER_POINT * est.points
    key = "spacing"  # too many points, or a horizon that holds thousands of them:
    if points_only < min(avail, 0.5 * est.bytes) and est.points < 2**31 - 1:
        key = "horizon" if d.horizon is not None else "horizon_factor"
    return (
        f"discretisation.{key}: the model is too large: {est.describe()}, {why}. "
        f"spacing = {d.spacing:g} m, horizon = {d.delta:g} m: check them (a typo in an "
        "exponent?), or pass --allow-large to try anyway"
    )


def work_problem(
    steps: float | None, bonds: float, allow_large: bool, estimated: bool
) -> str | None:
    """Why steps x bonds is beyond any sensible run (``None`` when it is not)."""
    if steps is None or allow_large:
        return None
    work = steps * bonds
    if not work > MAX_BOND_UPDATES:
        return None
    about = "about " if estimated else ""
    return (
        f"solver: {about}{steps:.3g} steps x {bonds:.3g} bonds = {work:.3g} bond updates, "
        f"about {human_time(work / BOND_UPDATES_PER_S)} at {BOND_UPDATES_PER_S:.0e} bond "
        f"updates/s (more than {MAX_BOND_UPDATES:.0e}); check solver.end_time, "
        "solver.time_step and the material's units, or pass --allow-large to run anyway"
    )


def built_problem(sim: Any, allow_large: bool) -> str | None:
    """Checks of a built model: a finite, non-zero time step; a sensible amount of
    work (steps x bonds)."""
    solver = sim.solver
    step = getattr(solver, "stable_step", None)  # damping or viscosity that lowers it
    lowered = step.limited_by() if step is not None else None
    for attr, key in (
        ("stable_time_step", lowered or "material.youngs_modulus"),
        ("dt", "solver.time_step"),
    ):
        value = getattr(solver, attr, None)
        if value is not None and not (math.isfinite(value) and value > 0):
            return (
                f"{key}: the {attr.replace('_', ' ')} is {value:.3g} s, not a finite time > 0; "
                "check material.youngs_modulus (Pa), material.density (kg/m^3), the "
                "discretisation (m), solver.damping (1/s) and material.viscosity"
            )
    from peridynamics.solvers.explicit import ExplicitSolver

    inner = getattr(solver, "second", solver)  # a hybrid: the PD model sets the cost
    inner = getattr(inner, "mechanical", inner)  # thermal expansion: the mechanical solver
    steps = float(solver.total_steps()) if isinstance(inner, ExplicitSolver) else None
    return work_problem(steps, float(sim.model.bonds.n_bonds), allow_large, False)


def build_checked(deck: Any, comm: Any, allow_large: bool) -> tuple[Any, str | None]:
    """Build ``deck`` as ``peridynamics run`` does, between its size checks: the estimate
    before allocating (a mesh's points counted first), then the built model's time step
    and work (:func:`built_problem`). Returns ``(simulation, None)``, or ``(None, why)``
    refused before the build, or ``(simulation, why)`` refused after it. Under MPI
    (``comm`` of several ranks) every rank calls it; the ranks on one machine share its
    memory."""
    from peridynamics.app.run import Simulation
    from peridynamics.build.cloud import build_cloud

    share = 1.0
    if comm is not None:  # the ranks on this machine hold their part of the model
        from peridynamics.parallel.launch import node_ranks

        share = node_ranks(comm) / comm.Get_size()
    problem = size_problem(deck, allow_large, share=share)
    if problem is None and deck.geometry.type in ("mesh", "gmsh"):
        problem = size_problem(deck, allow_large, build_cloud(deck).n_points, share)
    if problem:
        return None, problem
    sim = Simulation.from_deck(deck, comm)
    return sim, built_problem(sim, allow_large)


def refuse(msg: str) -> int:
    """Print ``msg`` as an invalid deck; the exit code of an invalid deck."""
    err(f"invalid deck:\n  {msg}")
    return EXIT_INVALID


def out_of_memory(exc: MemoryError) -> int:
    """Print that the model does not fit in memory; the exit code of an invalid deck."""
    err(
        f"error: out of memory ({exc or 'MemoryError'}): the model is too large for this "
        "machine; use a coarser discretisation.spacing or a smaller horizon"
    )
    return EXIT_INVALID
