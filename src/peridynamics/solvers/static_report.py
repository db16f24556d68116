"""The ``summary.json`` entries of a static run
(:meth:`peridynamics.solvers.static.StaticSolver.summary_fields`)."""

from __future__ import annotations

from typing import Any

from peridynamics.state import State

__all__ = ["summary_fields"]


def summary_fields(solver: Any, state: State) -> dict[str, Any]:
    """Solver entries of ``summary.json`` of a static run (``solver``: the
    :class:`~peridynamics.solvers.static.StaticSolver`; typed ``Any`` so that this module
    does not import the solver that imports it).

    Keys: ``solver`` ("static"), ``load_steps``, ``load_factor`` (lambda reached),
    ``solves``, ``newton_iterations``, ``cutbacks``, ``breaking_events``,
    ``breaking_scheme``, ``linear_solver`` (the one used), ``factorizations``,
    ``factorization_s``, ``update_column_solves``, ``time_per_event_s`` (wall time
    per bond-breaking solve), ``reuse_factorization``, ``pinned_points``,
    ``converged`` (the run reached lambda = 1), ``message``, ``time_step_s`` (None).
    """
    st = solver.stats
    events = int(st["events"])
    if solver._failed is not None:
        message = solver._failed
    elif solver.lam >= 1.0 - 1e-12:
        message = "final load reached"
    else:
        message = f"load level {solver.lam:.6g} of 1 reached"
    return {
        "solver": "static",
        "load_steps": solver.load_steps,
        "load_factor": solver.lam,
        "solves": int(st["solves"]),
        "newton_iterations": int(st["newton_iterations"]),
        "cutbacks": int(st["cutbacks"]),
        "breaking_events": events,
        "breaking_scheme": solver.scheme,
        "linear_solver": solver.system.method_used or solver.linear_solver,
        "factorizations": int(st["factorizations"]),
        "factorization_s": float(st["factorization_s"]),
        "update_column_solves": int(st["update_column_solves"]),
        "time_per_event_s": float(st["event_s"] / events) if events else None,
        "reuse_factorization": solver.reuse,
        "pinned_points": int(st["pinned_points"]),
        "first_break_m": None if solver._first_break is None else solver._first_break[0],
        "first_break_load_factor": (
            None if solver._first_break is None else solver._first_break[1]
        ),
        "converged": solver._failed is None and solver.lam >= 1.0 - 1e-12,
        "message": message,
        "time_step_s": None,
    }
