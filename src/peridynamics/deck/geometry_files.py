"""The files of the geometry kinds read from a file (surface, gmsh, image): their paths
made absolute against the deck's folder and checked to exist, and a Gmsh model's
dimension filled in when the deck leaves it out (the ``mesh`` kind has its own
resolution in :mod:`peridynamics.deck.reader`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from peridynamics.deck.errors import DeckError
from peridynamics.deck.geometry import GmshGeometry, ImageGeometry, SurfaceGeometry
from peridynamics.deck.schema import Deck

_KINDS = (SurfaceGeometry, GmshGeometry, ImageGeometry)


def _resolved(g: Any, key: str, base_dir: Path | None) -> Any:
    """``g`` with an absolute ``file`` (and a Gmsh model's ``dim``); ``DeckError`` when
    the file is missing or gmsh cannot read it. Without ``base_dir`` (a deck not read
    from a file) a file is only looked up, in the working folder, for a Gmsh model's
    dimension."""
    if base_dir is None and not (isinstance(g, GmshGeometry) and g.dim is None):
        return g
    path = Path(g.file)
    if not path.is_absolute():
        path = (base_dir or Path.cwd()) / path
    if not path.is_file():
        raise DeckError([(f"{key}.file", f"{g.type} file {str(path)!r} does not exist")])
    update: dict[str, Any] = {"file": str(path)}
    if isinstance(g, GmshGeometry) and g.dim is None:
        from peridynamics.geometry.gmsh_model import model_dimension

        try:
            dim = model_dimension(path)
        except ValueError as exc:
            raise DeckError([(f"{key}.file", str(exc))]) from None
        if dim not in (2, 3):
            raise DeckError([(f"{key}.dim", f"the model in {str(path)!r} is {dim}-D")])
        update["dim"] = dim
    return g.model_copy(update=update)


def resolve_geometry_files(deck: Deck, base_dir: Path | None) -> Deck:
    """The deck with the files of its surface, gmsh and image geometries resolved (the
    deck's geometry, the bodies' and the rigid bodies' point sets)."""
    update: dict[str, Any] = {}
    if isinstance(deck.geometry, _KINDS):
        update["geometry"] = _resolved(deck.geometry, "geometry", base_dir)
    bodies = list(deck.bodies)
    for k, b in enumerate(bodies):
        if isinstance(b.geometry, _KINDS):
            g = _resolved(b.geometry, f"bodies.{k}.geometry", base_dir)
            bodies[k] = b.model_copy(update={"geometry": g})
            update["bodies"] = bodies
    rigid = list(deck.rigid_bodies)
    for k, r in enumerate(rigid):
        if isinstance(r.shape.points, _KINDS):
            g = _resolved(r.shape.points, f"rigid_bodies.{k}.shape.points", base_dir)
            shape = r.shape.model_copy(update={"points": g})
            rigid[k] = r.model_copy(update={"shape": shape})
            update["rigid_bodies"] = rigid
    return deck.model_copy(update=update) if update else deck
