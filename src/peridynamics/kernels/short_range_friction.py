"""Coulomb friction in the short-range pair contact: Numba kernels and NumPy twin.

Used by
:meth:`peridynamics.evaluation.short_range_contact.ShortRangeContact.add_force_with_friction`,
which
documents the model; the frictionless force pass
(:func:`peridynamics.kernels.short_range_contact.add_contact_force`) is not touched, so a contact
without friction runs exactly the code it ran before.

Pair (i, j) in contact (``r < d_c``, ``r > 0``, no intact bond), masses
``m = rho V``, reduced mass ``m_ij = m_i m_j / (m_i + m_j)``, normal pair force density
``f_n = c_s (d_c - r) / d_c`` (N/m^6; the pair pushes with ``f_n V_i V_j`` N), point load
``L_i = V_i sum_j f_n V_j`` (N) and ``L_ij = max(L_i, L_j)``. With ``v_t`` the part of
``v_i - v_j`` normal to ``y_j - y_i``, the friction pair force density on i is

    stick (m_ij |v_t| / dt <= mu_s L_ij):  f_t = -f_n m_ij / (dt L_ij) v_t
    slide (otherwise):                     f_t = -mu_k f_n v_t / |v_t|

and ``F_i += f_t V_j``. ``f_t`` is odd in (i, j) (``v_t`` changes sign, every scalar is
symmetric), so the force on j is ``-f_t V_i`` and ``V_i F_i + V_j F_j = 0``: linear
momentum is conserved to round-off. An isolated pair (``L_i = L_j = f_n V_i V_j``)
sticks with the pair force ``-m_ij v_t / dt`` (N), which stops the relative tangential
velocity in one explicit step (``dv_rel = dt T (1/m_i + 1/m_j)``); a point in several
contacts shares the stopping force in proportion to the normal loads.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange
from numpy.typing import NDArray

from peridynamics.kernels.short_range_contact import (
    _dist_sq,
    _excluded,
    _reference_pairs,
    contact_force_reference,
)

# strict floating point: with fast-math, a kernel compiled in the process and the same
# kernel loaded from Numba's cache gave different bits (a resumed run then differed from
# an uninterrupted one; tests/regression/test_bodies_checkpoint.py with a cold cache)
_hot = njit(parallel=True, fastmath=False, error_model="numpy", cache=True)


@_hot
def contact_load(x, u, volume, pair_offsets, pair_j, pair_bond_ij, pair_bond_ji, intact,
                 d_c, c_s, load):  # fmt: skip
    """Normal load of each point ``L_i = V_i sum_j c_s (d_c - r) / d_c V_j`` (N), (n,),
    over its pairs in contact with ``r > 0``."""
    n = x.shape[0]
    dc_sq = d_c * d_c
    for i in prange(n):
        acc = 0.0
        for k in range(pair_offsets[i], pair_offsets[i + 1]):
            j = pair_j[k]
            r2 = _dist_sq(i, j, x, u)
            if r2 >= dc_sq or r2 == 0.0:
                continue
            if _excluded(k, pair_bond_ij, pair_bond_ji, intact):
                continue
            acc += (d_c - np.sqrt(r2)) * volume[j]
        load[i] = volume[i] * c_s / d_c * acc


@_hot
def add_contact_force_friction(x, u, v, volume, density, pair_offsets, pair_j, pair_bond_ij,
                               pair_bond_ji, intact, d_c, c_s, mu_s, mu_k, dt, load, force,
                               power):  # fmt: skip
    """ADD the contact force density with Coulomb friction (N/m^3) to ``force`` (n, dim)
    and write each point's share of the friction power ``power`` (n,) (W, <= 0; half of
    each pair's ``T . v_t``). ``load`` (n,) is from :func:`contact_load`."""
    n, d = x.shape
    dc_sq = d_c * d_c
    scale = c_s / d_c
    for i in prange(n):
        mi = density[i] * volume[i]
        pw = 0.0
        for k in range(pair_offsets[i], pair_offsets[i + 1]):
            j = pair_j[k]
            r2 = _dist_sq(i, j, x, u)
            if r2 >= dc_sq or r2 == 0.0:
                continue
            if _excluded(k, pair_bond_ij, pair_bond_ji, intact):
                continue
            r = np.sqrt(r2)
            g = scale * (d_c - r) / r * volume[j]
            s = 0.0  # (y_j - y_i) . (v_i - v_j)
            for c in range(d):
                e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                force[i, c] -= g * e
                s += e * (v[i, c] - v[j, c])
            vt2 = 0.0
            for c in range(d):
                e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                t = (v[i, c] - v[j, c]) - e * (s / r2)
                vt2 += t * t
            if vt2 == 0.0:
                continue
            vt = np.sqrt(vt2)
            fn = scale * (d_c - r)
            mj = density[j] * volume[j]
            m_ij = mi * mj / (mi + mj)
            l_ij = max(load[i], load[j])
            if m_ij * vt <= mu_s * l_ij * dt:
                a = fn * m_ij / (dt * l_ij)
            else:
                a = mu_k * fn / vt
            for c in range(d):
                e = (x[j, c] - x[i, c]) + (u[j, c] - u[i, c])
                t = (v[i, c] - v[j, c]) - e * (s / r2)
                force[i, c] -= a * t * volume[j]
            pw -= 0.5 * a * vt2 * volume[j]
        power[i] = volume[i] * pw


def contact_friction_reference(
    x: NDArray,
    u: NDArray,
    v: NDArray,
    volume: NDArray,
    density: NDArray,
    offsets: NDArray,
    bond_j: NDArray,
    intact: NDArray,
    d_c: float,
    c_s: float,
    mu_s: float,
    mu_k: float,
    dt: float,
) -> tuple[NDArray[np.float64], float]:
    """Brute-force O(n^2) NumPy twin: force density with friction (n, dim) (N/m^3) and
    the friction power (W)."""
    normal = contact_force_reference(x, u, volume, offsets, bond_j, intact, d_c, c_s)
    e, r, mask = _reference_pairs(x, u, offsets, bond_j, intact, d_c)
    mask &= r > 0
    fn = np.where(mask, c_s * (d_c - r) / d_c, 0.0)
    load = volume * (fn @ volume)
    m = density * volume
    m_ij = np.outer(m, m) / (m[:, None] + m[None, :])
    l_ij = np.maximum(load[:, None], load[None, :])
    w = v[:, None, :] - v[None, :, :]
    s = np.sum(e * w, axis=-1)
    r2 = np.where(mask, r * r, 1.0)
    vt = w - e * (s / r2)[..., None]
    speed = np.sqrt(np.sum(vt * vt, axis=-1))
    with np.errstate(divide="ignore", invalid="ignore"):
        stick = m_ij * speed <= mu_s * l_ij * dt
        a = np.where(stick, fn * m_ij / (dt * l_ij), mu_k * fn / speed)
    a = np.where(mask & (speed > 0), a, 0.0)
    force = normal - np.einsum("ij,ijc,j->ic", a, vt, volume)
    power = -float(np.sum(a * speed**2 * np.outer(volume, volume))) / 2.0
    return force, power
