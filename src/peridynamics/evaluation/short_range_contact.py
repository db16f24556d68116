"""Short-range repulsive contact forces between points that are not bonded.

Bond-based peridynamics only acts along bonds: the faces of a crack, fragments, or two
separate bodies pass through each other unless a contact force keeps them apart.
:class:`ShortRangeContact` adds the short-range repulsion of Silling & Askari (2005),
in the form used by the LAMMPS PERI package (Parks et al.), with a cell-list /
Verlet-list neighbour search in the current configuration, and optional Coulomb
friction (Cundall & Strack 1979) decided on the one-step stopping force (Bardenhagen
et al. 2000).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import short_range_contact as kernels
from peridynamics.kernels import short_range_friction as friction_kernels

#: LAMMPS PERI (pair_peri_pmb.cpp) multiplies the micromodulus by this constant, taken
#: from the EMU theory manual (Silling 2005)
PARKS_FACTOR = 15.0
#: contact distance as a fraction of the initial nearest-neighbour spacing (Parks et al.)
DEFAULT_DISTANCE_FACTOR = 0.9
#: Verlet skin as a fraction of the contact distance
DEFAULT_SKIN_FACTOR = 0.5
#: a dense cell table is used up to this many cells per point (plus 4096)
_DENSE_CELLS_PER_POINT = 4


def _positive(name: str, value: float, unit: str) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a finite value > 0 {unit}, got {value}")
    return v


def check_friction(static: float, kinetic: float) -> tuple[float, float]:
    """Validated Coulomb coefficients ``(mu_s, mu_k)``: finite, ``mu_s >= mu_k >= 0``."""
    mu_s, mu_k = float(static), float(kinetic)
    if not (math.isfinite(mu_s) and math.isfinite(mu_k) and mu_s >= mu_k >= 0.0):
        raise ValueError(
            f"friction coefficients must be finite with static >= kinetic >= 0, got "
            f"friction_static={static}, friction_kinetic={kinetic}"
        )
    return mu_s, mu_k


class ShortRangeContact:
    """Short-range repulsive contact force between points not joined by an intact bond.

    Two points i, j whose CURRENT distance ``r = |y_j - y_i|`` (``y = x + u``) is below
    the contact distance ``d_c`` and that are not joined by an intact bond (never
    bonded: separate bodies, distant faces of a crack; or bonded by a broken bond) repel
    each other with the pair force density (N/m^6, force per volume squared)

    .. math:: f_{ij} = -c_s \\frac{d_c - r}{d_c} e_{ij}, \\qquad
              e_{ij} = (y_j - y_i) / r,

    so that the force density on i is ``F_i = sum_j f_ij V_j`` (N/m^3) and the force on
    j is the opposite, with ``V_i``: a central pair force, so linear and angular momentum
    are conserved exactly. It derives from the energy (J)

    .. math:: \\Phi = \\sum_{\\{i, j\\}} V_i V_j \\, c_s \\frac{(d_c - r_{ij})^2}{2 d_c}

    (one term per unordered pair in contact): ``V_i F_i = -dPhi/du_i``. The force is
    continuous (zero) at ``r = d_c`` and reaches ``c_s V_j`` as ``r -> 0``; coincident
    points (``r = 0`` exactly) have no direction and get no force.

    Pairs joined by an intact bond are left to the bond force (an intact bond in either
    direction (i, j) or (j, i) excludes the pair, so the exclusion is symmetric). The
    model therefore adds no force to an undamaged body as long as no two non-bonded
    points come closer than ``d_c``; with ``d_c`` below the initial nearest-neighbour
    spacing and a horizon >= that spacing, the initial configuration is force-free.

    Stiffness convention: ``stiffness`` ``c_s`` (N/m^6) is the pair force density at
    full overlap, the analogue of the PMB micromodulus ``c`` times a stretch, here the
    dimensionless overlap ``(d_c - r) / d_c``. The LAMMPS PERI implementation
    (``pair_peri_pmb.cpp``; Parks et al.) uses ``15 c (d - r) / delta`` with ``delta``
    the horizon, i.e. ``c_s = 15 c d_c / delta``: see :meth:`parks_stiffness`.
    Silling & Askari (2005) take ``d = min(0.9 |x_j - x_i|, 1.35 (r_i + r_j))`` per
    pair (node radii r); LAMMPS takes ``min(0.9 |x_j - x_i|, 1.35 dx)``. Here one
    global ``d_c`` is used; ``0.9 x`` the initial nearest-neighbour spacing is the usual
    choice (:meth:`from_cloud`).

    Friction (optional, ``friction_static`` mu_s >= ``friction_kinetic`` mu_k >= 0,
    default 0): Coulomb's law between the two points of a pair (Cundall & Strack 1979),
    decided on the force that would stop the relative tangential velocity ``v_t`` (the
    part of ``v_i - v_j`` normal to the pair) in one step, as in the frictional contact
    of the material-point method (Bardenhagen et al. 2000). With masses ``m = rho V``,
    ``m_ij = m_i m_j / (m_i + m_j)``, point loads ``L_i = V_i sum_j c_s (d_c - r) / d_c
    V_j`` (N) and ``L_ij = max(L_i, L_j)``: the pair sticks when ``m_ij |v_t| / dt <=
    mu_s L_ij``, with ``f_t = -c_s (d_c - r) / d_c m_ij / (dt L_ij) v_t`` (an isolated
    pair: the force ``-m_ij v_t / dt`` (N) that stops the slip in one explicit step; a
    point in several contacts shares it by normal load, so it is never stopped several
    times over), else it slides, ``f_t = -mu_k c_s (d_c - r) / d_c v_t / |v_t|``.
    ``F_i += f_t V_j`` and the force on j is ``-f_t V_i`` (``f_t`` is odd in (i, j)):
    linear momentum is conserved; angular momentum is not (the friction is not
    central). The friction power ``sum_pairs T . v_t`` (W) is <= 0. No friction in 1-D.
    :meth:`add_force_with_friction` evaluates it (it needs v, rho and dt); without
    friction :meth:`add_force` runs the frictionless kernel, unchanged.

    The contact stiffens the system: a point in contact with ``m`` neighbours gains a
    radial stiffness of about ``m c_s V / d_c`` (N/m^3 per m), to add to
    ``sum_k c V_k / |xi_k|`` in the explicit stable time-step bound.

    Neighbour search: the current positions are binned into cells of side
    ``>= d_c + skin`` (cells capped at 2^(62 // dim) per axis, so a far-away point never
    makes a huge grid: the cells then grow, which stays correct but slower); every pair
    closer than ``d_c + skin`` goes into a Verlet list, rebuilt only when some point has
    moved by more than ``skin / 2`` since the last build (no pair outside the list can
    then be closer than ``d_c``). The force pass gathers over each point's list row in
    parallel, without atomics.

    Parameters
    ----------
    x : ndarray, shape (n, dim)
        Reference positions (m), dim 1, 2 or 3.
    volume : ndarray, shape (n,)
        Nodal volumes (m^3).
    bonds : Bonds
        The bond list the ``intact`` arrays refer to.
    contact_distance : float
        d_c (m), > 0.
    stiffness : float
        c_s (N/m^6), > 0.
    skin : float, optional
        Verlet skin (m), > 0; default ``0.5 d_c``. A larger skin means fewer rebuilds
        but more candidate pairs.
    friction_static, friction_kinetic : float, optional
        Coulomb coefficients mu_s >= mu_k >= 0; default 0 (frictionless).

    Attributes
    ----------
    n_rebuilds : int
        Number of Verlet-list builds so far (the first evaluation builds the list).
    pair_offsets, pair_j : ndarray
        The directed CSR Verlet list of the last build (both (i, j) and (j, i)), each
        row sorted by j.
    pair_bond_ij, pair_bond_ji : ndarray of int64
        Index of bond (i, j) in row i and of bond (j, i) in row j of ``bonds`` for each
        listed pair, -1 when the two points are not bonded.

    References
    ----------
    S. A. Silling, E. Askari (2005), A meshfree method based on the peridynamic model of
    solid mechanics, Computers & Structures 83, 1526-1535 (short-range forces).
    M. L. Parks, R. B. Lehoucq, S. J. Plimpton, S. A. Silling (2008), Implementing
    peridynamics within a molecular dynamics code, Comput. Phys. Commun. 179, 777-783;
    LAMMPS ``pair_style peri/pmb``.
    M. P. Allen, D. J. Tildesley, Computer Simulation of Liquids (cell and Verlet lists).
    P. A. Cundall, O. D. L. Strack (1979), A discrete numerical model for granular
    assemblies, Geotechnique 29, 47-65 (Coulomb friction between particles).
    S. G. Bardenhagen, J. U. Brackbill, D. Sulsky (2000), The material-point method for
    granular materials, Comput. Methods Appl. Mech. Engrg. 187, 529-541 (friction from
    the one-step stopping force).
    """

    def __init__(
        self,
        x: NDArray,
        volume: NDArray,
        bonds: Bonds,
        contact_distance: float,
        stiffness: float,
        skin: float | None = None,
        friction_static: float = 0.0,
        friction_kinetic: float = 0.0,
        global_ids: NDArray[np.int64] | None = None,
    ) -> None:
        xa = np.ascontiguousarray(np.asarray(x, dtype=np.float64))
        if xa.ndim != 2 or xa.shape[1] not in (1, 2, 3):
            raise ValueError(f"x must have shape (n_points, 1|2|3), got {xa.shape}")
        n = xa.shape[0]
        vol = np.ascontiguousarray(np.asarray(volume, dtype=np.float64))
        if vol.shape != (n,):
            raise ValueError(f"volume must have shape ({n},), got {vol.shape}")
        if bonds.n_points != n:
            raise ValueError(f"bonds are for {bonds.n_points} points, x has {n}")
        self.contact_distance = _positive("contact_distance", contact_distance, "m")
        self.stiffness = _positive("stiffness", stiffness, "N/m^6")
        if skin is None:
            skin = DEFAULT_SKIN_FACTOR * self.contact_distance
        self.skin = _positive("skin", skin, "m")
        self.friction_static, self.friction_kinetic = check_friction(
            friction_static, friction_kinetic
        )
        self.cutoff = self.contact_distance + self.skin
        self.x = xa
        self.volume = vol
        self.bonds = bonds
        self.n_rebuilds = 0
        self.pair_offsets = np.zeros(n + 1, dtype=np.int64)
        self.pair_j = np.zeros(0, dtype=np.int32)
        self.pair_bond_ij = np.zeros(0, dtype=np.int64)
        self.pair_bond_ji = np.zeros(0, dtype=np.int64)
        self._u_ref: NDArray | None = None
        # the order of a point's contacts and of its family: global ids (serial: 0..n-1)
        self._key = np.ascontiguousarray(
            np.arange(n, dtype=np.int64) if global_ids is None else global_ids, dtype=np.int64
        )
        self._limit_sq = (0.5 * self.skin) ** 2
        self._coords = np.empty((n, xa.shape[1]), dtype=np.int64)
        self._keys = np.empty(n, dtype=np.int64)
        self._counts = np.empty(n, dtype=np.int64)
        self._w = np.empty(n)
        self._load = np.empty(0)
        self._power = np.empty(0)

    # -- construction helpers -------------------------------------------------------------
    @staticmethod
    def parks_stiffness(
        micromodulus: float, contact_distance: float, horizon: float, factor: float = 15.0
    ) -> float:
        """``c_s = factor c d_c / delta`` (N/m^6): with ``factor = 15`` the force of the
        LAMMPS PERI implementation, ``15 c (d_c - r) / delta`` (Parks et al.)."""
        return float(factor) * float(micromodulus) * float(contact_distance) / float(horizon)

    @classmethod
    def from_cloud(
        cls,
        cloud: PointCloud,
        bonds: Bonds,
        stiffness: float,
        distance_factor: float = DEFAULT_DISTANCE_FACTOR,
        skin: float | None = None,
        friction_static: float = 0.0,
        friction_kinetic: float = 0.0,
    ) -> ShortRangeContact:
        """Contact with ``d_c = distance_factor x`` the initial nearest-neighbour spacing
        (the shortest bond; ``cloud.spacing`` if there is none)."""
        factor = _positive("distance_factor", distance_factor, "")
        lengths = bonds.bond_length
        h = float(lengths.min()) if lengths.size else float(cloud.spacing)
        return cls(
            cloud.x, cloud.volume, bonds, factor * h, stiffness, skin, friction_static,
            friction_kinetic,
        )  # fmt: skip

    # -- Verlet list ------------------------------------------------------------------------
    @property
    def n_candidate_pairs(self) -> int:
        """Unordered pairs in the current Verlet list (closer than d_c + skin at the
        last build)."""
        return int(self.pair_j.shape[0] // 2)

    def needs_rebuild(self, u: NDArray) -> bool:
        """True if no list was built yet or some point moved by more than skin / 2."""
        if self._u_ref is None:
            return True
        return bool(kernels.max_displacement_sq(u, self._u_ref) > self._limit_sq)

    def rebuild(self, u: NDArray) -> None:
        """Build the Verlet list for displacements ``u`` (n, dim) now."""
        x = self.x
        n, d = x.shape
        lo = np.empty(d)
        hi = np.empty(d)
        if not kernels.bounding_box(x, u, lo, hi):
            raise ValueError("displacements contain NaN or inf: cannot search for contacts")
        extent = hi - lo
        max_cells = 2 ** (62 // d) - 2  # per axis: the linear keys stay below 2^62
        side = self.cutoff * (1.0 + 1e-9)  # margin: rounding never skips a cell
        side = max(side, float(extent.max()) / (max_cells - 1))
        ncell = np.minimum(np.floor(extent / side) + 1.0, float(max_cells)).astype(np.int64)
        stride = np.ones(d, dtype=np.int64)
        for c in range(d - 2, -1, -1):
            stride[c] = stride[c + 1] * ncell[c + 1]
        kernels.cell_keys(x, u, lo, 1.0 / side, ncell, stride, self._coords, self._keys)
        order = np.argsort(self._keys, kind="stable")
        sorted_keys = np.ascontiguousarray(self._keys[order])
        n_cells = math.prod(int(k) for k in ncell)
        if n_cells <= _DENSE_CELLS_PER_POINT * n + 4096:  # dense table: O(1) cell look-up
            cell_start = np.empty(n_cells + 1, dtype=np.int64)
            kernels.cell_table(sorted_keys, cell_start)
        else:  # sparse (something flew far away): binary searches in sorted_keys
            cell_start = np.empty(0, dtype=np.int64)
        cutoff_sq = self.cutoff * self.cutoff
        kernels.count_candidates(
            x, u, self._coords, ncell, stride, order, sorted_keys, cell_start, cutoff_sq,
            self._counts,
        )  # fmt: skip
        offsets = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(self._counts, out=offsets[1:])
        m = int(offsets[-1])
        pair_j = np.empty(m, dtype=np.int32)
        bond_ij = np.empty(m, dtype=np.int64)
        bond_ji = np.empty(m, dtype=np.int64)
        b = self.bonds
        kernels.fill_candidates(
            x, u, self._coords, ncell, stride, order, sorted_keys, cell_start, cutoff_sq, offsets,
            b.offsets, b.bond_j, pair_j, bond_ij, bond_ji, self._key,
        )  # fmt: skip
        self.pair_offsets, self.pair_j = offsets, pair_j
        self.pair_bond_ij, self.pair_bond_ji = bond_ij, bond_ji
        self._u_ref = np.array(u, dtype=np.float64, copy=True)
        self.n_rebuilds += 1

    def _prepare(self, u: NDArray, intact: NDArray) -> None:
        if u.shape != self.x.shape:
            raise ValueError(f"u must have shape {self.x.shape}, got {u.shape}")
        if intact.shape != (self.bonds.n_bonds,):
            raise ValueError(f"intact must have shape ({self.bonds.n_bonds},), got {intact.shape}")
        if self.needs_rebuild(u):
            self.rebuild(u)

    # -- physics ----------------------------------------------------------------------------
    @property
    def has_friction(self) -> bool:
        """True when the friction acts (mu_s > 0 and dim > 1)."""
        return self.friction_static > 0.0 and self.x.shape[1] > 1

    def add_force(
        self,
        u: NDArray,
        intact: NDArray[np.uint8],
        force: NDArray,
        *,
        v: NDArray | None = None,
        density: float | NDArray | None = None,
        dt: float | None = None,
    ) -> float:
        """ADD the contact force density (N/m^3) to ``force`` (n, dim).

        ``u`` (n, dim) are the displacements (m), ``intact`` (n_bonds,) the bond states
        (uint8, aligned with ``bonds.bond_j``). Rebuilds the Verlet list only when needed.
        With friction, ``v``, ``density`` and ``dt`` are required (as for
        :meth:`add_force_with_friction`). Returns the friction power (W, 0.0 without).
        """
        if self.has_friction:
            if v is None or density is None or dt is None:
                raise ValueError(
                    "this contact has friction: pass v, density and dt "
                    "(or call add_force_with_friction)"
                )
            return self.add_force_with_friction(u, v, intact, force, density, dt)
        self._prepare(u, intact)
        if force.shape != self.x.shape:
            raise ValueError(f"force must have shape {self.x.shape}, got {force.shape}")
        kernels.add_contact_force(
            self.x, u, self.volume, self.pair_offsets, self.pair_j, self.pair_bond_ij,
            self.pair_bond_ji, intact, self.contact_distance, self.stiffness, force,
        )  # fmt: skip
        return 0.0

    def add_force_with_friction(
        self,
        u: NDArray,
        v: NDArray,
        intact: NDArray[np.uint8],
        force: NDArray,
        density: float | NDArray,
        dt: float,
    ) -> float:
        """ADD the contact force density with friction (N/m^3) to ``force`` (n, dim) and
        return the friction power ``sum_pairs T . v_t`` (W, <= 0).

        ``v`` (n, dim): velocities (m/s), ``density`` (kg/m^3): scalar or (n,), ``dt``:
        the time step (s). Without friction this is :meth:`add_force` (power 0.0).
        """
        if not self.has_friction:
            return self.add_force(u, intact, force)
        self._prepare(u, intact)
        n = self.x.shape[0]
        for name, a in (("force", force), ("v", v)):
            if a.shape != self.x.shape:
                raise ValueError(f"{name} must have shape {self.x.shape}, got {a.shape}")
        rho = np.asarray(density, dtype=np.float64)
        rho = np.full(n, float(rho)) if rho.ndim == 0 else rho
        if rho.shape != (n,) or not np.all(rho > 0):
            raise ValueError(f"density must be > 0, a scalar or shape ({n},)")
        step = _positive("dt", dt, "s")
        if self._load.shape[0] != n:
            self._load = np.empty(n)
            self._power = np.empty(n)
        args = (self.pair_offsets, self.pair_j, self.pair_bond_ij, self.pair_bond_ji, intact)
        friction_kernels.contact_load(
            self.x, u, self.volume, *args, self.contact_distance, self.stiffness, self._load
        )
        friction_kernels.add_contact_force_friction(
            self.x, u, v, self.volume, rho, *args, self.contact_distance, self.stiffness,
            self.friction_static, self.friction_kinetic, step, self._load, force, self._power,
        )  # fmt: skip
        return float(np.sum(self._power))

    def _energy_and_count(self, u: NDArray, intact: NDArray) -> tuple[float, int]:
        self._prepare(u, intact)
        kernels.contact_energy_density(
            self.x, u, self.volume, self.pair_offsets, self.pair_j, self.pair_bond_ij,
            self.pair_bond_ji, intact, self.contact_distance, self.stiffness, self._w,
            self._counts,
        )  # fmt: skip
        energy = float(np.sum(self._w * self.volume))
        return energy, int(np.sum(self._counts)) // 2

    def energy(self, u: NDArray, intact: NDArray[np.uint8]) -> float:
        """Contact energy sum over pairs V_i V_j c_s (d_c - r)^2 / (2 d_c) (J)."""
        return self._energy_and_count(u, intact)[0]

    def n_pairs_in_contact(self, u: NDArray, intact: NDArray[np.uint8]) -> int:
        """Number of unordered pairs closer than d_c and not joined by an intact bond."""
        return self._energy_and_count(u, intact)[1]
