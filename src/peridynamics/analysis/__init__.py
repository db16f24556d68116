"""Post-processing and analysis tools."""

from peridynamics.analysis.crack import branching, count_branches, crack_tip, tip_speed

__all__ = ["branching", "count_branches", "crack_tip", "tip_speed"]
