"""Timing shared by the benchmarks (run as `python3 bench/NAME.py`, so this folder is on sys.path)."""

import statistics
import time


def timings_s(fn, repeat):
    """(median, fastest) wall time in seconds of `repeat` calls."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times)


def median_ms(fn, repeat):
    return 1e3 * timings_s(fn, repeat)[0]
