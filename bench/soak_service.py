"""`footprint serve` kept busy for a long time (issue 49 item 6): does its local cluster keep its workers?

Starts the real service (`footprint serve --workers 2`, SQLite in a temporary folder: what a planner's first command
starts), and for DURATION_S keeps it busy as users and a hostile machine would:

- jobs back to back, JOBS_AT_ONCE at a time: footprints of the Table 2 case, each a different bank set;
- every CANCEL_EVERY_S a sweep cancelled a moment after its start (the engine stops its task: a worker restart);
- every KILL_EVERY_S one worker process killed with SIGKILL (the kernel's out-of-memory killer, a crash);
- /api/health read every HEALTH_EVERY_S.

Run it beside a mixed load (e.g. `stress-ng --cpu 4 --vm 2 --hdd 1`) for the figures the README quotes. Reported
(bench/results/soak_service.json): jobs submitted, succeeded, failed (each error), cancelled; the time health said
fewer than 2 workers, the longest such stretch and the workers at the end; the lines the service logged about its
workers (why each left, each replacement); the load average beside them. Not a timing: a count of what was lost.

    python3 bench/soak_service.py [--duration-s 3600] [--label NAME]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import random
import re
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx

ROOT = Path(__file__).resolve().parents[1]
CASE = json.loads((ROOT / "examples" / "table2_lod22.json").read_text())
SWEEP = json.loads((ROOT / "examples" / "sweep_dataset1.json").read_text())
JOBS_AT_ONCE = 3
CANCEL_EVERY_S = 120.0
KILL_EVERY_S = 300.0
HEALTH_EVERY_S = 2.0
START_S = 600.0  # a cold start on a loaded machine compiles for minutes
TERMINAL = ("succeeded", "failed", "cancelled")
WORKER_LINES = re.compile(r"left the cluster|replacing|does not answer|answers again|could not")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def cpu_model() -> str:
    """The CPU's model name (Linux), else the platform's machine."""
    try:
        lines = Path("/proc/cpuinfo").read_text().splitlines()
        return next(ln.split(":", 1)[1].strip() for ln in lines if ln.startswith("model name"))
    except (OSError, StopIteration):
        return platform.machine()


def footprint_study(i: int) -> dict:
    return {"case": CASE, "method": "single_parameter", "bank0_deg": [5.0 * (i % 7), 40.0, 80.0]}


def worker_pids(serve_pid: int) -> list[int]:
    """The local cluster's worker processes: the serving process's children spawned by multiprocessing."""
    pids = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            cmdline = (entry / "cmdline").read_bytes().decode(errors="replace")
        except OSError:
            continue
        if int(stat[1]) == serve_pid and "spawn_main" in cmdline:
            pids.append(int(entry.name))
    return pids


def soak(duration_s: float) -> dict:
    tmp = Path(tempfile.mkdtemp(prefix="footprint-soak-"))
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    log_path = tmp / "serve.log"
    env = {k: v for k, v in os.environ.items() if not k.startswith("FOOTPRINT_")}
    with open(log_path, "w") as log:
        serve = subprocess.Popen(
            [sys.executable, "-m", "footprint.cli", "serve", "--port", str(port), "--workers", "2"],
            cwd=tmp, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
        )  # fmt: skip
    client = httpx.Client(base_url=base, timeout=60)
    counts = {"submitted": 0, "succeeded": 0, "failed": 0, "cancelled": 0, "kills": 0, "cancels": 0}
    errors: list[str] = []
    short, longest, stretch_from, samples, degraded = 0.0, 0.0, None, 0, 0
    loads = []
    try:
        deadline = time.monotonic() + START_S
        while True:
            assert serve.poll() is None, log_path.read_text()[-3000:]
            assert time.monotonic() < deadline, "the service did not start"
            try:
                if client.get("/api/health").json()["cluster"]["workers"] == 2:
                    break
            except (httpx.HTTPError, ValueError, KeyError):
                pass
            time.sleep(1)
        t0 = time.monotonic()
        running: list[str] = []
        next_cancel, next_kill, next_health, i = t0 + CANCEL_EVERY_S, t0 + KILL_EVERY_S, t0, 0
        while time.monotonic() - t0 < duration_s:
            now = time.monotonic()
            while len(running) < JOBS_AT_ONCE:
                r = client.post("/api/jobs", json={"kind": "footprint", "study": footprint_study(i)})
                i += 1
                counts["submitted"] += 1
                running.append(r.json()["id"])
            for job_id in list(running):
                job = client.get(f"/api/jobs/{job_id}").json()
                if job["status"] in TERMINAL:
                    running.remove(job_id)
                    counts[job["status"]] += 1
                    if job["status"] == "failed":
                        errors.append(job["error"])
            if now >= next_cancel:
                sweep = client.post("/api/jobs", json={"kind": "sweep", "study": SWEEP}).json()["id"]
                time.sleep(0.3)
                client.delete(f"/api/jobs/{sweep}")
                counts["cancels"] += 1
                next_cancel += CANCEL_EVERY_S
            if now >= next_kill:
                pids = worker_pids(serve.pid)
                if pids:
                    os.kill(random.choice(pids), signal.SIGKILL)
                    counts["kills"] += 1
                next_kill += KILL_EVERY_S
            if now >= next_health:
                r = client.get("/api/health")
                workers = r.json()["cluster"]["workers"]
                samples += 1
                degraded += r.status_code != 200
                if workers < 2:
                    stretch_from = stretch_from or now
                    short += HEALTH_EVERY_S
                    longest = max(longest, now - stretch_from)
                else:
                    stretch_from = None
                loads.append(os.getloadavg()[0])
                next_health += HEALTH_EVERY_S
            time.sleep(0.5)
        for job_id in running:  # the last ones end: none may be lost
            end = time.monotonic() + 600
            while (job := client.get(f"/api/jobs/{job_id}").json())["status"] not in TERMINAL:
                assert time.monotonic() < end, job
                time.sleep(1)
            counts[job["status"]] += 1
            if job["status"] == "failed":
                errors.append(job["error"])
        time.sleep(30)  # a kill's replacement comes back
        final = client.get("/api/health")
        return {
            "date": time.strftime("%Y-%m-%d %H:%M"),
            "machine": cpu_model(),
            "duration_s": duration_s,
            "jobs": counts,
            "failed_errors": errors[:20],
            "health_samples": samples,
            "health_degraded_samples": degraded,
            "seconds_with_fewer_than_2_workers": short,
            "longest_stretch_with_fewer_than_2_workers_s": round(longest, 1),
            "final_health": {"code": final.status_code, **final.json()},
            "load_average_1min": {"min": min(loads), "median": sorted(loads)[len(loads) // 2], "max": max(loads)},
            "worker_lines": [ln for ln in log_path.read_text().splitlines() if WORKER_LINES.search(ln)][:200],
        }
    finally:
        client.close()
        os.killpg(serve.pid, signal.SIGTERM)
        try:
            serve.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(serve.pid, signal.SIGKILL)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--duration-s", type=float, default=3600.0)
    parser.add_argument("--label", default="")
    args = parser.parse_args()
    result = soak(args.duration_s)
    out = ROOT / "bench" / "results" / f"soak_service{'-' + args.label if args.label else ''}.json"
    out.write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps({k: v for k, v in result.items() if k != "worker_lines"}, indent=2))


if __name__ == "__main__":
    main()
