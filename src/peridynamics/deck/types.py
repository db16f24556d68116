"""Number types, the strict base schema and the tagged unions shared by every deck
section.

The base and the number types are those of the output options
(:mod:`peridynamics.io.options`), which the deck's section ``output`` reuses.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Literal

from peridynamics.io.options import Finite, NonNegFloat, NotBool, Num, PosFloat, Strict

Component = Literal["x", "y", "z"]

#: (key path, message) pairs: what every check of the deck returns
Errors = list[tuple[str, str]]


def tag_of(default: str, key: str) -> Callable[[Any], str]:
    """The discriminator of a section with several kinds: the value of ``key`` (a raw
    mapping or a validated section), ``default`` when it is left out."""

    def pick(v: Any) -> str:
        if isinstance(v, dict):
            return str(v.get(key, default))
        return str(getattr(v, key, default))

    return pick


__all__ = [
    "Component",
    "Errors",
    "Finite",
    "NonNegFloat",
    "NotBool",
    "Num",
    "PosFloat",
    "Strict",
    "tag_of",
]
