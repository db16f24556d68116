"""The shipped example decks: where they are installed and their names (``peridynamics
examples`` lists them; :meth:`peridynamics.api.deck.Deck.example` reads one)."""

from __future__ import annotations

from pathlib import Path


def examples_dir() -> Path:
    """Folder holding the example decks (installed copy first, then the source tree)."""
    here = Path(__file__).resolve().parents[1]  # the package
    for cand in (here / "_examples", here.parents[1] / "examples"):
        if cand.is_dir():
            return cand
    raise FileNotFoundError("the example decks are not installed")


def list_examples() -> dict[str, Path]:
    """Map example name -> deck path (every ``*.yaml`` under the examples folder)."""
    root = examples_dir()
    out = {}
    for p in sorted(root.rglob("*.yaml")):
        rel = p.relative_to(root)
        name = rel.parent.as_posix() if p.stem == "deck" else rel.with_suffix("").as_posix()
        out[name] = p
    for folder in sorted(d for d in root.iterdir() if d.is_dir()):
        scripts = sorted(folder.glob("*.py"))
        if scripts and not any(folder.glob("*.yaml")):  # a script example (figures, ...)
            out[folder.name] = scripts[0]
    return dict(sorted(out.items()))
