"""Issue 15 item 2: jobs are bounded and cancellable. Dask cannot interrupt a running task, so a cancelled job's
worker kept computing (an optimization at the limits runs ~11 h) and two such requests held both workers; a job
had no time limit; and a job showed "running" while it waited for a worker.

The service runs on SQLite against the tests' shared two-worker cluster (tests/service/conftest.py)."""

import time

import pytest

from footprint import parallel
from footprint.service.jobs import engine
from tests.service.conftest import WAIT_S, running_service, wait_for_job, wait_until
from tests.service.sample_requests import CASE, FOOTPRINT, OPTIMIZE

LONG = OPTIMIZE | {"max_trajectories": 100_000, "case": CASE | {"integrator": {"rtol": 1e-12, "max_step_s": 0.05}}}


@pytest.fixture
def service(scheduler_address, tmp_path):
    with running_service(f"sqlite:///{tmp_path / 'footprint.db'}", scheduler_address, job_time_limit_s=60) as api:
        yield api


def _status_soon(api, job_id, wanted, timeout_s=WAIT_S):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        job = api.get(f"/api/jobs/{job_id}").json()
        if job["status"] == wanted:
            return job
        time.sleep(0.1)
    raise AssertionError(f"job {job_id} not {wanted} after {timeout_s} s: {job}")


def _reports(api, job_id) -> bool:
    """The optimization has reported its first trajectories."""
    return (api.get(f"/api/jobs/{job_id}").json()["progress_note"] or "").startswith("trajectory ")


def test_cancelled_jobs_free_their_workers_and_a_waiting_job_says_queued(service):
    long = [service.post("/api/jobs", json={"kind": "optimize", "study": LONG}).json()["id"] for _ in range(2)]
    for job_id in long:
        _status_soon(service, job_id, "running")  # both workers busy
    # a single-task job reports as it goes (it sat at 0 % until the end)
    wait_until(lambda: _reports(service, long[0]), "the optimization reports its trajectories")
    assert 0.0 < service.get(f"/api/jobs/{long[0]}").json()["progress"] < 0.01
    waiting = service.post("/api/jobs", json={"kind": "optimize", "study": LONG}).json()["id"]
    time.sleep(2.0)
    assert service.get(f"/api/jobs/{waiting}").json()["status"] == "queued"  # no worker has it yet
    for job_id in long + [waiting]:
        assert service.delete(f"/api/jobs/{job_id}").json()["status"] == "cancelled"
    short = service.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT}).json()["id"]
    job = wait_for_job(service, short, timeout_s=WAIT_S)  # the cancelled ones would have held both workers for hours
    assert job["status"] == "succeeded", job


def test_a_job_past_its_time_limit_fails_with_one_line(scheduler_address, tmp_path):
    with running_service(f"sqlite:///{tmp_path / 'footprint.db'}", scheduler_address, job_time_limit_s=3) as api:
        job_id = api.post("/api/jobs", json={"kind": "optimize", "study": LONG}).json()["id"]
        job = wait_for_job(api, job_id, timeout_s=WAIT_S)
    assert job["status"] == "failed"
    assert job["error"] == (
        "JobTimeLimit: the job ran past its time limit of 3 s (FOOTPRINT_JOB_TIME_LIMIT_S) and was stopped"
    )


def test_a_cancelled_optimization_stops_itself_and_keeps_its_worker(service, scheduler_address, monkeypatch):
    """The cancel reaches the running task (its progress reports answer "stop"): the optimizer ends by itself and its
    worker is free without a restart (the restart stays the last resort, for loops that report nothing). The grace
    before that restart is made long here, so that a loaded machine's slow report is not taken for no report."""
    import os

    from distributed import Client

    monkeypatch.setattr(engine, "STOP_GRACE_S", WAIT_S)

    with Client(scheduler_address, timeout="10s") as cluster:
        pids = cluster.run(os.getpid)
        job_id = service.post("/api/jobs", json={"kind": "optimize", "study": LONG}).json()["id"]
        wait_until(lambda: _reports(service, job_id), "the optimization reports its trajectories")
        assert service.delete(f"/api/jobs/{job_id}").json()["status"] == "cancelled"
        # the workers, not the scheduler (which forgets the task at the cancel), say when it stopped
        wait_until(lambda: not any(cluster.run(parallel.running_keys).values()), "the cancelled task stops")
        assert cluster.run(os.getpid) == pids  # the same worker processes: none was restarted


def test_a_task_that_reports_nothing_is_stopped_by_restarting_its_worker(service, scheduler_address):
    """The last resort: the scheduler forgets a cancelled task while its worker's thread runs on (and the next task
    waits behind it), so the engine asks the workers what they run and restarts the one still running it."""
    import os

    from distributed import Client

    jobs = service.app.state.jobs
    with Client(scheduler_address, timeout="10s") as cluster:
        pids = cluster.run(os.getpid)
        stuck = jobs.client.submit(time.sleep, 3_600, pure=False)  # only a restart frees its worker in time
        wait_until(
            lambda: any(cluster.run(lambda dask_worker: len(dask_worker.state.executing)).values()),
            "a worker runs the stuck task",
        )
        jobs.stop([stuck])  # the 1 s grace, then the nanny's restart
        free = jobs.client.submit(os.getpid, pure=False)
        assert free.result(timeout=WAIT_S) in (after := cluster.run(os.getpid)).values()
        assert len(set(after.values()) - set(pids.values())) == 1  # one worker restarted, the other kept


def test_a_job_error_hides_cluster_addresses_but_keeps_the_sentence():
    from footprint.service.jobs.engine import one_line

    exc = RuntimeError(
        "Attempted to run task 'x' on 4 different workers, but all those workers died while running it. "
        "The last worker that attempt to run the task was tcp://127.0.0.1:41234. Inspecting worker "
        "logs is often a good next step ('tls://10.0.0.2:8786')."
    )
    assert one_line(exc) == (
        "RuntimeError: Attempted to run task 'x' on 4 different workers, but all those workers "
        "died while running it. The last worker that attempt to run the task was <address>. "
        "Inspecting worker logs is often a good next step ('<address>')."
    )
