"""A restart loses no job: `footprint serve` as a real process (its default SQLite file in the working
directory, two local workers), jobs submitted, the process group killed with SIGKILL mid-job, the service started
again: every job ends succeeded and each job's results are stored exactly once."""

import os
import signal
import socket
import sqlite3
import subprocess
import sys
import time
from contextlib import closing
from pathlib import Path

import httpx

from .sample_requests import CASE, FOOTPRINT

START_TIMEOUT_S = 300.0  # a cold numba cache compiles for a minute, longer on a loaded machine
# a few seconds of one worker's time (fine integrator steps): still running when the server is killed, now that a job
# shows "running" only once a worker has started it
OPTIMIZE_1S = {
    "case": CASE | {"integrator": {"rtol": 1e-12, "max_step_s": 0.2}},
    "constraints": [{"quantity": "downrange_nmi", "equals": 3_000}],
    "max_trajectories": 250,
}


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def launch(tmp_path, port: int, workers: int = 2, **env_extra: str) -> tuple[subprocess.Popen, Path]:
    """`footprint serve` in its own process group (so SIGKILL reaches its Dask workers too, as a crash would), with
    no FOOTPRINT_ setting of the test's environment but `env_extra`; not waited for. (The process, its log.)"""
    log_path = tmp_path / f"serve-{time.monotonic_ns()}.log"
    log = open(log_path, "w")
    env = {k: v for k, v in os.environ.items() if not k.startswith("FOOTPRINT_")} | env_extra
    cmd = [
        sys.executable,
        "-c",
        "from footprint.cli import main; main()",
        "serve",
        "--port",
        str(port),
        "--workers",
        str(workers),
    ]  # the database: the default, footprint.db in the working directory
    proc = subprocess.Popen(cmd, cwd=tmp_path, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    return proc, log_path


def start(tmp_path, port: int, **env_extra: str) -> subprocess.Popen:
    """launch() and wait until health says ok."""
    proc, log_path = launch(tmp_path, port, **env_extra)
    deadline = time.monotonic() + START_TIMEOUT_S
    while time.monotonic() < deadline:
        assert proc.poll() is None, f"serve exited ({proc.returncode}):\n{log_path.read_text()[-3000:]}"
        try:
            if httpx.get(f"http://127.0.0.1:{port}/api/health", timeout=2).json()["status"] == "ok":
                return proc
        except httpx.HTTPError:
            pass
        time.sleep(0.2)
    kill(proc)
    raise AssertionError("footprint serve did not become healthy")


def kill(proc: subprocess.Popen) -> None:
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=30)


def statuses(base: str, ids: list[str]) -> dict:
    return {i: httpx.get(f"{base}/api/jobs/{i}", timeout=10).json()["status"] for i in ids}


def test_sigkill_mid_job_then_restart_loses_nothing_and_writes_once(tmp_path):
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    proc = start(tmp_path, port)
    try:
        jobs = [("optimize", OPTIMIZE_1S)] * 3 + [("footprint", FOOTPRINT)] * 2
        ids = [httpx.post(f"{base}/api/jobs", json={"kind": k, "study": s}, timeout=10).json()["id"] for k, s in jobs]
        deadline = time.monotonic() + 120
        while "running" not in statuses(base, ids).values() and time.monotonic() < deadline:
            time.sleep(0.05)
        time.sleep(0.5)
    finally:
        kill(proc)
    with closing(sqlite3.connect(tmp_path / "footprint.db")) as db:  # the state the crash left
        before = dict(db.execute("SELECT id, status FROM jobs").fetchall())
    assert "running" in before.values() and list(before.values()).count("succeeded") < len(ids), before
    proc = start(tmp_path, port)
    try:
        deadline = time.monotonic() + 120
        while set(statuses(base, ids).values()) & {"queued", "running"} and time.monotonic() < deadline:
            time.sleep(0.2)
        after = {i: httpx.get(f"{base}/api/jobs/{i}", timeout=10).json() for i in ids}
    finally:
        kill(proc)
    assert {i: j["status"] for i, j in after.items()} == dict.fromkeys(ids, "succeeded")
    with closing(sqlite3.connect(tmp_path / "footprint.db")) as db:
        results = dict(db.execute("SELECT job_id, COUNT(*) FROM job_results GROUP BY job_id").fetchall())
        footprints = dict(db.execute("SELECT job_id, COUNT(*) FROM footprints GROUP BY job_id").fetchall())
        attempts = dict(db.execute("SELECT id, attempts FROM jobs").fetchall())
    assert results == dict.fromkeys(ids, 1)
    assert footprints == {i: 1 for i, (kind, _) in zip(ids, jobs) if kind == "footprint"}
    resubmitted = [i for i in ids if before[i] != "succeeded"]
    # every job was handed to the cluster before the kill (a "queued" one was waiting for a worker) and again after
    assert all(attempts[i] == 2 for i in resubmitted)
    assert all(len(after[i]["result"]["footprints"]) == 1 for i, (kind, _) in zip(ids, jobs) if kind == "footprint")
