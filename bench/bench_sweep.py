"""The whole Appendix C data set 1 sweep (3 vehicles x 4 inertial velocities x 10 entry angles = 120
footprints) on a Dask LocalCluster of 1 and then 2 worker processes (one thread each), in this process.

Measured for each: the wall time from the first submission to the last footprint gathered (`sweep_s`,
which includes each new worker loading numba's on-disk cache on its first task), the cluster's start-up
apart, trajectories per second over `sweep_s` (every trajectory flown), the sum of the tasks' own times (what one
core would need), and the speed-up of 2 workers over 1. Both runs must give the same numbers, point for point.

    python3 bench/bench_sweep.py            # prints the figures, writes bench/results/sweep.json
"""

import json
import os
import platform
import time
from collections import defaultdict
from pathlib import Path

from _timing import save_result  # noqa: E402
from distributed import Client, LocalCluster

from footprint import parallel
from footprint.contracts import parse

HERE = Path(__file__).resolve().parent
PRESET = HERE.parent / "examples" / "sweep_dataset1.json"


def measure(sweep, n_workers):
    load_before = os.getloadavg()[0]
    t0 = time.perf_counter()
    with (
        LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster,
        Client(cluster) as client,
    ):
        started = time.perf_counter()
        result = parallel.run("sweep", sweep, client=client)
    by_vehicle = defaultdict(float)
    for (vehicle, _, _), run in result.runs.items():
        by_vehicle[vehicle] += run.seconds
    unfinished = sum(
        p.stop_reason in ("max_steps", "step_underflow")
        for fp in result.footprints.values()
        for p in list(fp.points) + list(fp.interior)
    )
    figures = {
        "workers": result.workers,
        "footprints": len(result.runs),
        "tasks": result.tasks,
        "trajectories": result.trajectories,
        "failed_footprints": len(result.errors),
        "unfinished_trajectories_max_steps": unfinished,
        "cluster_start_s": round(started - t0, 2),
        "sweep_s": round(result.seconds, 2),
        "trajectories_per_s": round(result.trajectories / result.seconds, 1),
        "footprints_per_s": round(len(result.runs) / result.seconds, 2),
        "task_seconds_sum": round(sum(r.seconds for r in result.runs.values()), 2),
        "task_seconds_by_vehicle": {k: round(v, 2) for k, v in by_vehicle.items()},
        "load_average_1min_before": round(load_before, 2),
    }
    return figures, result


def main():
    sweep = parse("sweep", json.loads(PRESET.read_text()))
    one, r1 = measure(sweep, 1)
    print(json.dumps(one, indent=2), flush=True)
    two, r2 = measure(sweep, 2)
    print(json.dumps(two, indent=2), flush=True)
    same = all(
        r1.runs[k].footprint is not None
        and r2.runs[k].footprint is not None
        and r1.runs[k].footprint.points == r2.runs[k].footprint.points
        for k in r1.runs
    )
    result = {
        "sweep": PRESET.name,
        "grid": f"{len(sweep.vehicles)} vehicles x {len(sweep.entry_velocity_fps)} velocities x "
        f"{len(sweep.entry_gamma_deg)} angles",
        "cores": os.cpu_count(),
        "machine": platform.processor() or platform.machine(),
        "one_worker": one,
        "two_workers": two,
        "speedup_2_over_1": round(one["sweep_s"] / two["sweep_s"], 2),
        "same_numbers_both_runs": same,
        "note": "the machine may be shared: load_average_1min_before is the 1-minute load when each run began",
    }
    save_result("sweep", result)
    print(
        f"1 worker: {one['trajectories_per_s']} trajectories/s ({one['sweep_s']} s); 2 workers: "
        f"{two['trajectories_per_s']} trajectories/s ({two['sweep_s']} s); speed-up {result['speedup_2_over_1']}; "
        f"same numbers: {same}"
    )


if __name__ == "__main__":
    main()
