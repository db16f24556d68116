"""Observers: every output of a run is a small class with ``on_step`` and ``finalize``.

:mod:`~peridynamics.io.observers.base` holds the interface (:class:`Observer`,
:class:`RunContext`, :class:`RunOptions`), one module per family of outputs holds the
observers, and :mod:`~peridynamics.io.observers.registry` maps names to classes and
picks the observers of a run (:func:`~peridynamics.io.observers.registry.observers_for`).
"""
