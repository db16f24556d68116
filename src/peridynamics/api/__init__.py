"""The Python API: build, run and inspect a simulation from a script or a notebook.

Its names are re-exported at the top level (``peridynamics.Deck``,
``peridynamics.Simulation``, ``peridynamics.Result``, ``peridynamics.Callback``,
``peridynamics.sweep``, ``peridynamics.ensemble``); the command line and this API run
the same code (:mod:`peridynamics.app`). The layer sits beside the command line, above
the application layer (``docs/architecture.md``).
"""
