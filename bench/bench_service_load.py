"""The web service under load, on loopback: 200 concurrent reads and 20 concurrent footprint jobs.

Starts the real service as a subprocess (`footprint serve --port FREE --database-url sqlite:///TMP
--workers 2`: uvicorn, SQLite, an in-process Dask LocalCluster of 2 worker processes), waits for
/api/health, seeds one footprint job, then with httpx.AsyncClient over 127.0.0.1:

1. reads alone: each endpoint once (its first answer fills the service's caches: reported apart as
   first_read_ms), then ROUNDS bursts of 200 concurrent GETs, a quarter each of /api/footprints,
   /api/footprints/{id}, /api/vehicles and /api/health;
2. jobs: 20 footprint jobs submitted at once (small single-parameter studies of the Table 2 case,
   each a different bank set), and while they run another burst of 200 concurrent reads;
   every job must reach `succeeded` and own exactly one stored footprint with its points.

Every response must be 2xx (no error) and no job may be lost. Reported: p50/p99/max latency of the
reads (alone, and while the jobs run), the job throughput (jobs and trajectories per second from the
first submission to the last success), and each endpoint's reads one at a time (the service time
without queueing). Baseline, in this process after the server has stopped: the same reads (bursts and
one at a time) sent to the same app (create_app on a copy of the same database) through
httpx.ASGITransport, i.e. with no sockets, no HTTP parsing and no uvicorn; the ratios
(loopback_over_in_process) say what the loopback HTTP server in its own process adds. Bounded: the whole run stops with an error past TOTAL_BUDGET_S (2 min).

    python3 bench/bench_service_load.py     # prints the figures, writes bench/results/service_load.json

tests/service/test_load.py runs the same code, smaller (50 reads, 5 jobs).
"""

from __future__ import annotations

import asyncio
import json
import os
import platform
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

import httpx

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CASE = json.loads((ROOT / "examples" / "table2_lod22.json").read_text())
CONCURRENT_READS = 200
ROUNDS = 3
SEQUENTIAL_REPEAT = 10  # one-at-a-time reads of each endpoint (the service time without queueing)
JOBS = 20
TOTAL_BUDGET_S = 120.0
START_BUDGET_S = 60.0
JOBS_BUDGET_S = 60.0


def small_study(i: int) -> dict:
    """A small footprint study: the Table 2 case, 3 bank settings (one of them different per job), one half."""
    return {"case": CASE, "method": "single_parameter", "bank0_deg": [0.0, 30.0 + i, 90.0],
            "min_range": "zero_lift", "mirror": False}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextmanager
def running_service(workdir: Path, *, workers: int = 2):
    """`footprint serve` on a free loopback port with a fresh SQLite file; yields (base_url, db_path, log_path)."""
    port = _free_port()
    db = workdir / "load.db"
    log = workdir / "serve.log"
    cmd = ["footprint", "serve", "--host", "127.0.0.1", "--port", str(port), "--database-url", f"sqlite:///{db}",
           "--workers", str(workers)]
    env = {k: v for k, v in os.environ.items() if not k.startswith("FOOTPRINT_")}
    with open(log, "w") as out:
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, cwd=workdir, env=env,
                                start_new_session=True)
    try:
        yield f"http://127.0.0.1:{port}", db, log, proc
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait(timeout=10)


async def wait_healthy(client: httpx.AsyncClient, proc, budget_s: float) -> tuple[float, dict]:
    """Seconds until /api/health answers 200 with a working database and cluster."""
    t0 = time.perf_counter()
    last = None
    while time.perf_counter() - t0 < budget_s:
        if proc.poll() is not None:
            raise RuntimeError(f"footprint serve exited with {proc.returncode}")
        try:
            r = await client.get("/api/health", timeout=5)
            last = r.json()
            if r.status_code == 200 and last["database"]["ok"] and last["cluster"]["ok"] and \
                    last["cluster"]["workers"] >= 1:
                return time.perf_counter() - t0, last
        except (httpx.TransportError, ValueError, KeyError):
            pass
        await asyncio.sleep(0.2)
    raise TimeoutError(f"/api/health not ok after {budget_s} s (last: {last})")


def _check(r: httpx.Response, expected: int, what: str) -> dict | list:
    if r.status_code != expected:
        raise AssertionError(f"{what}: HTTP {r.status_code} (expected {expected}): {r.text[:300]}")
    return r.json()


async def submit_jobs(client: httpx.AsyncClient, studies: list[dict], label: str) -> tuple[list[str], list[float]]:
    """POST all jobs at once; (ids, submission latencies in seconds)."""

    async def one(i, study):
        t0 = time.perf_counter()
        r = await client.post("/api/jobs", json={"kind": "footprint", "study": study, "name": f"{label}-{i}"})
        dt = time.perf_counter() - t0
        body = _check(r, 202, f"POST /api/jobs #{i}")
        assert body["status"] == "queued" and body["id"], body
        return body["id"], dt

    done = await asyncio.gather(*(one(i, s) for i, s in enumerate(studies)))
    return [d[0] for d in done], [d[1] for d in done]


async def wait_jobs(client: httpx.AsyncClient, ids: list[str], budget_s: float) -> tuple[dict[str, dict], float]:
    """Poll until every job is terminal; (final job documents by id, seconds until the last one ended)."""
    t0 = time.perf_counter()
    final: dict[str, dict] = {}
    while len(final) < len(ids):
        if time.perf_counter() - t0 > budget_s:
            missing = [i for i in ids if i not in final]
            raise TimeoutError(f"{len(missing)} of {len(ids)} jobs not finished after {budget_s} s: {missing[:3]}")
        pending = [i for i in ids if i not in final]
        docs = await asyncio.gather(*(client.get(f"/api/jobs/{i}") for i in pending))
        for job_id, r in zip(pending, docs):
            doc = _check(r, 200, f"GET /api/jobs/{job_id}")
            if doc["status"] in ("succeeded", "failed", "cancelled"):
                final[job_id] = doc
        if len(final) < len(ids):
            await asyncio.sleep(0.1)
    return final, time.perf_counter() - t0


async def check_jobs(client: httpx.AsyncClient, final: dict[str, dict]) -> dict[str, dict]:
    """Every job succeeded and owns exactly one footprint with points; {job id: footprint document}."""
    bad = {i: (d["status"], d.get("error")) for i, d in final.items() if d["status"] != "succeeded"}
    if bad:
        raise AssertionError(f"{len(bad)} jobs did not succeed: {list(bad.items())[:3]}")
    out = {}
    for job_id, doc in final.items():
        links = doc["result"]["footprints"]
        assert len(links) == 1, f"job {job_id}: {len(links)} footprints"
        fp = _check(await client.get(links[0]), 200, f"GET {links[0]}")
        assert fp["job_id"] == job_id, (fp["job_id"], job_id)
        assert len(fp["points"]) >= 3, f"job {job_id}: footprint with {len(fp['points'])} points"
        listed = _check(await client.get("/api/footprints", params={"job_id": job_id}), 200, "GET /api/footprints")
        assert listed["total"] == 1 and listed["items"][0]["id"] == fp["id"], f"job {job_id}: stored {listed['total']}"
        out[job_id] = fp
    return out


def read_paths(footprint_id: str, n: int) -> list[str]:
    mix = ["/api/footprints", f"/api/footprints/{footprint_id}", "/api/vehicles", "/api/health"]
    return [mix[i % len(mix)] for i in range(n)]


async def read_burst(client: httpx.AsyncClient, paths: list[str]) -> list[float]:
    """All GETs at once; their latencies in seconds. Any non-200 answer or transport error raises."""

    async def one(path):
        t0 = time.perf_counter()
        r = await client.get(path)
        dt = time.perf_counter() - t0
        _check(r, 200, f"GET {path}")
        return dt

    return list(await asyncio.gather(*(one(p) for p in paths)))


async def sequential_reads(client: httpx.AsyncClient, paths: list[str], repeat: int) -> list[float]:
    """Each distinct path `repeat` times, one request at a time: the service time without queueing."""
    out = []
    for _ in range(repeat):
        for path in dict.fromkeys(paths):
            out += await read_burst(client, [path])
    return out


def percentiles_ms(latencies_s: list[float]) -> dict:
    ms = sorted(1e3 * x for x in latencies_s)
    q = statistics.quantiles(ms, n=100, method="inclusive")
    return {"n": len(ms), "p50_ms": round(statistics.median(ms), 2), "p99_ms": round(q[98], 2),
            "max_ms": round(ms[-1], 2)}


def http_client(base_url=None, transport=None, concurrency=CONCURRENT_READS) -> httpx.AsyncClient:
    # idle connections are dropped after 4 s, before uvicorn's 5 s keep-alive timeout closes them from the
    # server side: reusing a connection the server is closing at that moment is a client race, not an error
    limits = httpx.Limits(max_connections=concurrency, max_keepalive_connections=concurrency, keepalive_expiry=4.0)
    return httpx.AsyncClient(base_url=base_url or "http://footprint.local", transport=transport, limits=limits,
                             timeout=httpx.Timeout(30.0))


async def seed(client: httpx.AsyncClient) -> tuple[str, str]:
    """One footprint job run to success; (job id, footprint id)."""
    ids, _ = await submit_jobs(client, [small_study(100)], "seed")
    final, _ = await wait_jobs(client, ids, JOBS_BUDGET_S)
    fps = await check_jobs(client, final)
    return ids[0], fps[ids[0]]["id"]


async def load(base_url: str, proc, *, reads: int, rounds: int, jobs: int, sequential: int) -> dict:
    """The measured run against a started service; raises on any error or lost job."""
    async with http_client(base_url, concurrency=max(reads, jobs)) as client:
        start_s, health = await wait_healthy(client, proc, START_BUDGET_S)
        t_seed = time.perf_counter()
        _, footprint_id = await seed(client)
        seed_s = time.perf_counter() - t_seed
        paths = read_paths(footprint_id, reads)
        # each endpoint once, one at a time: its first answer fills the service's caches (the built-in
        # vehicles' (L/D)max is computed on first use); reported apart, not in the percentiles
        first = {}
        for path in dict.fromkeys(paths):
            first[path.replace(footprint_id, "{id}")] = round(1e3 * (await read_burst(client, [path]))[0], 1)
        load_before = os.getloadavg()[0]
        one_at_a_time = await sequential_reads(client, paths, sequential)
        await read_burst(client, paths)  # open the connections (not measured)
        t_reads = time.perf_counter()
        alone = []
        for _ in range(rounds):
            alone += await read_burst(client, paths)
        reads_s = time.perf_counter() - t_reads
        by_path = {}
        for lat, path in zip(alone, paths * rounds):
            by_path.setdefault(path.replace(footprint_id, "{id}"), []).append(lat)

        t0 = time.perf_counter()
        studies = [small_study(i) for i in range(jobs)]
        submitting = asyncio.create_task(submit_jobs(client, studies, "load"))
        during = await read_burst(client, paths)
        ids, submit_s = await submitting
        final, _ = await wait_jobs(client, ids, JOBS_BUDGET_S)
        jobs_wall = time.perf_counter() - t0
        fps = await check_jobs(client, final)
        total = _check(await client.get("/api/jobs", params={"limit": 1}), 200, "GET /api/jobs")["total"]
        assert total == jobs + 1, f"{total} jobs stored, expected {jobs + 1}"
    trajectories = sum(fp["trajectories"] for fp in fps.values())
    return {
        "service_start_to_healthy_s": round(start_s, 2),
        "seed_job_s": round(seed_s, 2),
        "read_bursts_s": round(reads_s, 2),
        "first_read_ms": first,
        "load_average_1min_before": round(load_before, 2),
        "cluster_workers": health["cluster"]["workers"],
        "reads": {"concurrent": reads, "rounds": rounds, "mix": sorted(set(p.replace(footprint_id, "{id}")
                                                                            for p in paths)),
                  "errors": 0, **percentiles_ms(alone),
                  "by_path": {k: percentiles_ms(v) for k, v in by_path.items()}},
        "reads_one_at_a_time": percentiles_ms(one_at_a_time),
        "reads_while_jobs_run": {"concurrent": reads, "errors": 0, **percentiles_ms(during)},
        "jobs": {"submitted": jobs, "succeeded": len(final), "lost": jobs - len(fps),
                 "footprints_stored": len(fps), "trajectories": trajectories,
                 "submit_p50_ms": round(1e3 * statistics.median(submit_s), 1),
                 "submit_max_ms": round(1e3 * max(submit_s), 1),
                 "first_submission_to_last_success_s": round(jobs_wall, 2),
                 "jobs_per_s": round(jobs / jobs_wall, 2),
                 "trajectories_per_s": round(trajectories / jobs_wall, 1)},
    }


async def in_process_reads(db_copy: Path, *, reads: int, rounds: int, sequential: int) -> dict:
    """The same read bursts through httpx.ASGITransport into create_app() in this process."""
    from footprint.service.app import create_app
    from footprint.service.settings import Settings

    app = create_app(Settings(database_url=f"sqlite:///{db_copy}", dask_workers=1))
    async with app.router.lifespan_context(app):
        async with http_client(transport=httpx.ASGITransport(app=app), concurrency=reads) as client:
            items = _check(await client.get("/api/footprints", params={"limit": 1}), 200, "GET /api/footprints")
            paths = read_paths(items["items"][0]["id"], reads)
            for path in dict.fromkeys(paths):
                await read_burst(client, [path])
            one_at_a_time = await sequential_reads(client, paths, sequential)
            await read_burst(client, paths)
            lat = []
            for _ in range(rounds):
                lat += await read_burst(client, paths)
    return {"concurrent": percentiles_ms(lat), "one_at_a_time": percentiles_ms(one_at_a_time)}


def run(*, reads: int = CONCURRENT_READS, rounds: int = ROUNDS, jobs: int = JOBS, workers: int = 2,
        sequential: int = SEQUENTIAL_REPEAT, baseline: bool = True, budget_s: float = TOTAL_BUDGET_S) -> dict:
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="footprint-load-") as tmp:
        workdir = Path(tmp)
        with running_service(workdir, workers=workers) as (base_url, db, log, proc):
            try:
                figures = asyncio.run(asyncio.wait_for(load(base_url, proc, reads=reads, rounds=rounds, jobs=jobs,
                                                            sequential=sequential),
                                                       budget_s))
            except BaseException:
                sys.stderr.write(f"--- footprint serve log ---\n{log.read_text()[-4000:]}\n")
                raise
            t_stop = time.perf_counter()
        figures["service_stop_s"] = round(time.perf_counter() - t_stop, 2)
        if baseline:
            db_copy = workdir / "in_process.db"
            shutil.copy(db, db_copy)
            left = budget_s - (time.perf_counter() - t0)
            t_base = time.perf_counter()
            figures["in_process_asgi_reads"] = asyncio.run(asyncio.wait_for(
                in_process_reads(db_copy, reads=reads, rounds=rounds, sequential=sequential), max(left, 1.0)))
            figures["in_process_asgi_reads"]["with_its_start_and_stop_s"] = round(time.perf_counter() - t_base, 1)
            base = figures["in_process_asgi_reads"]
            figures["loopback_over_in_process"] = {
                "concurrent_p50": round(figures["reads"]["p50_ms"] / base["concurrent"]["p50_ms"], 2),
                "concurrent_p99": round(figures["reads"]["p99_ms"] / base["concurrent"]["p99_ms"], 2),
                "one_at_a_time_p50": round(figures["reads_one_at_a_time"]["p50_ms"] / base["one_at_a_time"]["p50_ms"], 2),
            }
    figures["total_s"] = round(time.perf_counter() - t0, 1)
    if figures["total_s"] > budget_s:
        raise AssertionError(f"the run took {figures['total_s']} s, over its {budget_s} s budget")
    return figures


def main():
    figures = run()
    result = {
        "what": "footprint serve (uvicorn, SQLite, LocalCluster of 2 workers) on 127.0.0.1, httpx.AsyncClient",
        "baseline": "the same reads through httpx.ASGITransport into create_app() in-process (no socket, no uvicorn)",
        "cores": os.cpu_count(),
        "machine": platform.machine(),
        **figures,
    }
    from _timing import save_result  # run as a script: bench/ is on the path (the tests import this module)

    save_result("service_load", result)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
