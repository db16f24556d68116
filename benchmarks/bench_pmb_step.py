"""Benchmark: explicit PMB step (bond force + velocity Verlet), Numba vs plain NumPy.

Run from the repository root::

    python benchmarks/bench_pmb_step.py            # 1-D 1e6 points, 2-D 1000^2, 3-D 60^3
    python benchmarks/bench_pmb_step.py --size full  # 3-D 100^3 (about 8 GB of bonds)

Equivalent to ``peridynamics bench``. Bond updates per second count directed bonds;
the NumPy figure is the best plain-NumPy variant (half list, bincount scatter) timed in
the same process on the same bonds.
"""

from __future__ import annotations

import sys

from peridynamics.cli import main

if __name__ == "__main__":
    sys.exit(main(["bench", *sys.argv[1:]]))
