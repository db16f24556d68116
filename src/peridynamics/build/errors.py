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
    """

    def __init__(self, path: str, message: str) -> None:
        self.path = path
        super().__init__(f"{path}: {message}")
