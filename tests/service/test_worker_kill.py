"""A Dask worker process killed with SIGKILL while it runs a job's task (the kernel's out-of-memory killer, a crash):
the job still ends, succeeded or failed with one line, and never hangs (issue 15).

The worker's nanny starts a new worker process, and the scheduler hands the task to a worker again unless tasks of it
have now killed more than `allowed-failures` workers (distributed.scheduler.allowed-failures, 3 by default). So,
with the default, the job succeeds and its footprint is stored exactly once; with no failures allowed it fails with
the engine's one line: KilledWorker, the worker's address hidden. The cluster is this module's own (a kill must not
reach the workers the other service tests share), a LocalCluster as `footprint serve --workers 2` starts one.
"""

import os
import signal
import time

import pytest
from distributed import Client, LocalCluster

from footprint.service.db import queries as q

from .conftest import TERMINAL, running_service, wait_until
from .sample_requests import CASE

# 2-4 s of one worker's time (fine integrator steps, 50 bank settings: 100 trajectories), all in one task: still
# running well after the job shows "running" (its task's first event)
SLOW_FOOTPRINT = {
    "case": CASE | {"integrator": {"rtol": 1e-12, "max_step_s": 0.2}},
    "method": "single_parameter",
    "bank0_deg": [3.0 * i for i in range(50)],
}
INTO_THE_TASK_S = 0.5  # the kill comes this long after the task started
ENDS_WITHIN_S = 120.0  # the task flown again (2-4 s), with room to spare on a busy machine: else it hangs
WORKERS = 2


@pytest.fixture(scope="module")
def cluster():
    """A client of this module's LocalCluster (worker processes under nannies, one thread each)."""
    with (
        LocalCluster(
            n_workers=WORKERS,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            scheduler_kwargs={"dashboard": False},
        ) as local,
        Client(local, set_as_default=False) as client,
    ):
        yield client


@pytest.fixture(scope="module")
def service(cluster, tmp_path_factory):
    url = f"sqlite:///{tmp_path_factory.mktemp('worker-kill') / 'footprint.db'}"
    with running_service(url, cluster.scheduler.address) as client:
        yield client


@pytest.fixture
def no_retry(cluster):
    """The scheduler gives up on a task at the first worker that dies running it."""

    def set_allowed(n, dask_scheduler=None):
        before, dask_scheduler.allowed_failures = dask_scheduler.allowed_failures, n
        return before

    before = cluster.run_on_scheduler(set_allowed, 0)
    try:
        yield
    finally:
        cluster.run_on_scheduler(set_allowed, before)


def all_workers(cluster, timeout_s: float = 120.0) -> dict[str, int]:
    """{worker address: pid} once the cluster has all its workers (a killed one's nanny starts a new one)."""
    deadline = time.monotonic() + timeout_s
    while len(cluster.scheduler_info(n_workers=-1)["workers"]) < WORKERS:
        assert time.monotonic() < deadline, "the cluster did not get its workers back"
        time.sleep(0.2)
    return cluster.run(os.getpid)


def poll(service, job_id: str, until, timeout_s: float) -> dict:
    deadline = time.monotonic() + timeout_s
    while True:
        job = service.get(f"/api/jobs/{job_id}").json()
        if until(job) or time.monotonic() > deadline:
            return job
        time.sleep(0.05)


def kill_the_worker_running(service, cluster, job_id: str) -> tuple[str, str, int]:
    """SIGKILL the worker process that is running the job's task, a moment into it; (the task's key, the worker's
    address, its pid)."""
    job = poll(service, job_id, lambda j: j["status"] != "queued", timeout_s=120.0)
    assert job["status"] == "running", job  # a worker started the task (its first event)
    time.sleep(INTO_THE_TASK_S)
    busy = {w: k for w, keys in cluster.processing().items() for k in keys if job_id in str(k)}
    assert len(busy) == 1, cluster.processing()  # one task, on one worker
    ((address, key),) = busy.items()
    pid = cluster.run(os.getpid, workers=[address])[address]
    assert poll(service, job_id, lambda j: True, 0)["status"] == "running"  # still mid-task when killed
    os.kill(pid, signal.SIGKILL)
    return key, address, pid


def times_processed(cluster, key: str) -> int:
    """How often the scheduler handed the task to a worker (its transition log)."""

    def count(dask_scheduler=None):
        return sum(1 for t in dask_scheduler.story(key) if t[0] == key and t[2] == "processing")

    return cluster.run_on_scheduler(count)


def submit(service, study: dict) -> str:
    r = service.post("/api/jobs", json={"kind": "footprint", "study": study})
    assert r.status_code == 202, r.text
    return r.json()["id"]


def stored(service, job_id: str) -> dict:
    with service.app.state.sessions() as session:
        return q.count_rows(session, job_id=job_id)


def test_a_worker_killed_mid_job_is_replaced_and_the_job_succeeds_storing_its_footprint_once(service, cluster):
    before = all_workers(cluster)
    job_id = submit(service, SLOW_FOOTPRINT)
    key, _, pid = kill_the_worker_running(service, cluster, job_id)
    job = poll(service, job_id, lambda j: j["status"] in TERMINAL, ENDS_WITHIN_S)
    assert job["status"] == "succeeded", job
    assert times_processed(cluster, key) == 2  # the scheduler ran the task again (allowed-failures 3)
    assert job["error"] is None and len(job["result"]["footprints"]) == 1
    assert stored(service, job_id) == {"job_results": 1, "footprints": 1}
    footprint = service.get(job["result"]["footprints"][0]).json()
    assert footprint["trajectories"] >= 2 * len(SLOW_FOOTPRINT["bank0_deg"])  # the whole footprint, flown again
    after = all_workers(cluster)
    assert pid in before.values() and pid not in after.values()  # the nanny started a new worker process


def test_a_worker_killed_mid_job_with_no_retry_allowed_fails_the_job_with_one_line(service, cluster, no_retry):
    all_workers(cluster)
    job_id = submit(service, SLOW_FOOTPRINT)
    key, address, _ = kill_the_worker_running(service, cluster, job_id)
    job = poll(service, job_id, lambda j: j["status"] in TERMINAL, ENDS_WITHIN_S)
    assert job["status"] == "failed", job
    assert times_processed(cluster, key) == 1
    error = job["error"]
    assert error.startswith("KilledWorker: ") and job_id in error, error  # the task's key names the job
    assert len(error.splitlines()) == 1 and len(error) <= 500, error
    assert "://" not in error.replace("https://", "") and address.split("://")[1] not in error, error
    assert "<address>" in error, error
    assert job["result"] is None and stored(service, job_id) == {"job_results": 0, "footprints": 0}
    all_workers(cluster)  # the nanny started a new worker: until then health says degraded, 1 of the 2 it had
    wait_until(lambda: service.get("/api/health").json()["status"] == "ok", "health ok again")  # the service goes on
