"""Other load on the machine during a timing window, and timing statistics.

Imported by ``bond_ceiling.py`` and ``lammps_peri.py``. The other load is measured from
``/proc/stat`` (busy CPU time of the whole machine) less the CPU time of this process
and its finished children over the same window, in cores (2.0 = both cores busy with
someone else's work). Linux only; elsewhere the load reads ``nan``.
"""

from __future__ import annotations

import os
import resource
import statistics
import time
from dataclasses import dataclass, field

_TICK = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100


def _busy_seconds() -> float:
    """Busy CPU seconds of the whole machine since boot (user+nice+system+irq+softirq
    +steal; idle and iowait excluded)."""
    with open("/proc/stat") as fh:
        parts = fh.readline().split()[1:]
    v = [int(p) for p in parts]
    user, nice, system, _idle, _iowait, irq, softirq = v[:7]
    steal = v[7] if len(v) > 7 else 0
    return (user + nice + system + irq + softirq + steal) / _TICK


def _own_seconds() -> float:
    """CPU seconds of this process (all threads) and its waited-for children."""
    s = resource.getrusage(resource.RUSAGE_SELF)
    c = resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


@dataclass
class LoadMeter:
    """Accumulates the other load over several timing windows."""

    windows: list[float] = field(default_factory=list)  # other cores, one per window

    def __enter__(self) -> LoadMeter:
        try:
            self._b0, self._o0 = _busy_seconds(), _own_seconds()
        except OSError:
            self._b0 = float("nan")
            self._o0 = 0.0
        self._t0 = time.perf_counter()
        return self

    def __exit__(self, *exc: object) -> None:
        wall = time.perf_counter() - self._t0
        try:
            other = (_busy_seconds() - self._b0) - (_own_seconds() - self._o0)
        except OSError:
            other = float("nan")
        self.windows.append(max(other, 0.0) / wall if wall > 0 else float("nan"))

    def summary(self) -> dict:
        """Mean and largest other load (cores) over the windows."""
        w = [x for x in self.windows if x == x]
        if not w:
            return {"other_load_mean_cores": float("nan"), "other_load_max_cores": float("nan")}
        return {
            "other_load_mean_cores": round(statistics.fmean(w), 3),
            "other_load_max_cores": round(max(w), 3),
        }


def wait_quiet(max_wait: float, threshold: float) -> float:
    """Sleep in 0.5 s samples until the other load is below ``threshold`` cores (this
    process idle meanwhile) or ``max_wait`` seconds passed; returns the seconds waited."""
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < max_wait:
        m = LoadMeter()
        with m:
            time.sleep(0.5)
        if m.windows[0] < threshold:
            break
    return round(time.perf_counter() - t0, 1)


def timed_clean(
    fn, repeat: int, meter: LoadMeter, quiet: tuple[float, float], retries: int = 2,
    accept: float = 0.25,
) -> tuple[float, float, int]:  # fmt: skip
    """Seconds per call of ``fn`` over ``repeat`` calls, in a window whose other load is
    at most ``accept`` cores: wait for quiet (:func:`wait_quiet` with ``quiet`` =
    (max_wait, threshold)), time, and time again (up to ``retries`` times) when someone
    else's load hit the window. Returns (seconds per call, other load of the kept
    window in cores, windows thrown away); only the kept window goes into ``meter``."""
    dropped = 0
    while True:
        wait_quiet(*quiet)
        m = LoadMeter()
        with m:
            t = time.perf_counter()
            for _ in range(repeat):
                fn()
            s = (time.perf_counter() - t) / repeat
        if m.windows[0] <= accept or dropped >= retries:
            meter.windows.extend(m.windows)
            return s, m.windows[0], dropped
        dropped += 1


def loadavg() -> str:
    """The first three fields of /proc/loadavg."""
    try:
        with open("/proc/loadavg") as fh:
            return " ".join(fh.read().split()[:3])
    except OSError:
        return "unknown"


def peak_rss_gib() -> float:
    """Peak resident set size of this process (GiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def best_median(times: list[float]) -> tuple[float, float]:
    """(best, median) of a list of timings."""
    return min(times), statistics.median(times)
