"""Numba kernels over flat bond arrays, each with a NumPy twin in ``reference``."""
