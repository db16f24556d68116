"""Post-processing and analysis tools: crack tracking, dispersion relations, the
J-integral, crack-opening profiles and the energy release rate from broken bonds."""

from peridynamics.analysis.anisotropy import DamageAnisotropy, damage_anisotropy
from peridynamics.analysis.attenuation import corrected_strength, fit_attenuation
from peridynamics.analysis.crack import branching, count_branches, crack_tip, tip_speed
from peridynamics.analysis.crack_opening import (
    crack_opening,
    k_and_tip_from_opening,
    k_from_opening,
    lefm_opening,
)
from peridynamics.analysis.crack_path import extract_crack_path, extract_crack_paths
from peridynamics.analysis.crack_polyline import CrackPath
from peridynamics.analysis.crack_speed import rayleigh_speed, tip_speed_from_paths
from peridynamics.analysis.dispersion import (
    Advice,
    Dispersion,
    advise_1d,
    bloch_dispersion,
    continuous_1d,
    fdm_1d,
    fully_discrete_1d,
    lattice_family_2d,
    oscillation_index_2d,
    semi_discrete_1d,
    semi_discrete_2d,
    semi_discrete_omega_1d,
    viscous_1d,
    zero_energy_points_1d,
    zero_group_velocity_points_1d,
)
from peridynamics.analysis.energy_release import broken_bond_energy, energy_release_rate
from peridynamics.analysis.j_integral import j_integral

__all__ = [
    "DamageAnisotropy",
    "damage_anisotropy",
    "Advice",
    "CrackPath",
    "extract_crack_path",
    "extract_crack_paths",
    "rayleigh_speed",
    "tip_speed_from_paths",
    "Dispersion",
    "advise_1d",
    "bloch_dispersion",
    "branching",
    "broken_bond_energy",
    "continuous_1d",
    "corrected_strength",
    "count_branches",
    "crack_opening",
    "crack_tip",
    "energy_release_rate",
    "fit_attenuation",
    "fdm_1d",
    "fully_discrete_1d",
    "j_integral",
    "k_and_tip_from_opening",
    "k_from_opening",
    "lattice_family_2d",
    "lefm_opening",
    "oscillation_index_2d",
    "semi_discrete_1d",
    "semi_discrete_2d",
    "semi_discrete_omega_1d",
    "tip_speed",
    "viscous_1d",
    "zero_energy_points_1d",
    "zero_group_velocity_points_1d",
]
