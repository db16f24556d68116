"""Numba kernel of the 1-D central finite-difference operator (Lu & Wang (2016), eq. 17).

A serial loop: one pass over the nodes, three loads and a store each, so a thread pool
would cost more than it saves on any bar a 1-D run uses. The NumPy twin is
:func:`peridynamics.kernels.reference.fdm_force_1d`.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True, fastmath=False)
def fdm_force_1d(u, coef, inv_dx, force, max_stretch):  # pragma: no cover - compiled
    """Fill ``force`` (n, 1) with coef (u_{i+1} - 2 u_i + u_{i-1}) with free ends (the
    missing neighbour dropped) and ``max_stretch`` (n,) with the largest tensile
    (u_{i+1} - u_i) inv_dx to a neighbour (0 when both are compressive)."""
    n = u.shape[0]
    for i in range(n):
        force[i, 0] = 0.0
        max_stretch[i] = 0.0
    for i in range(n - 1):
        du = u[i + 1, 0] - u[i, 0]
        force[i, 0] += coef * du
        force[i + 1, 0] -= coef * du
        s = du * inv_dx
        if s > max_stretch[i]:
            max_stretch[i] = s
        if s > max_stretch[i + 1]:
            max_stretch[i + 1] = s
