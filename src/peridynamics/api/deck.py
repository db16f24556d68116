"""The deck of the Python API: :class:`Deck`, read from a file, a mapping or keywords.

Every way of making one runs the command line's validation: the strict schema, the
cross-section checks and the files a deck names (a mesh, initial fields) resolved; an
invalid deck raises :class:`~peridynamics.deck.errors.DeckError`, whose message is the
one ``peridynamics check`` prints (each problem as ``key.path: message``).
"""

from __future__ import annotations

import copy
import html
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import yaml
from pydantic import ValidationError

from peridynamics.deck.errors import DeckError, validation_errors
from peridynamics.deck.reader import apply_overrides, load_deck, parse_deck
from peridynamics.deck.schema import Deck as DeckSchema


def _overrides(values: Mapping[str, Any] | Iterable[str] | None) -> list[str]:
    """``{"solver.steps": 100}`` or ``["solver.steps=100"]`` as ``--set`` arguments."""
    if values is None:
        return []
    if isinstance(values, Mapping):
        return [f"{key}={yaml.safe_dump(v, default_flow_style=True).strip()}"
                for key, v in values.items()]  # fmt: skip
    if isinstance(values, str):
        return [values]
    return [str(v) for v in values]


class Deck(DeckSchema):
    """A validated simulation deck (the YAML deck of the command line as an object).

    Make one with :meth:`from_file`, :meth:`from_dict` or :meth:`from_yaml`, or with
    keywords, one per section (``Deck(name=..., geometry={...}, ...)``); each runs the
    schema and the cross-section checks of ``peridynamics check`` and raises
    :class:`~peridynamics.deck.errors.DeckError` with the same messages. Sections are
    attributes (``deck.material.youngs_modulus``); :meth:`with_` returns a copy with
    values changed by key path, as ``--set`` does. ``peridynamics help deck`` lists
    every key.

    Examples
    --------
    >>> import peridynamics as pd
    >>> deck = pd.Deck.example("bar_wave_1d")
    >>> deck.name, deck.dim
    ('bar_wave_1d', 1)
    >>> deck.with_({"material.youngs_modulus": 2.0e11}).material.youngs_modulus
    200000000000.0
    >>> pd.Deck.from_dict({"name": "x"})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    peridynamics.deck.errors.DeckError: invalid deck:
      geometry: required
    ...
    """

    def __init__(self, **sections: Any) -> None:
        try:
            super().__init__(**sections)
        except ValidationError as exc:
            raise DeckError(validation_errors(exc)) from None
        checked = parse_deck(self.model_dump(by_alias=True, exclude_unset=True))
        self.__dict__.update(checked.__dict__)

    @classmethod
    def _of(cls, deck: DeckSchema) -> Deck:
        """The validated schema object ``deck`` as a :class:`Deck` (no new validation;
        a :class:`Deck` is returned as it is)."""
        if isinstance(deck, cls):
            return deck
        return cls.model_construct(
            _fields_set=set(deck.model_fields_set),
            **{name: getattr(deck, name) for name in DeckSchema.model_fields},
        )

    @classmethod
    def from_file(
        cls, path: str | Path, overrides: Mapping[str, Any] | Iterable[str] | None = None
    ) -> Deck:
        """Read a YAML deck; files it names are found relative to its folder.

        Parameters
        ----------
        path : str or Path
            The deck file.
        overrides : mapping or list of str, optional
            Values changed by key path before validation, as ``--set`` does:
            ``{"solver.steps": 100}`` or ``["solver.steps=100"]``.

        Examples
        --------
        >>> import peridynamics as pd
        >>> from peridynamics.app.examples import list_examples
        >>> path = list_examples()["bar_wave_1d"]
        >>> pd.Deck.from_file(path, {"solver.end_time": 1.0e-4}).solver.end_time
        0.0001
        """
        return cls._of(load_deck(path, _overrides(overrides)))

    @classmethod
    def example(cls, name: str, overrides: Mapping[str, Any] | Iterable[str] | None = None) -> Deck:
        """A shipped example deck by name (``peridynamics examples`` lists the names).

        Examples
        --------
        >>> import peridynamics as pd
        >>> pd.Deck.example("bar_wave_1d").geometry.length
        1.0
        """
        from peridynamics.app.examples import list_examples

        decks = {k: v for k, v in list_examples().items() if v.suffix == ".yaml"}
        if name not in decks:
            raise DeckError([("", f"no example deck {name!r}; the examples: {', '.join(decks)}")])
        return cls.from_file(decks[name], overrides)

    @classmethod
    def from_dict(
        cls,
        data: Mapping[str, Any],
        overrides: Mapping[str, Any] | Iterable[str] | None = None,
        base_dir: str | Path | None = None,
    ) -> Deck:
        """A deck from a mapping of sections (what YAML would read).

        Parameters
        ----------
        data : mapping
            The sections: ``name``, ``geometry``, ``discretisation``, ``material``,
            ``solver``, ...
        overrides : mapping or list of str, optional
            Values changed by key path, as in :meth:`from_file`.
        base_dir : str or Path, optional
            Where relative file names (a mesh, initial fields) are found (default: the
            current folder).

        Examples
        --------
        >>> import peridynamics as pd
        >>> deck = pd.Deck.example("bar_wave_1d")
        >>> pd.Deck.from_dict(deck.to_dict(), {"name": "copy"}).name
        'copy'
        """
        raw = copy.deepcopy(dict(data))
        if overrides:
            raw = apply_overrides(raw, _overrides(overrides))
        return cls._of(parse_deck(raw, Path(base_dir) if base_dir is not None else None))

    @classmethod
    def from_yaml(cls, text: str, base_dir: str | Path | None = None) -> Deck:
        """A deck from YAML text (read as deck files are: safe, no repeated key).

        Examples
        --------
        >>> import peridynamics as pd
        >>> text = pd.Deck.example("bar_wave_1d").to_yaml()
        >>> pd.Deck.from_yaml(text).name
        'bar_wave_1d'
        """
        from peridynamics.deck.yaml_source import yaml_load

        data = yaml_load(text)
        if not isinstance(data, dict):
            raise DeckError([("", "a deck is a YAML mapping of sections (name, geometry, ...)")])
        return cls.from_dict(data, base_dir=base_dir)

    def with_(self, overrides: Mapping[str, Any] | Iterable[str]) -> Deck:
        """A copy with values changed by key path (``--set`` semantics), validated again.

        Examples
        --------
        >>> import peridynamics as pd
        >>> deck = pd.Deck.example("bar_wave_1d")
        >>> deck.with_({"discretisation.spacing": 0.002}).discretisation.spacing
        0.002
        """
        return Deck.from_dict(self.to_dict(), overrides)

    def to_dict(self) -> dict[str, Any]:
        """The deck as plain data (the keys a YAML deck writes; defaults left out).

        Examples
        --------
        >>> import peridynamics as pd
        >>> sorted(pd.Deck.example("bar_wave_1d").to_dict())[:3]
        ['boundary_conditions', 'description', 'discretisation']
        """
        return self.model_dump(mode="json", by_alias=True, exclude_unset=True)

    def to_yaml(self, path: str | Path | None = None) -> str:
        """The deck as YAML text; also written to ``path`` when given.

        Examples
        --------
        >>> import peridynamics as pd
        >>> pd.Deck.example("bar_wave_1d").to_yaml().splitlines()[0]
        'name: bar_wave_1d'
        """
        text = yaml.safe_dump(self.to_dict(), sort_keys=False, allow_unicode=True)
        if path is not None:
            Path(path).write_text(text, encoding="utf-8")
        return text

    def _repr_html_(self) -> str:
        """A deck in a notebook: its name, description and sections as a table."""
        rows = []
        for key, value in self.to_dict().items():
            if key in ("name", "description"):
                continue
            text = yaml.safe_dump(value, sort_keys=False, default_flow_style=None).strip()
            rows.append(
                f"<tr><th style='text-align:left;vertical-align:top'>{html.escape(key)}</th>"
                f"<td style='text-align:left'><pre>{html.escape(text)}</pre></td></tr>"
            )
        title = f"<b>Deck {html.escape(self.name)}</b>"
        if self.description:
            title += f": {html.escape(self.description)}"
        return f"<div>{title}<table>{''.join(rows)}</table></div>"
