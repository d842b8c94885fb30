"""The doors against the kernel (issue 29 item 3): one trajectory (the Table 2 case, lod-2.2) flown by the compiled
integrator alone (trajectory._fly: the parameters packed, the entry state, the integration), by simulate(spec)
(the summary; the histories are made when first read) and with its histories read, by footprint.api.fly(dict)
(the case parsed, its spec built, flown, the summary), by the CLI's
`footprint fly CASE.json` as its command function in this process (the file read, the summary printed as JSON;
the interpreter's start-up and imports left out), and by POST /api/trajectories: through the service's ASGI app
called on an event loop in this process (the route's thread-pool hop, its middleware, the body parsed, the
answer serialized; SQLite in a temporary folder), a new run of the loop for each request and, as a server runs it, a
batch of requests on a loop that keeps running; the same with the thread-pool hop replaced by a direct call (the
route's own work); and through FastAPI's TestClient (which adds its own threads).
All in one process; rounds of batches taken in turn, each door's figure the median over the rounds of its time
over the kernel's in the same round (the machine's other work moves both alike). The target: every door within
30 % of the kernel. One part timed beside them: the POST's answer written alone (its summary and 16 histories of the
flight's rows as JSON), which every served answer pays.

    python3 bench/bench_doors.py   # bench/results/doors.json
"""

import asyncio
import contextlib
import functools
import io
import json
import os
import statistics
import tempfile
import time
import unittest.mock
from pathlib import Path

from _timing import save_result

CASE_FILE = Path(__file__).resolve().parents[1] / "examples" / "table2_lod22.json"
CASE = json.loads(CASE_FILE.read_text())
ROUNDS = 25  # batches per door, taken in turn
BATCH = 40  # calls per batch
SERVED = "POST /api/trajectories (ASGI app, its loop running)"
ANSWER_JSON = "the POST's answer written alone (trajectory_json)"


def asgi_post(app, path: str, body: bytes, state: dict):
    """A coroutine function that POSTs `body` to the ASGI app as a server hands it over: (status, response body)."""
    scope = {
        "type": "http",
        "asgi": {"version": "3.0"},
        "http_version": "1.1",
        "method": "POST",
        "scheme": "http",
        "path": path,
        "raw_path": path.encode(),
        "query_string": b"",
        "root_path": "",
        "headers": [
            (b"host", b"localhost"),
            (b"content-type", b"application/json"),
            (b"content-length", str(len(body)).encode()),
        ],
        "client": ("127.0.0.1", 50000),
        "server": ("127.0.0.1", 8000),
        "state": dict(state),
    }

    async def call():
        sent = [{"type": "http.request", "body": body, "more_body": False}]
        status, chunks = 0, []

        async def receive():
            return sent.pop() if sent else {"type": "http.disconnect"}

        async def send(message):
            nonlocal status
            if message["type"] == "http.response.start":
                status = message["status"]
            elif message["type"] == "http.response.body":
                chunks.append(message.get("body", b""))

        await app(scope, receive, send)
        return status, b"".join(chunks)

    return call


async def called_here(func, *args, **kwargs):
    return func(*args, **kwargs)


async def served_batch_ms(post) -> float:
    """A batch of POSTs on a loop that keeps running between them, as a server's does (a new run of the loop for each
    request, as batch_ms gives the other two, costs FastAPI's thread hop 0.25 ms more on a quiet 2-core machine)."""
    t0 = time.perf_counter()
    for _ in range(BATCH):
        await post()
    return 1e3 * (time.perf_counter() - t0) / BATCH


def batch_ms(fn) -> float:
    t0 = time.perf_counter()
    for _ in range(BATCH):
        fn()
    return 1e3 * (time.perf_counter() - t0) / BATCH


def main() -> None:
    import fastapi.routing
    from fastapi.testclient import TestClient

    from footprint import api, cli
    from footprint.contracts import parse
    from footprint.core.trajectory import _fly, simulate
    from footprint.service.app import create_app
    from footprint.service.routers.trajectories import trajectory_json
    from footprint.service.settings import load_settings

    spec = parse("case", CASE).to_spec()
    flown = simulate(spec)
    body = json.dumps(CASE).encode()

    def cli_fly():
        with contextlib.redirect_stdout(io.StringIO()):
            cli.fly(CASE_FILE, history=None)

    with tempfile.TemporaryDirectory() as folder:
        # an API process of `footprint serve --api-processes N` (runs_jobs=False: it flies the synchronous
        # trajectories itself); its cluster link is one local worker, idle here
        settings = load_settings(
            database_url=f"sqlite:///{folder}/bench.db", allowed_hosts="testserver", dask_workers=1
        )
        app = create_app(settings, runs_jobs=False)
        loop = asyncio.new_event_loop()
        with TestClient(app) as client:  # the app started (lifespan) on the test client's loop, in its thread
            test_client = lambda: client.post("/api/trajectories", json=CASE)  # noqa: E731
            assert test_client().status_code == 200
            # the same app called on this thread's loop, as a server hands it a request
            post = asgi_post(app, "/api/trajectories", body, {})
            status, answer = loop.run_until_complete(post())
            assert status == 200, (status, answer[:200])

            def post_without_hop():  # FastAPI's thread-pool hop replaced by a direct call: the route's own work
                with unittest.mock.patch.object(fastapi.routing, "run_in_threadpool", called_here):
                    loop.run_until_complete(post())

            calls = {
                "simulate(spec)": lambda: simulate(spec),
                "simulate(spec).history": lambda: simulate(spec).history,
                "api.fly(dict)": lambda: api.fly(CASE),
                "CLI fly (command function, in-process)": cli_fly,
                "POST /api/trajectories (ASGI app)": lambda: loop.run_until_complete(post()),
                "POST /api/trajectories (ASGI app, no thread hop)": post_without_hop,
                "POST /api/trajectories (TestClient)": test_client,
            }
            kernel = lambda: _fly(spec)  # noqa: E731
            for fn in (kernel, *calls.values()):  # warm: numba, pydantic, the thread pool
                for _ in range(20):
                    fn()
            doors = {name: functools.partial(batch_ms, fn) for name, fn in calls.items()}
            doors[SERVED] = lambda: loop.run_until_complete(served_batch_ms(post))
            doors[ANSWER_JSON] = functools.partial(batch_ms, lambda: trajectory_json(flown.summary, flown.history))
            times: dict[str, list[float]] = {"kernel": [], **{k: [] for k in doors}}
            ratios: dict[str, list[float]] = {k: [] for k in doors}
            load = [os.getloadavg()[0]]
            for _ in range(ROUNDS):
                k_ms = batch_ms(kernel)
                times["kernel"].append(k_ms)
                for name, timed_batch in doors.items():
                    ms = timed_batch()
                    times[name].append(ms)
                    ratios[name].append(ms / k_ms)
            load.append(os.getloadavg()[0])
        loop.close()
    data = {
        "case": "examples/table2_lod22.json",
        "kernel_ms": statistics.median(times["kernel"]),
        "doors_ms": {k: statistics.median(times[k]) for k in doors},
        "over_kernel": {k: statistics.median(r) - 1.0 for k, r in ratios.items() if k != ANSWER_JSON},
        "answer_json_share_of_kernel": statistics.median(ratios[ANSWER_JSON]),
        "target_over_kernel": 0.30,
        "rounds": ROUNDS,
        "calls_per_batch": BATCH,
        "load_1min_before_after": load,
    }
    print(json.dumps(data, indent=2))
    print(save_result("doors", data))


if __name__ == "__main__":
    main()
