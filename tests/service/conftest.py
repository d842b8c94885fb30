"""The service under test: a real Dask cluster (shared by the tests, reached as an external scheduler) and real
databases: a SQLite file, and Postgres (FOOTPRINT_TEST_POSTGRES_URL) in a fresh schema per test module,
dropped afterwards. Postgres tests skip when it is unreachable, unless FOOTPRINT_REQUIRE_POSTGRES=1."""

import os
import time
import uuid
from contextlib import contextmanager
from urllib.parse import quote

import pytest
from sqlalchemy import create_engine, text

POSTGRES_URL = os.environ.get("FOOTPRINT_TEST_POSTGRES_URL", "postgresql+psycopg://postgres@127.0.0.1:5432/test")
REQUIRE_POSTGRES = os.environ.get("FOOTPRINT_REQUIRE_POSTGRES", "") not in ("", "0")
DATABASES = ("sqlite", "postgresql")
TERMINAL = ("succeeded", "failed", "cancelled")
JOB_TIMEOUT_S = 600.0  # a test job's footprint takes well under a second once numba is warm; a loaded machine is slow
WAIT_S = 120.0  # how long a test waits for any state it polls for: generous, never a bound on speed


def postgres_reachable() -> str | None:
    """None when Postgres answers; else why not."""
    try:
        engine = create_engine(POSTGRES_URL, connect_args={"connect_timeout": 3})
        with engine.connect() as c:
            c.execute(text("SELECT 1"))
        engine.dispose()
        return None
    except Exception as exc:  # noqa: BLE001 -- any failure means: not reachable
        return f"{type(exc).__name__}: {exc}".splitlines()[0]


@contextmanager
def database_url(kind: str, tmp_path):
    """A URL of an empty database of this kind, cleaned up afterwards."""
    if kind == "sqlite":
        yield f"sqlite:///{tmp_path / 'footprint.db'}"
        return
    why = postgres_reachable()
    if why is not None:
        if REQUIRE_POSTGRES:
            pytest.fail(f"Postgres required (FOOTPRINT_REQUIRE_POSTGRES=1) but unreachable at {POSTGRES_URL}: {why}")
        pytest.skip(f"Postgres unreachable at {POSTGRES_URL}: {why}")
    schema = f"test_{uuid.uuid4().hex[:12]}"
    admin = create_engine(POSTGRES_URL, isolation_level="AUTOCOMMIT")
    with admin.connect() as c:
        c.execute(text(f'CREATE SCHEMA "{schema}"'))
    sep = "&" if "?" in POSTGRES_URL else "?"
    try:
        yield f"{POSTGRES_URL}{sep}options={quote(f'-csearch_path={schema}')}"
    finally:
        with admin.connect() as c:
            c.execute(text(f'DROP SCHEMA "{schema}" CASCADE'))
        admin.dispose()


@pytest.fixture(scope="session")
def scheduler_address():
    """One LocalCluster for every service test (two worker processes, one thread each), as an external
    scheduler: the service connects to it the way it connects to a deployment's dask-scheduler; kept at its size."""
    from distributed import LocalCluster

    from footprint.parallel import kept_at_size

    with (
        LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            scheduler_kwargs={"dashboard": False},
        ) as cluster,
        kept_at_size(cluster),  # as the service keeps its own: a worker lost on a busy machine is replaced
    ):
        yield cluster.scheduler_address


@contextmanager
def running_service(url: str, scheduler: str, **settings):
    """A TestClient of the app on this database and scheduler, its lifespan (migrations, engine) running."""
    from fastapi.testclient import TestClient

    from footprint.service.app import create_app
    from footprint.service.settings import load_settings

    app = create_app(load_settings(database_url=url, dask_scheduler=scheduler, **settings))
    with TestClient(app) as client:
        yield client


def wait_until(condition, what: str, timeout_s: float = WAIT_S):
    """Poll condition() until it returns something true, and return that; past timeout_s (a guard against a hang,
    never a bound on speed) a TimeoutError saying what did not happen."""
    deadline = time.monotonic() + timeout_s
    while not (value := condition()):
        if time.monotonic() > deadline:
            raise TimeoutError(f"{what}: not within {timeout_s:g} s")
        time.sleep(0.05)
    return value


def wait_for_job(client, job_id: str, timeout_s: float = JOB_TIMEOUT_S, headers=None) -> dict:
    """Poll until the job is terminal; its final state."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        job = client.get(f"/api/jobs/{job_id}", headers=headers).json()
        if job["status"] in TERMINAL:
            return job
        time.sleep(0.1)
    raise AssertionError(f"job {job_id} not finished after {timeout_s} s: {job}")


@pytest.fixture(scope="module", params=DATABASES)
def api(request, scheduler_address, tmp_path_factory):
    """A running service per database kind, for a whole test module."""
    with (
        database_url(request.param, tmp_path_factory.mktemp(request.param)) as url,
        running_service(url, scheduler_address) as client,
    ):
        client.database = request.param
        client.database_url = url
        yield client
