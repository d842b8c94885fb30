"""The web service under load, on loopback: 100 and 200 concurrent readers while 20 footprint jobs run.

Starts the real service as a subprocess (`footprint serve --port FREE --database-url sqlite:///TMP
--workers 2 [--api-processes N]`: uvicorn, SQLite, a Dask LocalCluster of 2 worker processes), waits for
/api/health, seeds one footprint job, then with httpx.AsyncClient over 127.0.0.1:

1. reads alone: each endpoint once (its first answer fills the service's caches: reported apart as
   first_read_ms), then ROUNDS bursts of 200 concurrent GETs, a quarter each of /api/footprints,
   /api/footprints/{id}, /api/vehicles and /api/health;
2. for each of READERS (100, 200) concurrent readers: 20 footprint jobs submitted at once (small
   single-parameter studies of the Table 2 case, each a different bank set) and, until the last of them
   ends, that many readers each sending the same mix one GET after another (a closed loop: a reader
   waits for its answer before it asks again); every job must reach `succeeded` and own exactly one
   stored footprint with its points. A read that is not a 200 or fails in transport is counted as an
   error (by kind), not raised;
3. with --long-jobs N, for each readers count: N dispersion jobs (one task each, so each holds a worker for
   a minute or more), and once all of them run, that many readers for WINDOW_S (20 s); no job may end inside the
   window; then they are cancelled, must end `cancelled`, and the cluster must be back at 2 workers.

No job may be lost. Reported: p50/p99/max latency of the reads (alone, and while the jobs run) with the
error counts, the job throughput (jobs and trajectories per second from the first submission to the last
success), and each endpoint's reads one at a time (the service time without queueing). Baseline, in this process
after the server has stopped: the same reads (bursts and one at a time) sent to the same app (create_app on a copy of
the same database) through httpx.ASGITransport, i.e. with no sockets, no HTTP parsing and no uvicorn; the ratios
(loopback_over_in_process) say what the loopback HTTP server in its own process adds. Bounded: the whole run stops
with an error past TOTAL_BUDGET_S (4 min).

    python3 bench/bench_service_load.py [--api-processes N] [--code DIR] [--label NAME] [--readers N ...]
                                        [--jobs N] [--long-jobs N] [--postgres-url URL]
        # prints the figures, writes bench/results/service_load[-NAME].json; --code: serve another checkout's
        # backend/ (the "before" of a change, measured by this same script; its migrations/ beside it);
        # --postgres-url: a new database on that server for the run, dropped afterwards (else a SQLite file)
        # the issue 24 figures: --readers 200 --jobs 0 --long-jobs 2 [--postgres-url ...]

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
from contextlib import asynccontextmanager, contextmanager
from pathlib import Path

import httpx

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CASE = json.loads((ROOT / "examples" / "table2_lod22.json").read_text())
CONCURRENT_READS = 200
READERS = (100, 200)  # closed-loop readers while the jobs run
ROUNDS = 3
SEQUENTIAL_REPEAT = 10  # one-at-a-time reads of each endpoint (the service time without queueing)
JOBS = 20
TOTAL_BUDGET_S = 240.0
START_BUDGET_S = 60.0
JOBS_BUDGET_S = 60.0
WINDOW_S = 20.0  # readers measured while the long jobs are running
# examples/disperse_lod189.json in one task (~45,000 flights, a minute or two on one core): each long job runs on a
# worker of its own, and none ends inside the window
LONG_DISPERSION = json.loads((ROOT / "examples" / "disperse_lod189.json").read_text()) | {
    "samples": 2048,
    "chunk_samples": 2048,
}


def small_study(i: int) -> dict:
    """A small footprint study: the Table 2 case, 3 bank settings (one of them different per job), one half."""
    return {
        "case": CASE,
        "method": "single_parameter",
        "bank0_deg": [0.0, 30.0 + i, 90.0],
        "min_range": "zero_lift",
        "mirror": False,
    }


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextmanager
def fresh_database(workdir: Path, server_url: str | None):
    """A new empty database: a SQLite file in `workdir`, or (given a Postgres URL) a new database on that server,
    dropped afterwards; yields its SQLAlchemy URL."""
    if server_url is None:
        yield f"sqlite:///{workdir / 'load.db'}"
        return
    import sqlalchemy as sa

    url = sa.engine.make_url(server_url)
    name = f"footprint_load_{os.getpid()}_{int(time.time())}"
    admin = sa.create_engine(url, isolation_level="AUTOCOMMIT")
    with admin.connect() as c:
        c.execute(sa.text(f'CREATE DATABASE "{name}"'))
    try:
        yield url.set(database=name).render_as_string(hide_password=False)
    finally:
        with admin.connect() as c:
            c.execute(sa.text(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)'))
        admin.dispose()


@contextmanager
def running_service(
    workdir: Path, database_url: str, *, workers: int = 2, api_processes: int = 1, code: Path | None = None
):
    """`footprint serve` on a free loopback port over `database_url` (the package from `code`, a backend/ folder,
    when given); yields (base_url, log_path, process)."""
    port = _free_port()
    log = workdir / "serve.log"
    cmd = [
        sys.executable,
        "-m",
        "footprint.cli",
        "serve",
        "--host",
        "127.0.0.1",
        "--port",
        str(port),
        "--database-url",
        database_url,
        "--workers",
        str(workers),
    ]
    if api_processes > 1:
        cmd += ["--api-processes", str(api_processes)]
    env = {k: v for k, v in os.environ.items() if not k.startswith("FOOTPRINT_")}
    if code is not None:
        env["PYTHONPATH"] = os.pathsep.join([str(code)] + [p for p in [env.get("PYTHONPATH")] if p])
    with open(log, "w") as out:
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, cwd=workdir, env=env, start_new_session=True)
    try:
        yield f"http://127.0.0.1:{port}", log, proc
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait(timeout=10)


async def wait_healthy(client: httpx.AsyncClient, proc, budget_s: float, workers: int = 1) -> tuple[float, dict]:
    """Seconds until /api/health answers 200 with a working database and a cluster of `workers` or more."""
    t0 = time.perf_counter()
    last = None
    while time.perf_counter() - t0 < budget_s:
        if proc is not None and proc.poll() is not None:
            raise RuntimeError(f"footprint serve exited with {proc.returncode}")
        try:
            r = await client.get("/api/health", timeout=5)
            last = r.json()
            if (
                r.status_code == 200
                and last["database"]["ok"]
                and last["cluster"]["ok"]
                and last["cluster"]["workers"] >= workers
            ):
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


def _template(path: str, paths: list[str]) -> str:
    """The path with the footprint's id as {id} (the mix's second path holds it)."""
    return path.replace(paths[1].rsplit("/", 1)[1], "{id}")


def read_paths(footprint_id: str, n: int) -> list[str]:
    mix = ["/api/footprints", f"/api/footprints/{footprint_id}", "/api/vehicles", "/api/health"]
    return [mix[i % len(mix)] for i in range(n)]


def httpx_get(client: httpx.AsyncClient):
    """GET through httpx: the status code, or the transport error's kind."""

    async def get(path: str) -> int | str:
        try:
            return (await client.get(path)).status_code
        except httpx.TransportError as exc:
            return type(exc).__name__

    return get


@asynccontextmanager
async def aiohttp_get(base_url: str, concurrency: int):
    """GET through aiohttp (the readers' client: httpx's own work per request capped it near 150 requests/s at 200
    connections on this machine, with the server mostly idle); the status code, or the transport error's kind."""
    import aiohttp

    connector = aiohttp.TCPConnector(limit=concurrency, keepalive_timeout=4.0)  # before uvicorn's 5 s (http_client)
    async with aiohttp.ClientSession(base_url, connector=connector, timeout=aiohttp.ClientTimeout(total=30)) as session:

        async def get(path: str) -> int | str:
            try:
                async with session.get(path) as r:
                    await r.read()
                    return r.status
            except (TimeoutError, aiohttp.ClientError) as exc:
                return type(exc).__name__

        yield get


async def read_burst(get, paths: list[str]) -> list[float]:
    """All GETs at once; their latencies in seconds. Any non-200 answer or transport error raises."""

    async def one(path):
        t0 = time.perf_counter()
        status = await get(path)
        dt = time.perf_counter() - t0
        if status != 200:
            raise AssertionError(f"GET {path}: {status}")
        return dt

    return list(await asyncio.gather(*(one(p) for p in paths)))


async def readers_until(
    get, paths: list[str], readers: int, done: asyncio.Event
) -> tuple[dict[str, list[float]], dict[str, int]]:
    """`readers` closed-loop readers, each sending the mix one GET after another until `done`; ({path: latencies of
    its 200s in seconds}, {error kind: count})."""
    latencies: dict[str, list[float]] = {p: [] for p in paths}
    errors: dict[str, int] = {}

    async def reader(i):
        k = i
        while not done.is_set():
            path = paths[k % len(paths)]
            k += 1
            t0 = time.perf_counter()
            status = await get(path)
            if status == 200:
                latencies[path].append(time.perf_counter() - t0)
            else:
                kind = f"HTTP {status}" if isinstance(status, int) else status
                errors[kind] = errors.get(kind, 0) + 1

    await asyncio.gather(*(reader(i) for i in range(readers)))
    return latencies, errors


async def readers_during_jobs(
    client: httpx.AsyncClient, get, paths: list[str], readers: int, jobs: int, label: str
) -> dict:
    """`jobs` footprint jobs submitted at once (through `client`) and `readers` readers (through `get`) until the
    last job ends; every job must succeed and be stored once."""
    done = asyncio.Event()
    reading = asyncio.create_task(readers_until(get, paths, readers, done))
    t0 = time.perf_counter()
    try:
        ids, submit_s = await submit_jobs(client, [small_study(i) for i in range(jobs)], label)
        final, _ = await wait_jobs(client, ids, JOBS_BUDGET_S)
    finally:
        done.set()
        by_path, errors = await reading
    latencies = [x for v in by_path.values() for x in v]
    wall = time.perf_counter() - t0
    fps = await check_jobs(client, final)
    trajectories = sum(fp["trajectories"] for fp in fps.values())
    return {
        "readers": readers,
        "errors": sum(errors.values()),
        "error_kinds": errors,
        **percentiles_ms(latencies),
        "reads_per_s": round(len(latencies) / wall, 1),
        "jobs": {
            "submitted": jobs,
            "succeeded": len(final),
            "lost": jobs - len(fps),
            "footprints_stored": len(fps),
            "trajectories": trajectories,
            "submit_p50_ms": round(1e3 * statistics.median(submit_s), 1),
            "submit_max_ms": round(1e3 * max(submit_s), 1),
            "first_submission_to_last_success_s": round(wall, 2),
            "jobs_per_s": round(jobs / wall, 2),
            "trajectories_per_s": round(trajectories / wall, 1),
        },
    }


async def readers_during_long_jobs(
    client: httpx.AsyncClient, get, paths: list[str], readers: int, jobs: int, window_s: float
) -> dict:
    """`jobs` dispersion jobs (minutes each on 2 workers) and, once all of them run, `readers` readers for
    `window_s`; then the jobs are cancelled: each must end `cancelled` and the cluster keep its workers."""
    ids = []
    for i in range(jobs):
        r = await client.post(
            "/api/jobs", json={"kind": "dispersion", "study": LONG_DISPERSION | {"seed": 100 + i}, "name": f"long-{i}"}
        )
        ids.append(_check(r, 202, f"POST /api/jobs long #{i}")["id"])
    t0 = time.perf_counter()
    while not all(
        d["status"] == "running" for d in [_check(await client.get(f"/api/jobs/{i}"), 200, "GET job") for i in ids]
    ):
        if time.perf_counter() - t0 > START_BUDGET_S:
            raise TimeoutError(f"{jobs} long jobs not all running after {START_BUDGET_S} s")
        await asyncio.sleep(0.2)
    done = asyncio.Event()
    reading = asyncio.create_task(readers_until(get, paths, readers, done))
    await asyncio.sleep(window_s)
    done.set()
    by_path, errors = await reading
    latencies = [x for v in by_path.values() for x in v]
    running = [(await client.get(f"/api/jobs/{i}")).json()["status"] for i in ids]
    if running != ["running"] * jobs:
        raise AssertionError(f"a long job ended inside the window ({running}): the window did not run beside {jobs}")
    for i in ids:
        _check(await client.delete(f"/api/jobs/{i}"), 200, f"DELETE /api/jobs/{i}")
    final, _ = await wait_jobs(client, ids, JOBS_BUDGET_S)
    assert all(d["status"] == "cancelled" for d in final.values()), [d["status"] for d in final.values()]
    await wait_healthy(client, None, START_BUDGET_S, workers=2)  # a stopped task's worker is replaced
    return {
        "readers": readers,
        "jobs_running": jobs,
        "window_s": window_s,
        "errors": sum(errors.values()),
        "error_kinds": errors,
        **percentiles_ms(latencies),
        "reads_per_s": round(len(latencies) / window_s, 1),
        "by_path": {_template(p, paths): percentiles_ms(v) for p, v in by_path.items()},
    }


async def sequential_reads(get, paths: list[str], repeat: int) -> list[float]:
    """Each distinct path `repeat` times, one request at a time: the service time without queueing."""
    out = []
    for _ in range(repeat):
        for path in dict.fromkeys(paths):
            out += await read_burst(get, [path])
    return out


def percentiles_ms(latencies_s: list[float]) -> dict:
    ms = sorted(1e3 * x for x in latencies_s)
    q = statistics.quantiles(ms, n=100, method="inclusive")
    return {
        "n": len(ms),
        "p50_ms": round(statistics.median(ms), 2),
        "p99_ms": round(q[98], 2),
        "max_ms": round(ms[-1], 2),
    }


def http_client(base_url=None, transport=None, concurrency=CONCURRENT_READS) -> httpx.AsyncClient:
    # idle connections are dropped after 4 s, before uvicorn's 5 s keep-alive timeout closes them from the
    # server side: reusing a connection the server is closing at that moment is a client race, not an error
    limits = httpx.Limits(max_connections=concurrency, max_keepalive_connections=concurrency, keepalive_expiry=4.0)
    return httpx.AsyncClient(
        base_url=base_url or "http://localhost", transport=transport, limits=limits, timeout=httpx.Timeout(30.0)
    )


async def seed(client: httpx.AsyncClient) -> tuple[str, str]:
    """One footprint job run to success; (job id, footprint id)."""
    ids, _ = await submit_jobs(client, [small_study(100)], "seed")
    final, _ = await wait_jobs(client, ids, JOBS_BUDGET_S)
    fps = await check_jobs(client, final)
    return ids[0], fps[ids[0]]["id"]


async def load(
    base_url: str,
    proc,
    *,
    reads: int,
    rounds: int,
    jobs: int,
    sequential: int,
    readers: tuple[int, ...] = READERS,
    long_jobs: int = 0,
    window_s: float = WINDOW_S,
) -> dict:
    """The measured run against a started service; raises on a lost job (read errors are counted)."""
    async with (
        http_client(base_url, concurrency=jobs + 2) as client,
        aiohttp_get(base_url, max((reads, *readers))) as get,
    ):
        start_s, health = await wait_healthy(client, proc, START_BUDGET_S)
        t_seed = time.perf_counter()
        _, footprint_id = await seed(client)
        seed_s = time.perf_counter() - t_seed
        paths = read_paths(footprint_id, reads)
        # each endpoint once, one at a time: its first answer fills the service's caches (the built-in
        # vehicles' (L/D)max is computed on first use); reported apart, not in the percentiles
        first = {}
        for path in dict.fromkeys(paths):
            first[path.replace(footprint_id, "{id}")] = round(1e3 * (await read_burst(get, [path]))[0], 1)
        load_before = os.getloadavg()[0]
        one_at_a_time = await sequential_reads(get, paths, sequential)
        await read_burst(get, paths)  # open the connections (not measured)
        t_reads = time.perf_counter()
        alone = []
        for _ in range(rounds):
            alone += await read_burst(get, paths)
        reads_s = time.perf_counter() - t_reads
        by_path = {}
        for lat, path in zip(alone, paths * rounds):
            by_path.setdefault(path.replace(footprint_id, "{id}"), []).append(lat)
        during = {str(n): await readers_during_jobs(client, get, paths, n, jobs, f"load-{n}") for n in readers if jobs}
        during_long = {
            str(n): await readers_during_long_jobs(client, get, paths, n, long_jobs, window_s)
            for n in readers
            if long_jobs
        }
        total = _check(await client.get("/api/jobs", params={"limit": 1}), 200, "GET /api/jobs")["total"]
        expected = (jobs + long_jobs) * len(readers) + 1
        assert total == expected, f"{total} jobs stored, expected {expected}"
    return {
        "service_start_to_healthy_s": round(start_s, 2),
        "seed_job_s": round(seed_s, 2),
        "read_bursts_s": round(reads_s, 2),
        "first_read_ms": first,
        "load_average_1min_before": round(load_before, 2),
        "cluster_workers": health["cluster"]["workers"],
        "reads": {
            "concurrent": reads,
            "rounds": rounds,
            "mix": sorted(set(p.replace(footprint_id, "{id}") for p in paths)),
            "errors": 0,
            **percentiles_ms(alone),
            "by_path": {k: percentiles_ms(v) for k, v in by_path.items()},
        },
        "reads_one_at_a_time": percentiles_ms(one_at_a_time),
        "readers_while_jobs_run": during,
        "readers_while_long_jobs_run": during_long,
    }


async def in_process_reads(database_url: str, *, reads: int, rounds: int, sequential: int) -> dict:
    """The same read bursts through httpx.ASGITransport into create_app() in this process."""
    from footprint.service.app import create_app
    from footprint.service.settings import Settings

    app = create_app(Settings(database_url=database_url, dask_workers=1))
    async with app.router.lifespan_context(app):
        async with http_client(transport=httpx.ASGITransport(app=app), concurrency=reads) as client:
            items = _check(await client.get("/api/footprints", params={"limit": 1}), 200, "GET /api/footprints")
            paths = read_paths(items["items"][0]["id"], reads)
            get = httpx_get(client)
            for path in dict.fromkeys(paths):
                await read_burst(get, [path])
            one_at_a_time = await sequential_reads(get, paths, sequential)
            await read_burst(get, paths)
            lat = []
            for _ in range(rounds):
                lat += await read_burst(get, paths)
    return {"concurrent": percentiles_ms(lat), "one_at_a_time": percentiles_ms(one_at_a_time)}


def run(
    *,
    reads: int = CONCURRENT_READS,
    rounds: int = ROUNDS,
    jobs: int = JOBS,
    workers: int = 2,
    sequential: int = SEQUENTIAL_REPEAT,
    baseline: bool = True,
    budget_s: float = TOTAL_BUDGET_S,
    readers: tuple[int, ...] = READERS,
    api_processes: int = 1,
    code: Path | None = None,
    long_jobs: int = 0,
    window_s: float = WINDOW_S,
    postgres_url: str | None = None,
) -> dict:
    t0 = time.perf_counter()
    with (
        tempfile.TemporaryDirectory(prefix="footprint-load-") as tmp,
        fresh_database(Path(tmp), postgres_url) as database_url,
    ):
        workdir = Path(tmp)
        with running_service(workdir, database_url, workers=workers, api_processes=api_processes, code=code) as (
            base_url,
            log,
            proc,
        ):
            try:
                figures = asyncio.run(
                    asyncio.wait_for(
                        load(
                            base_url,
                            proc,
                            reads=reads,
                            rounds=rounds,
                            jobs=jobs,
                            sequential=sequential,
                            readers=readers,
                            long_jobs=long_jobs,
                            window_s=window_s,
                        ),
                        budget_s,
                    )
                )
            except BaseException:
                sys.stderr.write(f"--- footprint serve log ---\n{log.read_text()[-4000:]}\n")
                raise
            t_stop = time.perf_counter()
        figures["service_stop_s"] = round(time.perf_counter() - t_stop, 2)
        if baseline:
            if postgres_url is None:  # a copy: the in-process app's own engine and migrations start on it
                shutil.copy(workdir / "load.db", workdir / "in_process.db")
                database_url = f"sqlite:///{workdir / 'in_process.db'}"
            left = budget_s - (time.perf_counter() - t0)
            t_base = time.perf_counter()
            figures["in_process_asgi_reads"] = asyncio.run(
                asyncio.wait_for(
                    in_process_reads(database_url, reads=reads, rounds=rounds, sequential=sequential), max(left, 1.0)
                )
            )
            figures["in_process_asgi_reads"]["with_its_start_and_stop_s"] = round(time.perf_counter() - t_base, 1)
            base = figures["in_process_asgi_reads"]
            figures["loopback_over_in_process"] = {
                "concurrent_p50": round(figures["reads"]["p50_ms"] / base["concurrent"]["p50_ms"], 2),
                "concurrent_p99": round(figures["reads"]["p99_ms"] / base["concurrent"]["p99_ms"], 2),
                "one_at_a_time_p50": round(
                    figures["reads_one_at_a_time"]["p50_ms"] / base["one_at_a_time"]["p50_ms"], 2
                ),
            }
    figures["total_s"] = round(time.perf_counter() - t0, 1)
    if figures["total_s"] > budget_s:
        raise AssertionError(f"the run took {figures['total_s']} s, over its {budget_s} s budget")
    return figures


def main():
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    parser.add_argument("--api-processes", type=int, default=1, help="footprint serve --api-processes")
    parser.add_argument("--code", type=Path, help="a backend/ folder to serve instead of this checkout's")
    parser.add_argument("--label", default="", help="results file suffix: service_load-LABEL.json")
    parser.add_argument(
        "--postgres-url",
        help="a Postgres server (e.g. postgresql+psycopg://postgres@127.0.0.1:5432/"
        "test): the run gets a new database on it, dropped afterwards",
    )
    parser.add_argument("--readers", type=int, nargs="+", default=list(READERS), help="closed-loop readers")
    parser.add_argument("--jobs", type=int, default=JOBS, help="small footprint jobs per readers count (0: none)")
    parser.add_argument(
        "--long-jobs",
        type=int,
        default=0,
        help=f"dispersion jobs that run through a {WINDOW_S:.0f} s window of readers, then are cancelled (0: none)",
    )
    args = parser.parse_args()
    figures = run(
        api_processes=args.api_processes,
        code=args.code,
        baseline=args.code is None,
        readers=tuple(args.readers),
        jobs=args.jobs,
        long_jobs=args.long_jobs,
        postgres_url=args.postgres_url,
        budget_s=TOTAL_BUDGET_S + len(args.readers) * (WINDOW_S + 40),
    )
    database = "Postgres" if args.postgres_url else "SQLite"
    result = {
        "what": f"footprint serve (uvicorn in {args.api_processes} process(es), {database}, LocalCluster of 2 workers) "
        "on 127.0.0.1, aiohttp readers",
        "code": str(args.code or "this checkout"),
        "baseline": "the same reads through httpx.ASGITransport into create_app() in-process (no socket, no uvicorn)",
        "cores": os.cpu_count(),
        "machine": platform.machine(),
        **figures,
    }
    from _timing import save_result  # run as a script: bench/ is on the path (the tests import this module)

    save_result("service_load" + (f"-{args.label}" if args.label else ""), result)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
