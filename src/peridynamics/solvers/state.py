"""Compatibility: the State lives in :mod:`peridynamics.state`."""

from peridynamics.state import State

__all__ = ["State"]
