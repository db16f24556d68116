"""Deck section ``solver``: explicit dynamics (with finite-difference and hybrid
variants), adaptive dynamic relaxation, the implicit static solver and heat
conduction (transient and steady); the registry of
solvers (:data:`SOLVER_SCHEMAS`)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Discriminator, Field, Tag, model_validator

from peridynamics.deck.fatigue import fatigue_errors
from peridynamics.deck.types import Errors, NonNegFloat, Num, PosFloat, Strict, tag_of


class Hybrid(Strict):
    """Run a cheap first model until the stretch reaches ``switch_fraction`` x s0, then
    the deck's peridynamic model (Lu & Wang (2016), section 3.3)."""

    first: Literal["fdm", "pd"]
    first_horizon_factor: Annotated[float, Field(ge=1.0, allow_inf_nan=False), Num] = 1.0
    switch_fraction: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False), Num] = 0.9


class Solver(Strict):
    """Explicit dynamics (``type: explicit``, the default)."""

    type: Literal["explicit"] = "explicit"
    method: Literal["pd", "fdm"] = "pd"
    hybrid: Hybrid | None = None
    integrator: Literal["velocity_verlet", "central_difference"] = "velocity_verlet"
    time_step: PosFloat | None = None
    safety_factor: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False), Num] = 0.8
    end_time: PosFloat | None = None
    steps: Annotated[int, Field(gt=0), Num] | None = None
    allow_unstable: bool = False
    blowup_factor: PosFloat = 1.0
    max_stretch: PosFloat = 1.0
    check_every: Annotated[int, Field(gt=0), Num] = 10
    damping: NonNegFloat = 0.0  # mass-proportional damping c_d (1/s); lowers the stable step
    precision: Literal["float64", "float32"] = "float64"
    backend: Literal["numba", "warp"] = "numba"
    device: Literal["auto", "cuda", "cpu"] = "auto"

    @model_validator(mode="after")
    def _length(self) -> Solver:
        if (self.end_time is None) == (self.steps is None):
            raise ValueError("[end_time] give exactly one of end_time (s) or steps")
        if self.method == "fdm" and self.hybrid is not None:
            raise ValueError(
                "[hybrid] a hybrid run switches to the deck's PD model: "
                "use method: pd with hybrid: {first: fdm}"
            )
        return self


def _numba_only(data: Any, solver: str) -> Any:
    """``backend``/``device`` in a static solver's section: ``numba`` is accepted (and
    dropped), anything else is refused with the reason (the Warp backend runs explicit
    dynamics only)."""
    if isinstance(data, dict) and ("backend" in data or "device" in data):
        data = dict(data)
        if data.get("backend", "numba") != "numba" or "device" in data:
            raise ValueError(
                f"[backend] the Warp backend runs explicit dynamics only; solver.type "
                f"{solver} runs on the Numba backend: remove solver.backend / solver.device"
            )
        data.pop("backend", None)
    return data


class ADRSolverSpec(Strict):
    """Adaptive dynamic relaxation to static equilibrium (``type: adr``; Kilic & Madenci
    2010), loads applied in ``load_steps`` proportional steps, damage committed per
    accepted load step."""

    type: Literal["adr"]
    load_steps: Annotated[int, Field(ge=1, le=1_000_000), Num] = 1
    tolerance: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False), Num] = 1e-8
    max_iterations: Annotated[int, Field(ge=1), Num] = 200_000
    proportional: bool = True
    max_damage_rounds: Annotated[int, Field(ge=1), Num] = 50

    @model_validator(mode="before")
    @classmethod
    def _backend(cls, data: Any) -> Any:
        return _numba_only(data, "adr")


class StaticSolverSpec(Strict):
    """Implicit static solver (``type: static``): Newton iterations on the unbalanced
    force with the model's tangent, ``load_steps`` load levels (cut back when Newton
    does not converge), prescribed displacements eliminated, and bond breaking between
    solves (scheme A, B or C of Zhou, Zhu & Li (n.d.)); ``linear_solver`` auto picks a
    direct solver up to 250 000 free dofs and AMG-preconditioned CG above."""

    type: Literal["static"]
    load_steps: Annotated[int, Field(ge=1, le=1_000_000), Num] = 10
    tolerance: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False), Num] = 1e-8
    max_iterations: Annotated[int, Field(ge=1, le=10_000), Num] = 20
    max_cutbacks: Annotated[int, Field(ge=0, le=60), Num] = 6
    proportional: bool = True
    linear_solver: Literal["auto", "direct", "iterative"] = "auto"
    breaking: Literal["A", "B", "C"] = "C"
    bonds_per_event: Annotated[int, Field(ge=1), Num] = 4
    event_driven: bool = True
    reuse_factorization: bool = True
    max_solves: Annotated[int, Field(ge=1), Num] = 1_000_000

    @model_validator(mode="before")
    @classmethod
    def _backend(cls, data: Any) -> Any:
        return _numba_only(data, "static")


class FatigueSolverSpec(Strict):
    """Fatigue by cycle jumping (``type: fatigue``, docs/theory_fatigue.md): static
    equilibria at the peak load (the deck's loads at pseudo-time 1, reached in
    ``load_steps``), between them a jump of N to the next bond whose remaining life is
    spent (``damage.model: fatigue``); cycling between the peak and ``load_ratio`` R
    times it, up to ``max_cycles``. Numba only, one rank."""

    type: Literal["fatigue"]
    load_ratio: Annotated[float, Field(ge=-1, lt=1, allow_inf_nan=False), Num] = 0.0
    max_cycles: PosFloat = 1.0e6
    batch_tolerance: NonNegFloat = 0.0
    max_increment: PosFloat | None = None
    load_steps: Annotated[int, Field(ge=1, le=1_000_000), Num] = 1
    tolerance: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False), Num] = 1e-8
    max_iterations: Annotated[int, Field(ge=1, le=10_000), Num] = 20
    max_cutbacks: Annotated[int, Field(ge=0, le=60), Num] = 6
    linear_solver: Literal["auto", "direct", "iterative"] = "auto"
    max_solves: Annotated[int, Field(ge=1), Num] = 1_000_000

    @model_validator(mode="before")
    @classmethod
    def _backend(cls, data: Any) -> Any:
        return _numba_only(data, "fatigue")


class HeatSolverSpec(Strict):
    """Transient heat conduction by forward Euler (``type: heat``,
    docs/theory_thermal.md): ``time_step`` or ``safety_factor`` times the stable step
    rho c / sum G; ``end_time`` or ``steps``. Numba only (``backend: warp`` is refused)."""

    type: Literal["heat"]
    time_step: PosFloat | None = None
    safety_factor: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False), Num] = 0.9
    end_time: PosFloat | None = None
    steps: Annotated[int, Field(gt=0), Num] | None = None
    allow_unstable: bool = False

    @model_validator(mode="before")
    @classmethod
    def _backend(cls, data: Any) -> Any:
        return _numba_only(data, "heat")

    @model_validator(mode="after")
    def _length(self) -> HeatSolverSpec:
        if (self.end_time is None) == (self.steps is None):
            raise ValueError("[end_time] give exactly one of end_time (s) or steps")
        return self


class SteadyHeatSolverSpec(Strict):
    """The steady temperature by one sparse solve (``type: heat_steady``; the
    conditions' time functions at pseudo-time 1). Numba only."""

    type: Literal["heat_steady"]

    @model_validator(mode="before")
    @classmethod
    def _backend(cls, data: Any) -> Any:
        return _numba_only(data, "heat_steady")


#: the registry of solvers: deck name -> schema of its section
SOLVER_SCHEMAS: dict[str, type[Strict]] = {
    "explicit": Solver,
    "adr": ADRSolverSpec,
    "static": StaticSolverSpec,
    "fatigue": FatigueSolverSpec,
    "heat": HeatSolverSpec,
    "heat_steady": SteadyHeatSolverSpec,
}

AnySolver = Annotated[
    Annotated[Solver, Tag("explicit")]
    | Annotated[ADRSolverSpec, Tag("adr")]
    | Annotated[StaticSolverSpec, Tag("static")]
    | Annotated[FatigueSolverSpec, Tag("fatigue")]
    | Annotated[HeatSolverSpec, Tag("heat")]
    | Annotated[SteadyHeatSolverSpec, Tag("heat_steady")],
    Discriminator(tag_of("explicit", "type")),
]


def solver_errors(deck: Any) -> Errors:
    """Finite differences and hybrids are 1-D; the fatigue solver and law go together."""
    sv = deck.solver
    if deck.dim != 1 and isinstance(sv, Solver) and (sv.method == "fdm" or sv.hybrid is not None):
        return [("solver.method", "finite differences and hybrids are 1-D")]
    return fatigue_errors(deck)
