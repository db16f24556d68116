"""A deck turned into the objects of a run: :class:`SimulationSetup`.

``SimulationSetup.from_deck(deck)`` builds geometry -> bonds -> model -> solver (one
rank's part of the body under MPI); the run loop
(:class:`peridynamics.app.run.Simulation`) steps what it built.
"""

from __future__ import annotations

import hashlib
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Self

from peridynamics import deck as dk
from peridynamics.build.bodies import attach_rigid_bodies, build_deck_model
from peridynamics.build.cloud import build_bonds_for, build_cloud
from peridynamics.build.errors import SetupError
from peridynamics.build.loads import build_conditions
from peridynamics.build.solvers import build_solver
from peridynamics.deck.thermal_coupling import coupling_of
from peridynamics.evaluation import Evaluator
from peridynamics.families.registry import MATERIALS
from peridynamics.geometry import PointCloud
from peridynamics.solvers.base import Solver
from peridynamics.solvers.fdm import FDMModel1D


@dataclass
class SimulationSetup:
    """A deck turned into objects, ready to run."""

    deck: dk.Deck
    cloud: PointCloud
    model: Evaluator
    solver: Solver
    setup_s: float = 0.0
    #: a decomposed run (``mpiexec -n N``): the collective side (None when serial)
    session: Any = None
    #: a decomposed run: the whole body (``cloud`` is this rank's part); a
    #: :class:`~peridynamics.parallel.global_cloud.GlobalCloud` view when no rank made it
    global_cloud: Any = None

    @classmethod
    def from_deck(cls, deck: dk.Deck, comm: Any = None) -> Self:
        """Build geometry -> bonds -> model -> solver. Raises SetupError / DeckError.

        ``comm``: an mpi4py communicator of more than one rank decomposes the body over
        its ranks (:mod:`peridynamics.parallel`); every rank calls this."""
        t0 = time.perf_counter()
        if comm is not None and comm.Get_size() > 1:
            if deck.solver.type in ("heat", "heat_steady"):
                raise SetupError(
                    "solver.type",
                    f"{deck.solver.type} runs in one process; run it without mpiexec",
                )
            if coupling_of(deck) is not None:
                raise SetupError(
                    "thermal.expansion",
                    "thermal expansion runs in one process; run it without mpiexec",
                )
            from peridynamics.build.decomposed import build_distributed
            from peridynamics.parallel.session import Session

            parts = build_distributed(deck, comm)
            session = Session(parts["communicator"], parts["model"], parts["global_cloud"])
            session.set_up = parts["set_up"]
            return cls(
                deck, parts["cloud"], parts["model"], parts["solver"],
                setup_s=time.perf_counter() - t0, session=session,
                global_cloud=session.global_cloud,
            )  # fmt: skip
        cloud = build_cloud(deck)
        bonds = build_bonds_for(deck, cloud)
        body, kin, init = build_conditions(deck, cloud)
        s = deck.solver
        if isinstance(s, dk.Solver) and s.method == "fdm":
            m = deck.material
            assert isinstance(m, dk.Material)
            material = MATERIALS[m.model](m.youngs_modulus, m.density, m.micromodulus_profile)
            model: Evaluator = FDMModel1D(cloud, material, body, damping=s.damping)
        else:
            model = build_deck_model(deck, cloud, bonds, body)
        attach_rigid_bodies(deck, cloud, model, bonds)
        solver = build_solver(deck, cloud, model, body, kin, init)
        return cls(deck, cloud, model, solver, setup_s=time.perf_counter() - t0)

    @property
    def n_steps(self) -> int:
        """Total number of steps of the run."""
        return self.solver.total_steps()

    def fingerprint(self) -> str:
        """Hash of the validated deck, the package version and (for geometries read from
        a file: mesh, surface, gmsh, image) that file: a checkpoint only resumes the same
        problem with the same code."""
        from peridynamics import __version__

        text = json.dumps(self.deck.model_dump(mode="json", by_alias=True), sort_keys=True)
        h = hashlib.sha256(text.encode())
        h.update(__version__.encode())
        file = getattr(self.deck.geometry, "file", None)
        if file is not None:
            h.update(Path(file).read_bytes())
        return h.hexdigest()
