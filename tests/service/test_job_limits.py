"""Issue 15 item 2: jobs are bounded and cancellable. Dask cannot interrupt a running task, so a cancelled job's
worker kept computing (an optimization at the limits runs ~11 h) and two such requests held both workers; a job
had no time limit; and a job showed "running" while it waited for a worker.

The service runs on SQLite against the tests' shared two-worker cluster (tests/service/conftest.py)."""

import time

import pytest

from tests.service.conftest import running_service, wait_for_job
from tests.service.sample_requests import CASE, FOOTPRINT, OPTIMIZE

LONG = OPTIMIZE | {"max_trajectories": 100_000, "case": CASE | {"integrator": {"rtol": 1e-12, "max_step_s": 0.05}}}


@pytest.fixture
def service(scheduler_address, tmp_path):
    with running_service(f"sqlite:///{tmp_path / 'footprint.db'}", scheduler_address, job_time_limit_s=60) as api:
        yield api


def _status_soon(api, job_id, wanted, timeout_s=30.0):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        job = api.get(f"/api/jobs/{job_id}").json()
        if job["status"] == wanted:
            return job
        time.sleep(0.1)
    raise AssertionError(f"job {job_id} not {wanted} after {timeout_s} s: {job}")


def test_cancelled_jobs_free_their_workers_and_a_waiting_job_says_queued(service):
    long = [service.post("/api/jobs", json={"kind": "optimize", "study": LONG}).json()["id"] for _ in range(2)]
    for job_id in long:
        _status_soon(service, job_id, "running")  # both workers busy
    deadline = time.monotonic() + 20.0  # a single-task job reports as it goes (it sat at 0 % until the end)
    while not (service.get(f"/api/jobs/{long[0]}").json()["progress_note"] or "").startswith("trajectory "):
        assert time.monotonic() < deadline, service.get(f"/api/jobs/{long[0]}").json()
        time.sleep(0.2)
    assert 0.0 < service.get(f"/api/jobs/{long[0]}").json()["progress"] < 0.01
    waiting = service.post("/api/jobs", json={"kind": "optimize", "study": LONG}).json()["id"]
    time.sleep(2.0)
    assert service.get(f"/api/jobs/{waiting}").json()["status"] == "queued"  # no worker has it yet
    t0 = time.monotonic()
    for job_id in long + [waiting]:
        assert service.delete(f"/api/jobs/{job_id}").json()["status"] == "cancelled"
    short = service.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT}).json()["id"]
    job = wait_for_job(service, short, timeout_s=60.0)
    assert job["status"] == "succeeded", job
    assert time.monotonic() - t0 < 30.0  # seconds, not the hours the cancelled ones would have held the workers


def test_a_job_past_its_time_limit_fails_with_one_line(scheduler_address, tmp_path):
    with running_service(f"sqlite:///{tmp_path / 'footprint.db'}", scheduler_address, job_time_limit_s=3) as api:
        job_id = api.post("/api/jobs", json={"kind": "optimize", "study": LONG}).json()["id"]
        job = wait_for_job(api, job_id, timeout_s=60.0)
    assert job["status"] == "failed"
    assert job["error"] == ("JobTimeLimit: the job ran past its time limit of 3 s (FOOTPRINT_JOB_TIME_LIMIT_S) and "
                            "was stopped")
