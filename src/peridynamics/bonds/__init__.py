"""Bonds: horizon search, directed CSR list, partial volumes, pre-cracks, surface correction."""

from peridynamics.bonds.bonds import Bonds, build_bonds
from peridynamics.bonds.partial_volume import PARTIAL_VOLUME_RULES, partial_volume_factor
from peridynamics.bonds.precrack import RectangleCrack, SegmentCrack, make_crack
from peridynamics.bonds.search import brute_force_pairs, find_pairs

__all__ = [
    "PARTIAL_VOLUME_RULES",
    "Bonds",
    "RectangleCrack",
    "SegmentCrack",
    "brute_force_pairs",
    "build_bonds",
    "find_pairs",
    "make_crack",
    "partial_volume_factor",
]
