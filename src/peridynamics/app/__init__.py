"""Application: sweeps, ensembles and the benchmark, on top of the build layer."""
