"""Compute backends beside the Numba kernels: NVIDIA Warp (``solver.backend: warp``).

:mod:`~peridynamics.backends.warp_solver` is the explicit solver stepping on a Warp
device (its CUDA device when there is one, its CPU device otherwise);
:mod:`~peridynamics.backends.warp_device` holds the device arrays and the seam of a
model family on the device; the families and extras are in ``warp_families``,
``warp_lps``, ``warp_correspondence``, ``warp_extras``, ``warp_short_range_contact`` and
``warp_damage``; the kernel sources in the ``_warp_*_dsl`` modules. Nothing here is
imported unless a run asks for the Warp backend (extra ``[gpu]``: warp-lang).
"""
