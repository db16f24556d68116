"""Compute backends beside the Numba kernels (issue "GPU backend", in progress).

:mod:`peridynamics.backends.warp_kernels` holds NVIDIA Warp versions of the explicit
PMB kernels (Warp's CUDA device when there is one, its CPU device otherwise); they are
tested against the Numba kernels and their NumPy twins on the CPU device. They are not
yet wired into the solvers (no ``solver.backend`` key yet).
"""
