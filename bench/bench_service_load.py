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
   a minute or more), and once all of them run, each read of the mix one at a time (the service time beside the
   jobs), then that many readers for --window-s (20 s); no job may end inside the window (one that does, or a
   service that stops answering, is reported with the figures so far, and the run fails after writing them); then
   they are cancelled, must end `cancelled`, and the cluster must be back at 2 workers; then the baseline in the same
   process: the same readers on the same paths for the same window with no job running (during_over_no_job). Beside
   each window: the 1-minute load average at its start and its end (the machine is shared), the serving process's
   CPU seconds (a core's worth is 1 per second) and the readers' own.

--mix page (issue 49): the reads the map page does instead of the four above, each route an equal share: the
footprint list (limit=200), a footprint as JSON, GeoJSON and CSV (three stored, one after another), the job list and
the page's succeeded-dispersions list, a running long job and a succeeded one (GET /api/jobs/{id}), /api/health and
/api/vehicles. In step 1 its bursts count a failed read as an error too (issue 49's "before" answered none).

No job may be lost. Reported: p50/p99/max latency of the reads (alone, and while the jobs run) with the
error counts, the job throughput (jobs and trajectories per second from the first submission to the last
success), and each endpoint's reads one at a time (the service time without queueing). Baseline of the issue 24
mix, in this process after the server has stopped: the same reads (bursts and one at a time) sent to the same app
(create_app on a copy of the same database) through httpx.ASGITransport, i.e. with no sockets, no HTTP parsing and
no uvicorn; the ratios (loopback_over_in_process) say what the loopback HTTP server in its own process adds. Bounded:
the whole run stops with an error past TOTAL_BUDGET_S (8 min; a guard against a hang on a loaded machine, not a
bound on speed).

    python3 bench/bench_service_load.py [--api-processes N] [--code DIR] [--label NAME] [--readers N ...]
                                        [--jobs N] [--long-jobs N] [--window-s S] [--mix issue24|page]
                                        [--postgres-url URL]
        # prints the figures, writes bench/results/service_load[-NAME].json; --code: serve another checkout's
        # backend/ (the "before" of a change, measured by this same script; its migrations/ beside it);
        # --postgres-url: a new database on that server for the run, dropped afterwards (else a SQLite file)
        # the issue 24 figures: --readers 200 --jobs 0 --long-jobs 2 [--postgres-url ...]
        # the issue 49 figures: --readers 200 --jobs 0 --long-jobs 2 --window-s 40 --mix page [--postgres-url ...]

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
TOTAL_BUDGET_S = 480.0
START_BUDGET_S = 180.0  # a local cluster started at load 12 took over a minute
JOBS_BUDGET_S = 120.0
WINDOW_S = 20.0  # readers measured while the long jobs are running (--window-s)
SEQUENTIAL_BESIDE_JOBS = 5  # one-at-a-time reads of each path while the long jobs run
SEEDED_FOOTPRINTS = 3  # stored before the page mix's reads (one job each)
MIXES = ("issue24", "page")
# examples/disperse_lod189.json in one task (~90,000 flights, minutes on one core at the workers' nice 10): each long
# job runs on a worker of its own, and none ends inside the window
LONG_DISPERSION = json.loads((ROOT / "examples" / "disperse_lod189.json").read_text()) | {
    "samples": 4096,
    "chunk_samples": 4096,
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


def _route(path: str, names: dict[str, str]) -> str:
    """The path with each id in `names` replaced by its name ({id}, {running}...): the route it reads."""
    for stored_id, name in names.items():
        path = path.replace(stored_id, name)
    return path


def read_paths(footprint_id: str, n: int) -> list[str]:
    mix = ["/api/footprints", f"/api/footprints/{footprint_id}", "/api/vehicles", "/api/health"]
    return [mix[i % len(mix)] for i in range(n)]


def page_paths(footprint_ids: list[str], running_ids: list[str], succeeded_id: str, n: int) -> list[str]:
    """`n` GETs of the map page's reads, each route an equal share, its ids taken in turn (--mix page)."""
    routes = [
        lambda k: "/api/footprints?limit=200",
        lambda k: f"/api/footprints/{footprint_ids[k % len(footprint_ids)]}",
        lambda k: f"/api/footprints/{footprint_ids[k % len(footprint_ids)]}?format=geojson",
        lambda k: f"/api/footprints/{footprint_ids[k % len(footprint_ids)]}?format=csv",
        lambda k: f"/api/jobs/{running_ids[k % len(running_ids)]}",
        lambda k: f"/api/jobs/{succeeded_id}",
        lambda k: "/api/jobs?limit=50",
        lambda k: "/api/jobs?kind=dispersion&status=succeeded&limit=50",
        lambda k: "/api/health",
        lambda k: "/api/vehicles",
    ]
    return [routes[i % len(routes)](i // len(routes)) for i in range(n)]


def _say(what: str) -> None:
    """A line of progress on stderr."""
    print(f"{time.strftime('%H:%M:%S')} {what}", file=sys.stderr, flush=True)


def _cpu_s(pid: int) -> float:
    """The process's CPU seconds so far, user and system, all its threads (/proc; 0 where there is none)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime, stime: fields 14 and 15


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


async def read_burst(get, paths: list[str], errors: dict[str, int] | None = None) -> list[float | None]:
    """All GETs at once; their latencies in seconds. Any non-200 answer or transport error raises, or with `errors`
    is counted there by kind (its latency None)."""

    async def one(path):
        t0 = time.perf_counter()
        status = await get(path)
        dt = time.perf_counter() - t0
        if status != 200:
            if errors is None:
                raise AssertionError(f"GET {path}: {status}")
            kind = f"HTTP {status}" if isinstance(status, int) else status
            errors[kind] = errors.get(kind, 0) + 1
            return None
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


async def reading_window(get, paths: list[str], readers: int, window_s: float, names: dict, pid: int | None) -> dict:
    """`readers` closed-loop readers of `paths` for `window_s`: percentiles overall and by route, reads a second, the
    load average at the start and the end, and the CPU the serving process (`pid`) and these readers used."""
    load_start, cpu_start, own_start = os.getloadavg()[0], _cpu_s(pid) if pid else 0.0, time.process_time()
    _say(f"{readers} readers for {window_s:g} s at load {load_start:.1f}")
    done = asyncio.Event()
    reading = asyncio.create_task(readers_until(get, paths, readers, done))
    t0 = time.perf_counter()
    await asyncio.sleep(window_s)
    done.set()
    by_path, errors = await reading
    wall = time.perf_counter() - t0
    cpu, own = (_cpu_s(pid) - cpu_start if pid else None), time.process_time() - own_start
    latencies = [x for v in by_path.values() for x in v]
    by_route: dict[str, list[float]] = {}
    for path, lat in by_path.items():
        by_route.setdefault(_route(path, names), []).extend(lat)
    return {
        "readers": readers,
        "window_s": window_s,
        "errors": sum(errors.values()),
        "error_kinds": errors,
        **percentiles_ms(latencies),
        "reads_per_s": round(len(latencies) / wall, 1),
        "load_average_1min": {"start": round(load_start, 2), "end": round(os.getloadavg()[0], 2)},
        "serving_process_cpu_s_per_s": None if cpu is None else round(cpu / wall, 2),
        "serving_process_cpu_ms_per_read": None if cpu is None else round(1e3 * cpu / max(len(latencies), 1), 2),
        "readers_cpu_s_per_s": round(own / wall, 2),
        "by_path": {route: percentiles_ms(v) for route, v in by_route.items()},
    }


async def one_at_a_time_by_route(get, paths: list[str], repeat: int, names: dict) -> dict:
    """Each distinct path `repeat` times, one request at a time: each route's service time without queueing."""
    by_route: dict[str, list[float]] = {}
    for _ in range(repeat):
        for path in dict.fromkeys(paths):
            by_route.setdefault(_route(path, names), []).extend(await read_burst(get, [path]))
    return {route: percentiles_ms(v) for route, v in by_route.items()}


async def readers_during_long_jobs(
    client: httpx.AsyncClient, get, paths_for, readers: int, jobs: int, window_s: float, pid: int | None
) -> dict:
    """`jobs` dispersion jobs (minutes each on 2 workers) and, once all of them run, each path one at a time, then
    `readers` readers for `window_s`; then the jobs are cancelled (each must end `cancelled` and the cluster keep its
    workers), and the same readers read the same paths for as long with no job: the baseline. `paths_for(running
    ids)`: (the paths, {id: its name in a route})."""
    try:
        ids = await _start_long_jobs(client, jobs)
    except (httpx.TransportError, AssertionError, TimeoutError) as exc:  # a service stuck before the window
        return {"jobs_running": 0, "after_window_error": f"before the window: {type(exc).__name__}: {exc}"[:300]}
    _say(f"{jobs} long jobs running")
    paths, names = paths_for(ids)
    beside_jobs = await one_at_a_time_by_route(get, paths, SEQUENTIAL_BESIDE_JOBS, names)
    during = await reading_window(get, paths, readers, window_s, names, pid)
    figures = {"jobs_running": jobs, **during, "one_at_a_time_beside_jobs": beside_jobs}
    try:
        return figures | await _after_long_jobs(client, get, ids, paths, names, readers, window_s, pid, during)
    except (httpx.TransportError, AssertionError, TimeoutError) as exc:  # the figures so far, and what went wrong
        return figures | {"after_window_error": f"{type(exc).__name__}: {exc}"[:300]}


async def _start_long_jobs(client: httpx.AsyncClient, jobs: int) -> list[str]:
    """`jobs` long dispersion jobs submitted; their ids once all of them run."""
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
    return ids


async def _after_long_jobs(client, get, ids, paths, names, readers, window_s, pid, during) -> dict:
    """The long jobs' state after the window, their cancel, and the window with no job (the baseline)."""
    after = {i: _check(await client.get(f"/api/jobs/{i}"), 200, f"GET /api/jobs/{i}") for i in ids}
    # a job that ended inside the window is reported (main fails the run after writing the figures): the window did
    # not run beside all the jobs, and a job that failed there (issue 49: the connection pool) is a finding
    ended = [f"{d['status']}: {d['error']}" for d in after.values() if d["status"] != "running"]
    for i, d in after.items():
        if d["status"] == "running":
            _check(await client.delete(f"/api/jobs/{i}"), 200, f"DELETE /api/jobs/{i}")
    final, _ = await wait_jobs(client, ids, JOBS_BUDGET_S)
    cancelled = [final[i]["status"] for i, d in after.items() if d["status"] == "running"]
    assert cancelled == ["cancelled"] * len(cancelled), cancelled
    await wait_healthy(client, None, START_BUDGET_S, workers=2)  # a stopped task's worker is replaced
    alone = await reading_window(get, paths, readers, window_s, names, pid)
    return {
        "jobs_ended_inside_window": ended,
        "no_job_after_them": alone,
        "during_over_no_job": {
            "p50": round(during["p50_ms"] / alone["p50_ms"], 2),
            "p99": round(during["p99_ms"] / alone["p99_ms"], 2),
            "reads_per_s": round(during["reads_per_s"] / alone["reads_per_s"], 2),
        },
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
    if len(ms) < 2:  # a route that answered once or never in its window (a loaded machine): what there is
        return {"n": len(ms), **dict.fromkeys(("p50_ms", "p99_ms", "max_ms"), round(ms[0], 2) if ms else None)}
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
        base_url=base_url or "http://localhost", transport=transport, limits=limits, timeout=httpx.Timeout(120.0)
    )


async def seed(client: httpx.AsyncClient, n: int = 1) -> tuple[list[str], list[str]]:
    """`n` footprint jobs run to success; (their job ids, their footprint ids)."""
    ids, _ = await submit_jobs(client, [small_study(100 + i) for i in range(n)], "seed")
    final, _ = await wait_jobs(client, ids, JOBS_BUDGET_S)
    fps = await check_jobs(client, final)
    return ids, [fps[i]["id"] for i in ids]


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
    mix: str = "issue24",
    pid: int | None = None,
) -> dict:
    """The measured run against a started service (`pid`: its serving process, whose CPU is reported beside the long
    jobs' windows); raises on a lost job (read errors are counted)."""
    async with (
        http_client(base_url, concurrency=jobs + 2) as client,
        aiohttp_get(base_url, max((reads, *readers))) as get,
    ):
        start_s, health = await wait_healthy(client, proc, START_BUDGET_S)
        _say(f"healthy after {start_s:.1f} s")
        t_seed = time.perf_counter()
        job_ids, footprint_ids = await seed(client, SEEDED_FOOTPRINTS if mix == "page" else 1)
        seed_s = time.perf_counter() - t_seed
        footprint_id = footprint_ids[0]
        names = {i: "{id}" for i in footprint_ids} | {job_ids[0]: "{succeeded}"}

        def paths_for(running: list[str], n: int = reads) -> tuple[list[str], dict[str, str]]:
            if mix == "issue24":
                return read_paths(footprint_id, n), names
            return page_paths(footprint_ids, running, job_ids[0], n), names | {i: "{running}" for i in running}

        paths, _ = paths_for(job_ids[:1])
        # each endpoint once, one at a time: its first answer fills the service's caches (the built-in
        # vehicles' (L/D)max is computed on first use); reported apart, not in the percentiles
        first = {}
        for path in dict.fromkeys(paths):
            first[_route(path, names)] = round(1e3 * (await read_burst(get, [path]))[0], 1)
        load_before = os.getloadavg()[0]
        one_at_a_time = await sequential_reads(get, paths, sequential)
        one_at_a_time_by_path = await one_at_a_time_by_route(get, paths, sequential, names)
        burst_errors: dict[str, int] = {}
        await read_burst(get, paths, burst_errors)  # open the connections (not measured)
        burst_errors.clear()
        t_reads = time.perf_counter()
        bursts: list[float | None] = []
        for _ in range(rounds):
            bursts += await read_burst(get, paths, burst_errors)
        reads_s = time.perf_counter() - t_reads
        by_path: dict[str, list[float]] = {}
        for lat, path in zip(bursts, paths * rounds):
            if lat is not None:
                by_path.setdefault(_route(path, names), []).append(lat)
        alone = [x for v in by_path.values() for x in v]
        during = {str(n): await readers_during_jobs(client, get, paths, n, jobs, f"load-{n}") for n in readers if jobs}
        during_long = {
            str(n): await readers_during_long_jobs(
                client, get, lambda running, n=n: paths_for(running, n), n, long_jobs, window_s, pid
            )
            for n in readers
            if long_jobs
        }
        if not any("after_window_error" in w for w in during_long.values()):  # else the service may be stuck
            total = _check(await client.get("/api/jobs", params={"limit": 1}), 200, "GET /api/jobs")["total"]
            expected = (jobs + long_jobs) * len(readers) + len(job_ids)
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
            "mix": sorted(set(_route(p, names) for p in paths)),
            "errors": sum(burst_errors.values()),
            "error_kinds": burst_errors,
            **percentiles_ms(alone),
            "by_path": {k: percentiles_ms(v) for k, v in by_path.items()},
        },
        "reads_one_at_a_time": percentiles_ms(one_at_a_time),
        "reads_one_at_a_time_by_path": one_at_a_time_by_path,
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
    mix: str = "issue24",
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
                            mix=mix,
                            pid=proc.pid if api_processes == 1 else None,
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


def _cpu_model() -> str:
    """The CPU's model name (/proc/cpuinfo, as lscpu's "Model name")."""
    try:
        lines = Path("/proc/cpuinfo").read_text().splitlines()
    except OSError:
        return platform.processor()
    return next((line.split(":", 1)[1].strip() for line in lines if line.startswith("model name")), "")


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
        help="dispersion jobs that run through a window of readers, then are cancelled (0: none)",
    )
    parser.add_argument("--window-s", type=float, default=WINDOW_S, help="the readers' window beside the long jobs")
    parser.add_argument("--mix", choices=MIXES, default=MIXES[0], help="the reads: issue 24's four, or the page's")
    args = parser.parse_args()
    in_process = args.code is None and args.mix == "issue24"  # the page mix's baseline is its window with no job
    figures = run(
        api_processes=args.api_processes,
        code=args.code,
        baseline=in_process,
        readers=tuple(args.readers),
        jobs=args.jobs,
        long_jobs=args.long_jobs,
        window_s=args.window_s,
        postgres_url=args.postgres_url,
        mix=args.mix,
        budget_s=TOTAL_BUDGET_S + len(args.readers) * (2 * args.window_s + 60),
    )
    database = "Postgres" if args.postgres_url else "SQLite"
    result = {
        "what": f"footprint serve (uvicorn in {args.api_processes} process(es), {database}, LocalCluster of 2 workers) "
        f"on 127.0.0.1, aiohttp readers, the {args.mix} mix",
        "code": str(args.code or "this checkout"),
        "baseline": "the same reads through httpx.ASGITransport into create_app() in-process (no socket, no uvicorn)"
        if in_process
        else "the same readers on the same paths with no job running (no_job_after_them)",
        "date": time.strftime("%Y-%m-%d"),
        "cores": os.cpu_count(),
        "machine": platform.machine(),
        "cpu": _cpu_model(),
        **figures,
    }
    from _timing import save_result  # run as a script: bench/ is on the path (the tests import this module)

    save_result("service_load" + (f"-{args.label}" if args.label else ""), result)
    print(json.dumps(result, indent=2))
    wrong = {
        n: w.get("after_window_error") or w.get("jobs_ended_inside_window")
        for n, w in figures["readers_while_long_jobs_run"].items()
    }
    if any(wrong.values()):
        sys.exit(f"the long jobs' windows went wrong (figures written all the same): {wrong}")


if __name__ == "__main__":
    main()
