"""The application layer: what runs built objects (the run loop, sweeps, ensembles)."""
