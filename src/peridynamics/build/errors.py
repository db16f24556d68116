"""Set-up errors: a valid deck that describes a model that cannot be built."""

from __future__ import annotations


class SetupError(ValueError):
    """The deck is valid but the model it describes is not (empty node set, ...).

    Parameters
    ----------
    path : str
        The deck key (``"node_sets.load"``) or command-line option (``"--resume"``)
        that asks for what cannot be built.
    message : str
        Why.

    Examples
    --------
    >>> import peridynamics as pd
    >>> deck = pd.Deck.example("bar_wave_1d", {"node_sets.gauge": {"point": [5.0]}})
    >>> pd.Simulation(deck)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    peridynamics.build.errors.SetupError: node_sets.gauge: ...
    """

    def __init__(self, path: str, message: str) -> None:
        self.path = path
        self.message = message
        super().__init__(f"{path}: {message}")
