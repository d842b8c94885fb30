"""Issue 49: 200 concurrent GETs of the map page's reads (bench/bench_service_load.py --mix page). Before, on both
databases, the service stopped answering: the sync GET routes held their connection across FastAPI's hops between the
thread pool and the event loop (the route, its response model, its dependency's exit), so 200 readers held more
connections than the pool had (SQLAlchemy's 5 + 10 on SQLite, 10 + 40 on Postgres), each waited up to 30 s for one and
failed, and so did the jobs beside them, whose threads drew on the same pool; and a cached read and /api/health read
the database on the event loop, which stopped the whole server while the pool was empty. Each test here runs the app in
this process and sends the GETs at once through httpx's ASGI transport."""

import asyncio
import threading

import httpx
import pytest
from sqlalchemy import create_engine, event, select
from sqlalchemy.orm import Session

from footprint.service import deps
from footprint.service.db import queries as q
from footprint.service.db.engine import REQUEST_POOL_OVERFLOW, REQUEST_POOL_SIZE
from footprint.service.db.models import Job
from tests.service.conftest import running_service, wait_for_job, wait_until
from tests.service.sample_requests import FOOTPRINT

READERS = 200


@pytest.fixture(scope="module")
def stored(api):
    """(job id, footprint id) of a footprint job run through the module's service."""
    job = wait_for_job(api, api.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT}).json()["id"])
    assert job["status"] == "succeeded", job
    return job["id"], job["result"]["footprints"][0].rsplit("/", 1)[-1]


def page_reads(job_id: str, footprint_id: str) -> list[str]:
    """`READERS` GETs, the page's reads in turn."""
    reads = [
        "/api/footprints?limit=200",
        f"/api/footprints/{footprint_id}",
        f"/api/footprints/{footprint_id}?format=geojson",
        f"/api/footprints/{footprint_id}?format=csv",
        f"/api/jobs/{job_id}",
        "/api/jobs?limit=50",
        "/api/jobs?kind=dispersion&status=succeeded&limit=50",
        "/api/health",
        "/api/vehicles",
        "/api/sites",
        "/api/config",
    ]
    return [reads[i % len(reads)] for i in range(READERS)]


class Watch:
    """The request engine's connections held at once (most), and each statement with the thread that ran it."""

    def __init__(self, engine):
        self.held = self.most = 0
        self.statements: list[tuple[int, str]] = []
        self._lock = threading.Lock()
        event.listen(engine, "checkout", self._checkout)
        event.listen(engine, "checkin", self._checkin)
        event.listen(engine, "before_cursor_execute", self._execute)

    def _checkout(self, *_):
        with self._lock:
            self.held += 1
            self.most = max(self.most, self.held)

    def _checkin(self, *_):
        with self._lock:
            self.held -= 1

    def _execute(self, _connection, _cursor, statement, *_):
        with self._lock:
            self.statements.append((threading.get_ident(), statement))


def served_at_once(app, paths: list[str]) -> tuple[list[httpx.Response], Watch, int]:
    """Every path GET at once through the app's lifespan; (the answers, what the database saw meanwhile, the event
    loop's thread)."""

    async def main():
        async with app.router.lifespan_context(app):
            transport = httpx.ASGITransport(app=app)
            async with httpx.AsyncClient(transport=transport, base_url="http://localhost", timeout=120) as client:
                for path in dict.fromkeys(paths):  # each answer once: the cached ones are kept
                    assert (await client.get(path)).status_code == 200, path
                watch = Watch(app.state.sessions.kw["bind"])
                answers = await asyncio.gather(*(client.get(path) for path in paths))
                return answers, watch, threading.get_ident()

    return asyncio.run(main())


@pytest.fixture
def reader_app(api, scheduler_address):
    """Another API process over the module's database (its own pool, caches and loop), which runs no job."""
    from footprint.service.app import create_app
    from footprint.service.settings import load_settings

    return create_app(load_settings(database_url=api.database_url, dask_scheduler=scheduler_address), runs_jobs=False)


def test_200_concurrent_reads_hold_a_few_connections_off_the_event_loop(reader_app, stored):
    """Every GET answers, at most READ_THREADS connections and the shared revision read's one are held at once (the
    pool keeps room for the writes), and no statement runs on the event loop's thread (a round trip there stops every
    other request meanwhile)."""
    answers, watch, loop_thread = served_at_once(reader_app, page_reads(*stored))
    assert [r.status_code for r in answers] == [200] * READERS, {r.status_code: r.text[:200] for r in answers}
    assert 1 <= watch.most <= deps.READ_THREADS + 1
    assert watch.statements and not [s for thread, s in watch.statements if thread == loop_thread]


def test_concurrent_cached_reads_share_their_revision_reads(reader_app, stored):
    """A cached answer is current when the stored revisions, read after the request came, are those it was kept for:
    one revision read answers the requests that wait together (each read its own before: one query per request)."""
    paths = page_reads(*stored)
    answers, watch, _ = served_at_once(reader_app, paths)
    assert [r.status_code for r in answers] == [200] * READERS
    checking = sum(1 for p in paths if p.startswith(("/api/footprints", "/api/vehicles", "/api/health", "/api/jobs/")))
    shared = [s for _, s in watch.statements if "FROM revisions" in s]  # q.revisions: every kind's in one query
    assert 1 <= len(shared) < checking / 2, (len(shared), checking)
    assert not [s for _, s in watch.statements if "footprint_points" in s]  # the footprints answered from memory


def test_concurrent_reads_of_a_pending_job_and_the_job_list_share_their_reads(api, reader_app):
    """What no revision covers (a pending job, a job list) is read anew for each request that comes, but the requests
    that wait together share one read begun after they came: each read its own before, dozens a second."""
    own = create_engine(api.database_url)
    try:
        with Session(own) as session, session.begin():
            queued = q.create_job(session, kind="footprint", study=FOOTPRINT, name="never run").id  # no engine has it
    finally:
        own.dispose()
    paths = [f"/api/jobs/{queued}", "/api/jobs?limit=50"] * (READERS // 2)
    answers, watch, _ = served_at_once(reader_app, paths)
    assert [r.status_code for r in answers] == [200] * READERS
    assert {r.json()["status"] for r in answers[::2]} == {"queued"}
    reads = [s for _, s in watch.statements if "FROM jobs" in s]
    assert 1 <= len(reads) < len(paths) / 2, len(reads)


def test_a_finished_job_is_answered_from_memory_until_its_footprints_change(api, stored):
    job_id, footprint_id = stored
    first = api.get(f"/api/jobs/{job_id}")
    assert first.status_code == 200 and first.headers["etag"]
    assert api.get(f"/api/jobs/{job_id}", headers={"If-None-Match": first.headers["etag"]}).status_code == 304
    name = api.get(f"/api/footprints/{footprint_id}").json()["name"]
    try:
        assert api.patch(f"/api/footprints/{footprint_id}", json={"name": "renamed for the job"}).status_code == 200
        again = api.get(f"/api/jobs/{job_id}", headers={"If-None-Match": first.headers["etag"]})
        assert again.status_code == 304  # built again at the new revision: the same links, the same bytes
    finally:
        api.patch(f"/api/footprints/{footprint_id}", json={"name": name})


def test_a_job_runs_while_the_requests_hold_every_connection_of_their_pool(scheduler_address, tmp_path):
    """The job engine's threads draw on a pool of their own: before, under 200 readers, two dispersions failed with
    "QueuePool limit of size 10 overflow 40 reached, connection timed out" (bench_service_load --mix page)."""
    url = f"sqlite:///{tmp_path / 'footprint.db'}"
    with running_service(url, scheduler_address) as api:
        requests_engine = api.app.state.sessions.kw["bind"]
        held = [requests_engine.connect() for _ in range(REQUEST_POOL_SIZE + REQUEST_POOL_OVERFLOW)]
        own = create_engine(url)
        try:
            with Session(own) as session, session.begin():
                job_id = q.create_job(session, kind="footprint", study=FOOTPRINT, name="beside a full pool").id
            api.app.state.jobs.submit(job_id=job_id)

            def ended():
                with own.connect() as c:
                    status = c.execute(select(Job.status).where(Job.id == job_id)).scalar_one()
                return status if status not in ("queued", "running") else None

            assert wait_until(ended, "the job's end") == "succeeded"
        finally:
            for connection in held:
                connection.close()
            own.dispose()
        assert api.get(f"/api/jobs/{job_id}").json()["result"]["footprints"]


def test_a_repeated_cached_get_is_answered_before_the_route_while_current(api, stored, monkeypatch):
    """read_cache.CachedGets: the same path and query are answered from the read cache without FastAPI's routing and
    parameter parsing (half the event loop's time of a cached read), the same bytes, ETag and 304; after the guard (a
    Host not served is still refused) and only while the revision holds (a rename reaches the route again)."""
    job_id, footprint_id = stored
    routed = []
    real = deps.cached_hit
    monkeypatch.setattr(deps, "cached_hit", lambda *a: routed.append(a[1]) or real(*a))
    url = f"/api/footprints/{footprint_id}?format=csv"
    first = api.get(url)
    again = [api.get(url) for _ in range(5)]
    assert first.status_code == 200 and len(routed) == 1
    assert all(r.content == first.content and r.headers == first.headers for r in again) and len(routed) == 1
    assert api.get(url, headers={"If-None-Match": first.headers["etag"]}).status_code == 304
    assert api.head(url).headers["etag"] == first.headers["etag"] and len(routed) == 1
    assert api.get(url, headers={"Host": "elsewhere.example"}).status_code == 421
    name = api.get(f"/api/footprints/{footprint_id}").json()["name"]
    before = len(routed)
    try:
        assert api.patch(f"/api/footprints/{footprint_id}", json={"name": "renamed past the cache"}).status_code == 200
        assert api.get(f"/api/footprints/{footprint_id}").json()["name"] == "renamed past the cache"
        assert len(routed) == before + 1  # no longer current: the route built it again
    finally:
        api.patch(f"/api/footprints/{footprint_id}", json={"name": name})
    assert api.get(f"/api/jobs/{job_id}").status_code == 200


def test_footprint_serve_freezes_its_start_up_heap(scheduler_address, tmp_path):
    """The serving process's start-up objects (some 300,000: numba's, Dask's, SQLAlchemy's) go to the collector's
    permanent generation: each full collection scanned them all, 170-670 ms with the event loop stopped, every second
    or two at 200 readers (issue 49's p99 tail)."""
    import gc

    from fastapi.testclient import TestClient

    from footprint.service.app import create_app
    from footprint.service.settings import load_settings

    gc.unfreeze()
    settings = load_settings(database_url=f"sqlite:///{tmp_path / 'footprint.db'}", dask_scheduler=scheduler_address)
    try:
        with TestClient(create_app(settings, freezes_heap=True)) as api:
            assert api.get("/api/health").status_code == 200
            assert gc.get_freeze_count() > 0
    finally:
        gc.unfreeze()  # this test process's other apps keep the collector's usual ways
    with TestClient(create_app(settings)) as api:
        assert api.get("/api/health").status_code == 200
        assert gc.get_freeze_count() == 0


def test_the_job_list_reads_no_study(api, stored):
    """A list shows none of its jobs' studies (a few kB of JSON each, parsed for every row before)."""
    watch = Watch(api.app.state.sessions.kw["bind"])
    listed = api.get("/api/jobs", params={"limit": 50}).json()
    assert listed["total"] >= 1 and "study" not in listed["items"][0]
    selects = [s for _, s in watch.statements if "FROM jobs" in s]
    assert selects and not [s for s in selects if "jobs.study" in s]
