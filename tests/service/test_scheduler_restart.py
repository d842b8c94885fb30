"""Issue 49 item 1: the compose topology as real processes on loopback (`dask scheduler`, two `dask worker ...
--preload footprint`, `footprint serve` with FOOTPRINT_DASK_SCHEDULER), on SQLite and Postgres; the scheduler and
its workers killed with SIGKILL and started again, as a deployment's restart policy would.

Before: restarted after 15 s, the API's Dask client had given up after 10 s and stayed closed (the running job and
every later one failed with ClosedClientError); restarted within 4 s, health said "ok 2/2" but new jobs stayed
"queued" for ever (the progress subscription was not renewed on the new scheduler, and a job whose tasks ended with
no start event seen was "ended elsewhere" and run again five times a second); health said "ok" with no scheduler.
Now health is 503 "degraded" while no scheduler answers, the job in flight is submitted again once and stored once,
and every later job runs."""

import os
import signal
import subprocess
import sys
import time

import httpx
import pytest
from sqlalchemy import create_engine, text

from .conftest import DATABASES, TERMINAL, database_url
from .test_restart import free_port
from .test_worker_kill import SLOW_FOOTPRINT

WAIT_S = 180.0  # a loaded machine starts a process slowly: a guard against a hang, never a bound on speed
LONG_OUTAGE_S = 15.0  # past the Dask client's 10 s of reconnecting: it closes, and the link builds a new one
SHORT_OUTAGE_S = 3.0  # within them: the client reconnects to the new scheduler itself
QUICK = {"case": SLOW_FOOTPRINT["case"] | {"integrator": {}}, "method": "single_parameter", "bank0_deg": [0, 30, 60]}


class Compose:
    """The scheduler, two workers and the API as processes of their own (each its own process group)."""

    def __init__(self, tmp_path, url: str):
        self.tmp, self.url = tmp_path, url
        self.port, self.api_port = free_port(), free_port()
        self.scheduler = f"tcp://127.0.0.1:{self.port}"
        self.base = f"http://127.0.0.1:{self.api_port}"
        self.cluster: list[subprocess.Popen] = []
        self.api: subprocess.Popen | None = None

    def spawn(self, name: str, *args: str, env: dict | None = None) -> subprocess.Popen:
        log = open(self.tmp / f"{name}-{time.monotonic_ns()}.log", "w")
        base = {k: v for k, v in os.environ.items() if not k.startswith("FOOTPRINT_")}
        return subprocess.Popen(
            [sys.executable, *args], cwd=self.tmp, env=base | (env or {}), stdout=log, stderr=subprocess.STDOUT,
            start_new_session=True,
        )  # fmt: skip

    def start_cluster(self) -> None:
        dask = ("-m", "distributed.cli.dask_scheduler")
        self.cluster = [self.spawn("scheduler", *dask, "--host", "127.0.0.1", "--port", str(self.port),
                                   "--no-dashboard")]  # fmt: skip
        for i in (1, 2):
            self.cluster.append(
                self.spawn(
                    f"worker-{i}",
                    "-m",
                    "distributed.cli.dask_worker",
                    self.scheduler,
                    "--name",
                    f"worker-{i}",
                    "--nthreads",
                    "1",
                    "--no-dashboard",
                    "--preload",
                    "footprint",
                )  # fmt: skip
            )

    def kill_cluster(self) -> None:
        for proc in self.cluster:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=30)

    def start_api(self) -> None:
        env = {"FOOTPRINT_DASK_SCHEDULER": self.scheduler, "FOOTPRINT_DATABASE_URL": self.url}
        self.api = self.spawn("api", "-m", "footprint.cli", "serve", "--port", str(self.api_port), env=env)

    def close(self) -> None:
        for proc in [*self.cluster, *([self.api] if self.api else [])]:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait(timeout=30)
            except ProcessLookupError:
                pass

    def health(self) -> tuple[int, dict]:
        try:
            r = httpx.get(f"{self.base}/api/health", timeout=5)
            return r.status_code, r.json()
        except (httpx.HTTPError, ValueError):
            return 0, {}

    def logs(self) -> str:
        return "\n".join(f"--- {p.name}\n{p.read_text()[-2500:]}" for p in sorted(self.tmp.glob("*.log")))

    def wait(self, condition, what: str):
        deadline = time.monotonic() + WAIT_S
        while not (value := condition()):
            assert self.api is None or self.api.poll() is None, f"the API exited\n{self.logs()}"
            assert time.monotonic() < deadline, f"{what}: not within {WAIT_S:g} s\n{self.logs()}"
            time.sleep(0.2)
        return value

    def submit(self, study: dict) -> str:
        r = httpx.post(f"{self.base}/api/jobs", json={"kind": "footprint", "study": study}, timeout=30)
        assert r.status_code == 202, r.text
        return r.json()["id"]

    def job(self, job_id: str) -> dict:
        return httpx.get(f"{self.base}/api/jobs/{job_id}", timeout=30).json()

    def ended(self, job_id: str) -> dict:
        return self.wait(lambda: (j := self.job(job_id))["status"] in TERMINAL and j, f"job {job_id} ends")

    def stored(self) -> dict[str, tuple[int, int]]:
        """{job id: (its results, its footprints)} as the database holds them."""
        db = create_engine(self.url)
        try:
            with db.connect() as c:
                results = dict(c.execute(text("SELECT job_id, COUNT(*) FROM job_results GROUP BY job_id")).all())
                footprints = dict(c.execute(text("SELECT job_id, COUNT(*) FROM footprints GROUP BY job_id")).all())
        finally:
            db.dispose()
        return {j: (results.get(j, 0), footprints.get(j, 0)) for j in results.keys() | footprints.keys()}


@pytest.fixture(params=DATABASES)
def compose(request, tmp_path):
    with database_url(request.param, tmp_path) as url:
        c = Compose(tmp_path, url)
        try:
            c.start_cluster()
            c.start_api()
            c.wait(lambda: (h := c.health())[0] == 200 and h[1]["cluster"]["workers"] == 2, "the service is up")
            yield c
        finally:
            c.close()


def outage(compose: Compose, seconds: float) -> None:
    """The scheduler and its workers killed; health degraded while they are away; all started again."""
    compose.kill_cluster()
    killed = time.monotonic()
    code, health = compose.wait(lambda: (h := compose.health())[0] == 503 and h, "health says degraded")
    assert health["status"] == "degraded" and not health["cluster"]["ok"], health
    assert health["cluster"]["error"].startswith("no answer from the Dask scheduler (<address>) for "), health
    time.sleep(max(0.0, seconds - (time.monotonic() - killed)))
    assert compose.health()[0] == 503
    compose.start_cluster()
    compose.wait(lambda: (h := compose.health())[0] == 200 and h[1]["cluster"]["workers"] == 2, "health ok again")


def test_the_service_survives_its_scheduler_killed_and_restarted_late_and_soon(compose):
    in_flight = compose.submit(SLOW_FOOTPRINT)
    compose.wait(lambda: compose.job(in_flight)["status"] == "running", "the job runs")
    outage(compose, LONG_OUTAGE_S)
    job = compose.ended(in_flight)
    assert job["status"] == "succeeded", (job, compose.logs())  # submitted again once, on the new scheduler
    later = [compose.submit(QUICK) for _ in range(3)]
    assert [compose.ended(j)["status"] for j in later] == ["succeeded"] * 3, compose.logs()

    outage(compose, SHORT_OUTAGE_S)
    after = [compose.submit(QUICK) for _ in range(3)]
    assert [compose.ended(j)["status"] for j in after] == ["succeeded"] * 3, compose.logs()
    assert all(compose.job(j)["started_at"] for j in after)  # they ran: "running" came before "succeeded"

    assert compose.stored() == dict.fromkeys([in_flight, *later, *after], (1, 1))  # each stored exactly once
    log = compose.logs()
    assert "ended elsewhere" not in log and "ClosedClientError" not in log
    assert "subscriptions renewed" in log and "the Dask scheduler answers again" in log
