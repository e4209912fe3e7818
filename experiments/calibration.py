"""A calibration figure for benchmarks on a shared, noisy machine.

Print it next to every measured time: a fixed pure-Python loop whose duration
tracks how fast the machine runs at the moment.
"""
from __future__ import annotations

import statistics
import time


def calibration(repeats: int = 5) -> float:
    """Median seconds of a fixed pure-Python loop (10^6 multiply-adds)."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        acc = 0
        for i in range(1_000_000):
            acc += i * i
        times.append(time.perf_counter() - t0)
    return statistics.median(times)
