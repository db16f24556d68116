"""The limits every history-dependent material of a deck shares (correspondence and LPS
plasticity, viscoelastic LPS): a solver that commits the history, the Numba backend, no
thermal expansion and one body, each refused naming its key."""

from __future__ import annotations

from typing import Any

from peridynamics.deck.types import Errors


def history_errors(deck: Any, key: str, solvers: tuple[str, ...], solver_message: str) -> Errors:
    """Errors of a deck whose ``key`` (``material.plasticity``, ``material.viscoelastic``)
    keeps a history: ``solver.type`` not in ``solvers`` (``solver_message``, formatted
    with ``solver``), another backend, ``thermal.expansion``, ``bodies``."""
    errors: Errors = []
    solver = deck.solver.type
    if solver not in solvers:
        errors.append(("solver.type", solver_message.format(solver=repr(solver))))
    elif getattr(deck.solver, "backend", "numba") != "numba":
        errors.append(("solver.backend", f"{key} runs on the Numba backend only"))
    if getattr(getattr(deck, "thermal", None), "expansion", None) is not None:
        errors.append(("thermal.expansion", f"{key} has no thermal expansion; remove one"))
    if getattr(deck, "bodies", None):
        errors.append(("bodies", f"{key} runs in a single body; remove bodies"))
    return errors
