"""Dispersed footprints on Dask: the L/D 1.89 Table 2 case (examples/disperse_lod189.json, 22 flights a sample) at about
10,000 trajectories, flown in this process (the baseline, in the same run), then on a LocalCluster of 1 and of 2 workers
(one task per chunk of ~1,000 trajectories, contracts.dispersion.CHUNK_FLIGHTS). Cluster start-up is timed apart (it
includes the workers' warm-up, parallel.Warm: the contract modules imported, numba's cache loaded); a small run
follows it. Then the call a user makes, run(workers=2) starting its own cluster ("cold": its wall time holds the
cluster's start and the workers' warm-up), at 10,000 and at 100,000 trajectories (4,546 samples), the 100,000 with the
resident set (psutil RSS) of this process and of each worker sampled every RSS_PERIOD_S and at each finished chunk: a
run keeps the landing points only, so memory should stay flat.

run()'s seconds end with the last chunk, before the statistics, in process as on Dask: in_process_statistics_s is
wall minus seconds.
The 1-minute load average is recorded before and after each measurement (a shared 2-core machine).

    python3 bench/bench_disperse.py     # ~3 min; prints the figures, writes bench/results/disperse.json
"""

import json
import os
import sys
import threading
import time
from pathlib import Path

from _timing import save_result

ROOT = Path(__file__).resolve().parents[1]
STUDY = json.loads((ROOT / "examples" / "disperse_lod189.json").read_text())
FLIGHTS = 22  # a sample's flights: 11 bank settings and zero lift, both halves
SAMPLES = 455  # x 22 flights = 10,010 trajectories
SAMPLES_100K = 4_546  # x 22 = 100,012
TARGET_S = {"10k": 10.0, "100k": 100.0}  # issue 16, on 2 workers
RSS_PERIOD_S = 0.25
MIB = 2**20


def load() -> float:
    return round(os.getloadavg()[0], 2)


class RSS:
    """This process's and the LocalCluster workers' RSS, every RSS_PERIOD_S in a thread and at each chunk."""

    def __init__(self):
        import psutil

        self.psutil, self.me = psutil, psutil.Process()
        self.start = self.me.memory_info().rss
        self.ticks, self.chunks = [], []  # (main, {pid: rss}); (done, main, {pid: rss})
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, daemon=True)

    def now(self):
        workers = {}
        for p in self.me.children(recursive=True):
            try:  # the workers are multiprocessing spawn children (not the resource tracker)
                if "spawn_main" in " ".join(p.cmdline()):
                    workers[p.pid] = p.memory_info().rss
            except self.psutil.Error:
                pass
        return self.me.memory_info().rss, workers

    def _loop(self):
        while not self._stop.wait(RSS_PERIOD_S):
            self.ticks.append(self.now())

    def progress(self, done, total):
        self.chunks.append((done, *self.now()))

    def __enter__(self):
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()

    def report(self) -> dict:
        mains = [m for m, _ in self.ticks] + [m for _, m, _ in self.chunks]
        out = {
            "period_s": RSS_PERIOD_S,
            "ticks": len(self.ticks),
            "chunks": len(self.chunks),
            "main_start_mib": round(self.start / MIB, 1),
            "main_peak_mib": round(max(mains) / MIB, 1),
            "main_after_first_chunk_mib": round(self.chunks[0][1] / MIB, 1),
            "main_at_last_chunk_mib": round(self.chunks[-1][1] / MIB, 1),
            "workers": [],
        }
        for pid in sorted({pid for _, ws in self.ticks for pid in ws}):
            seen = [ws[pid] for _, ws in self.ticks if pid in ws]
            at = [ws[pid] for _, _, ws in self.chunks if pid in ws]
            out["workers"].append(
                {
                    "first_seen_mib": round(seen[0] / MIB, 1),
                    "peak_mib": round(max(seen + at) / MIB, 1),
                    "after_first_chunk_mib": round(at[0] / MIB, 1),
                    "at_last_chunk_mib": round(at[-1] / MIB, 1),
                    "growth_first_to_last_chunk_mib": round((at[-1] - at[0]) / MIB, 1),
                }
            )
        return out


def cold(run, study, samples, progress=None) -> dict:
    """run(workers=2) as a user calls it: the run's seconds, and the wall time with the cluster's start and close."""
    before, t0 = load(), time.perf_counter()
    _, info = run(study | {"samples": samples}, progress, workers=2)
    wall = time.perf_counter() - t0
    return {
        "trajectories": samples * FLIGHTS,
        "seconds": round(info["seconds"], 2),
        "wall_s": round(wall, 2),
        "start_close_and_statistics_s": round(wall - info["seconds"], 2),
        "tasks": info["tasks"],
        "trajectories_per_s": round(samples * FLIGHTS / info["seconds"]),
        "load_average_1min": {"before": before, "after": load()},
    }


def main():
    from footprint.api import disperse as run
    from footprint.parallel import start_client

    study = STUDY | {"samples": SAMPLES}
    run(study | {"samples": 2})  # warm this process
    before, t0 = load(), time.perf_counter()
    _, here = run(study)
    wall = time.perf_counter() - t0
    figures = {
        "trajectories": SAMPLES * FLIGHTS,
        "in_process_s": round(here["seconds"], 2),
        "in_process_statistics_s": round(wall - here["seconds"], 2),
        "load_average_1min": before,
        "load_average_1min_after": load(),
    }
    for workers in (1, 2):
        t0 = time.perf_counter()
        client, close = start_client(workers=workers)
        try:
            started = time.perf_counter() - t0
            run(study | {"samples": 20}, client=client)  # a small run first (the workers warmed as they started)
            before = load()
            _, info = run(study, client=client)
        finally:
            close()
        figures[f"workers_{workers}"] = {
            "cluster_start_s": round(started, 2),
            "seconds": round(info["seconds"], 2),
            "tasks": info["tasks"],
            "trajectories_per_s": round(figures["trajectories"] / info["seconds"]),
            "load_average_1min": {"before": before, "after": load()},
        }
    figures["speedup_1_to_2_workers"] = round(figures["workers_1"]["seconds"] / figures["workers_2"]["seconds"], 2)
    figures["in_process_over_2_workers"] = round(figures["in_process_s"] / figures["workers_2"]["seconds"], 2)
    figures["cold_workers_2"] = cold(run, study, SAMPLES)
    figures["in_process_over_cold_2_workers"] = round(figures["in_process_s"] / figures["cold_workers_2"]["seconds"], 2)
    with RSS() as rss:
        big = cold(run, study, SAMPLES_100K, rss.progress)
    figures["cold_workers_2_100k"] = big | {
        "rss": rss.report(),
        "in_process_estimate_s": round(figures["in_process_s"] / figures["trajectories"] * big["trajectories"], 1),
    }
    figures["targets"] = {
        "10k_on_2_workers_s": TARGET_S["10k"],
        "10k_met_warm": figures["workers_2"]["seconds"] <= TARGET_S["10k"],
        "10k_met_cold_run": figures["cold_workers_2"]["seconds"] <= TARGET_S["10k"],
        "10k_met_cold_wall": figures["cold_workers_2"]["wall_s"] <= TARGET_S["10k"],
        "100k_on_2_workers_s": TARGET_S["100k"],
        "100k_met_run": big["seconds"] <= TARGET_S["100k"],
        "100k_met_wall": big["wall_s"] <= TARGET_S["100k"],
    }
    figures["cores"] = os.cpu_count()
    save_result("disperse", figures)
    print(json.dumps(figures, indent=2))


if __name__ == "__main__":
    sys.exit(main())
