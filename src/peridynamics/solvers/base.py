"""The solver seam: every solver has the same small life cycle.

``init() -> State``, ``step(state) -> StepResult``, ``done(state)``,
``summary_fields(state)``; the run loop (:func:`run_solver`, and the runner's loop with
observers) never touches a solver's internals. A "step" is a time step for explicit
dynamics and an accepted load step for dynamic relaxation or static solvers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

from peridynamics.state import State


@dataclass
class StepResult:
    """What one solver step reports.

    Attributes
    ----------
    accepted : bool
        The step was taken (a static solver may reject a load step and cut it).
    converged : bool
        Static solvers: the equilibrium iteration met its tolerance.
    residual : float
        Static solvers: the relative residual norm at the end of the step (NaN for
        explicit dynamics).
    broken : int
        Directed bonds broken in this step.
    iterations : int
        Iterations the step took (1 for explicit dynamics).
    events : tuple of str
        Named events (``"switched"`` when a hybrid hands over).
    """

    accepted: bool = True
    converged: bool = False
    residual: float = float("nan")
    broken: int = 0
    iterations: int = 1
    events: tuple[str, ...] = ()


class Solver(Protocol):
    """What the run loop needs from a solver."""

    model: Any
    last_good: State | None

    def init(self) -> State:
        """The State at the start of the run."""
        ...

    def step(self, state: State) -> StepResult:
        """Advance ``state`` in place by one step."""
        ...

    def done(self, state: State) -> bool:
        """True when the run has reached its end."""
        ...

    def total_steps(self) -> int:
        """Number of steps of the whole run (progress bars)."""
        ...

    def check(self, state: State) -> None:
        """Raise :class:`~peridynamics.solvers.explicit.SimulationUnstable` when the
        state is not sound; else remember it as the last good one."""
        ...

    def resume(self, state: State) -> None:
        """Prepare to continue from ``state`` (read from a checkpoint)."""
        ...

    def summary_fields(self, state: State) -> dict[str, Any]:
        """Solver-specific entries of ``summary.json``'s results."""
        ...

    def describe(self) -> str:
        """One line for the command line (time step and length, or load steps)."""
        ...


def run_solver(solver: Solver, state: State | None = None) -> State:
    """Step ``solver`` until it is done (no observers) and return the final state."""
    s = solver.init() if state is None else state
    while not solver.done(s):
        solver.step(s)
    solver.check(s)
    return s
