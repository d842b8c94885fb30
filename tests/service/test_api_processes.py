"""Issue 15 item 9: several API processes over one database (`footprint serve --api-processes 2`, a real process
on SQLite with two local workers): the jobs the API processes queue are run by the engine in the serving process,
a cancel through any API process stops its job, and a write through one is read through the other at once. Their
connections carry TCP_NODELAY: without it each keep-alive request waited 44 ms for the client's delayed ACK."""

import re
import time

import httpx
import pytest

from tests.service.conftest import wait_until
from tests.service.sample_requests import FOOTPRINT
from tests.service.test_job_limits import LONG
from tests.service.test_restart import free_port, kill

START_TIMEOUT_S = 300.0


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    import os
    import subprocess
    import sys

    tmp = tmp_path_factory.mktemp("processes")
    port = free_port()
    log_path = tmp / "serve.log"
    env = {k: v for k, v in os.environ.items() if not k.startswith("FOOTPRINT_")}
    cmd = [
        sys.executable,
        "-m",
        "footprint.cli",
        "serve",
        "--port",
        str(port),
        "--workers",
        "2",
        "--api-processes",
        "2",
        "--database-url",
        f"sqlite:///{tmp / 'footprint.db'}",
    ]
    with open(log_path, "w") as log:
        proc = subprocess.Popen(cmd, cwd=tmp, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + START_TIMEOUT_S
        while True:
            assert proc.poll() is None, f"serve exited ({proc.returncode}):\n{log_path.read_text()[-3000:]}"
            assert time.monotonic() < deadline, log_path.read_text()[-3000:]
            try:  # the engine answers, and both API processes have started (one may take longer)
                if (
                    httpx.get(f"{base}/api/health", timeout=2).json()["status"] == "ok"
                    and log_path.read_text().count("Application startup complete") == 2
                ):
                    break
            except (httpx.HTTPError, ValueError, KeyError):
                pass
            time.sleep(0.2)
        yield base, log_path
    finally:
        kill(proc)


def _wait(client, job_id, timeout_s=120.0) -> dict:
    deadline = time.monotonic() + timeout_s
    while (job := client.get(f"/api/jobs/{job_id}").json())["status"] in ("queued", "running"):
        assert time.monotonic() < deadline, job
        time.sleep(0.1)
    return job


def test_two_api_processes_answer_and_the_engine_runs_their_jobs(served):
    base, log_path = served
    assert len(set(re.findall(r"Started server process \[(\d+)\]", log_path.read_text()))) == 2
    assert "died" not in log_path.read_text()  # uvicorn killed an API process that was slow to start
    with httpx.Client(base_url=base, timeout=30) as client:
        health = client.get("/api/health").json()
        assert health["cluster"] == {"ok": True, "workers": 2, "expected_workers": 2}
        ids = [client.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT}).json()["id"] for _ in range(4)]
        for job_id in ids:
            job = _wait(client, job_id)
            assert job["status"] == "succeeded" and len(job["result"]["footprints"]) == 1, job


def test_a_cancel_through_an_api_process_stops_the_job(served):
    base, _ = served
    with httpx.Client(base_url=base, timeout=30) as client:
        long = client.post("/api/jobs", json={"kind": "optimize", "study": LONG}).json()["id"]
        wait_until(lambda: client.get(f"/api/jobs/{long}").json()["status"] == "running", "the long job runs")
        assert client.delete(f"/api/jobs/{long}").json()["status"] == "cancelled"
        short = [
            client.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT}).json()["id"] for _ in range(2)
        ]  # both workers: one of them ran the cancelled job
        assert all(_wait(client, s)["status"] == "succeeded" for s in short)
        assert client.get(f"/api/jobs/{long}").json()["status"] == "cancelled"


def test_a_rename_through_one_process_is_read_through_every_one(served):
    base, _ = served
    with httpx.Client(base_url=base, timeout=30) as client:
        fp = client.get("/api/footprints", params={"limit": 1}).json()["items"][0]
        for _ in range(10):  # both processes' caches hold it
            assert httpx.get(f"{base}/api/footprints/{fp['id']}").json()["name"] == fp["name"]
        assert client.patch(f"/api/footprints/{fp['id']}", json={"name": "moved"}).json()["name"] == "moved"
    # a new connection each: the kernel spreads them over the two processes' accept queues
    names = {httpx.get(f"{base}/api/footprints/{fp['id']}").json()["name"] for _ in range(20)}
    assert names == {"moved"}


def test_keep_alive_requests_are_not_held_by_delayed_acks(served):
    base, _ = served
    with httpx.Client(base_url=base, timeout=30) as client:
        client.get("/api/config")
        times = []
        for _ in range(10):
            t0 = time.perf_counter()
            assert client.get("/api/config").status_code == 200
            times.append(time.perf_counter() - t0)
    assert sorted(times)[5] < 0.030  # s: the delayed ACK held every one ~44 ms (a quiet machine answers in ~1 ms)


def test_an_api_process_that_stalls_for_seconds_is_not_killed(served):
    """uvicorn's supervisor killed an API process that missed one 5 s ping (a new one still importing the app on a
    loaded machine, in CI) and its in-flight requests with it; stalled 8 s it now answers again."""
    import os
    import signal

    base, log_path = served
    pid = int(re.findall(r"Started server process \[(\d+)\]", log_path.read_text())[0])
    os.kill(pid, signal.SIGSTOP)
    try:
        time.sleep(8.0)
    finally:
        os.kill(pid, signal.SIGCONT)
    time.sleep(1.0)
    os.kill(pid, 0)  # still there
    assert "died" not in log_path.read_text()
    assert all(httpx.get(f"{base}/api/health", timeout=10).status_code == 200 for _ in range(6))
