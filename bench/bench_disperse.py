"""Dispersed footprints on Dask: the L/D 1.89 Table 2 case (examples/disperse_lod189.json, 22 flights a sample) at
about 10,000 trajectories, flown in this process (the baseline, in the same run), then on a LocalCluster of 1 and of 2
workers (one task per chunk of ~2,000 trajectories). Cluster start-up is timed apart; each cluster is warmed (numba's
cache loaded) by a small run first.

    python3 bench/bench_disperse.py     # prints the figures, writes bench/results/disperse.json
"""

import json
import os
import sys
import time
from pathlib import Path

from _timing import save_result

ROOT = Path(__file__).resolve().parents[1]
STUDY = json.loads((ROOT / "examples" / "disperse_lod189.json").read_text())
SAMPLES = 455  # x 22 flights = 10,010 trajectories


def main():
    from footprint.contracts.dispersion import run
    from footprint.parallel import start_client

    study = STUDY | {"samples": SAMPLES}
    run(study | {"samples": 2})  # warm this process
    t0 = time.perf_counter()
    _, here = run(study)
    figures = {"trajectories": SAMPLES * 22, "in_process_s": round(time.perf_counter() - t0, 2),
               "load_average_1min": round(os.getloadavg()[0], 2)}
    for workers in (1, 2):
        t0 = time.perf_counter()
        client, close = start_client(workers=workers)
        try:
            started = time.perf_counter() - t0
            run(study | {"samples": 20}, client=client)  # warm the workers
            _, info = run(study, client=client)
        finally:
            close()
        figures[f"workers_{workers}"] = {"cluster_start_s": round(started, 2), "seconds": round(info["seconds"], 2),
                                         "tasks": info["tasks"],
                                         "trajectories_per_s": round(figures["trajectories"] / info["seconds"])}
    figures["speedup_1_to_2_workers"] = round(figures["workers_1"]["seconds"] / figures["workers_2"]["seconds"], 2)
    figures["in_process_over_2_workers"] = round(figures["in_process_s"] / figures["workers_2"]["seconds"], 2)
    figures["cores"] = os.cpu_count()
    save_result("disperse", figures)
    print(json.dumps(figures, indent=2))


if __name__ == "__main__":
    sys.exit(main())
