"""Timing shared by the benchmarks (run as `python3 bench/NAME.py`, so this folder is on sys.path), and the
report's numbers and examples through the tests' one loader (tests/authorities/report.py)."""

import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root, for tests.authorities
from tests.authorities.report import REPORT, betts, example, guided_spreads, table2_entry, table2_stop  # noqa: E402

__all__ = [
    "REPORT",
    "betts",
    "example",
    "guided_spreads",
    "table2_entry",
    "table2_stop",
    "timings_s",
    "median_ms",
    "save_result",
]
RESULTS = Path(__file__).resolve().parent / "results"


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


def save_result(name: str, data: dict) -> Path:
    """bench/results/<name>.json, the figures the README quotes."""
    import json

    RESULTS.mkdir(exist_ok=True)
    path = RESULTS / f"{name}.json"
    path.write_text(json.dumps(data, indent=2, default=float) + "\n")
    return path
