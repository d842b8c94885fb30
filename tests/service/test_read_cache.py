"""Issue 15 item 9: reads under load. A stored footprint was serialized again on every GET (through FastAPI's response
model: 2-7 ms each, p99 1.3 s at 200 readers during 20 jobs); now each GET of a footprint, the footprint list or the
vehicles is kept serialized with the revision of what it shows and a strong ETag: If-None-Match answers 304, and a
write through any process over the database (each app here stands for one API process) is seen by the next read."""

import threading
import time

import pytest

from footprint.service import read_cache
from footprint.service.routers import footprints as footprint_routes
from tests.service.conftest import running_service, wait_for_job
from tests.service.sample_requests import FOOTPRINT


@pytest.fixture(scope="module")
def stored(api):
    """(footprint id, its name) of a footprint job run through the module's service."""
    job = wait_for_job(
        api, api.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT, "name": "cached"}).json()["id"]
    )
    assert job["status"] == "succeeded", job
    fp_id = job["result"]["footprints"][0].rsplit("/", 1)[-1]
    return fp_id, api.get(f"/api/footprints/{fp_id}").json()["name"]


@pytest.fixture(scope="module")
def other(api, scheduler_address):
    """A second app over the same database: another API process."""
    with running_service(api.database_url, scheduler_address) as client:
        yield client


def test_a_footprint_is_serialized_once_and_revalidated_by_its_etag(api, stored, monkeypatch):
    fp_id, _ = stored
    builds = []
    real = footprint_routes._stored
    monkeypatch.setattr(footprint_routes, "_stored", lambda *a: builds.append(a) or real(*a))
    url = f"/api/footprints/{fp_id}?format=geojson"  # a representation no other test has read yet
    first = api.get(url)
    again = [api.get(url) for _ in range(5)]
    assert first.status_code == 200 and first.headers["content-type"] == "application/geo+json"
    assert len(builds) == 1  # serialized once, answered five more times from memory
    etag = first.headers["etag"]
    assert etag.startswith('"') and all(r.headers["etag"] == etag and r.content == first.content for r in again)
    assert first.headers["cache-control"] == "no-cache"  # a browser revalidates before each use
    for tags in (etag, f"W/{etag}", f'"other", {etag}', "*"):
        r = api.get(url, headers={"If-None-Match": tags})
        assert r.status_code == 304 and r.content == b"" and r.headers["etag"] == etag, tags
    assert api.get(url, headers={"If-None-Match": '"other"'}).status_code == 200
    assert len(builds) == 1


def test_each_representation_has_its_own_etag(api, stored):
    fp_id, _ = stored
    tags = {fmt: api.get(f"/api/footprints/{fp_id}?format={fmt}").headers["etag"] for fmt in ("json", "geojson", "csv")}
    assert len(set(tags.values())) == 3
    csv = api.get(f"/api/footprints/{fp_id}?format=csv")
    assert csv.headers["content-disposition"] == f'attachment; filename="footprint-{fp_id}.csv"'


def test_a_rename_through_another_process_is_read_at_once(api, other, stored):
    fp_id, name = stored
    before = api.get(f"/api/footprints/{fp_id}")
    listed = api.get("/api/footprints", params={"limit": 500})
    assert before.json()["name"] == name and name in {i["name"] for i in listed.json()["items"]}
    try:
        assert other.patch(f"/api/footprints/{fp_id}", json={"name": "renamed elsewhere"}).status_code == 200
        after = api.get(f"/api/footprints/{fp_id}", headers={"If-None-Match": before.headers["etag"]})
        assert after.status_code == 200 and after.json()["name"] == "renamed elsewhere"
        assert after.headers["etag"] != before.headers["etag"]
        names = {i["name"] for i in api.get("/api/footprints", params={"limit": 500}).json()["items"]}
        assert "renamed elsewhere" in names and name not in names
    finally:
        other.patch(f"/api/footprints/{fp_id}", json={"name": name})
    assert api.get(f"/api/footprints/{fp_id}").json()["name"] == name


def test_vehicles_stored_and_deleted_elsewhere_are_listed_at_once(api, other):
    ids = lambda: [v["id"] for v in api.get("/api/vehicles").json()]  # noqa: E731
    assert "cached-glider" not in ids()
    vehicle = {"name": "glider", "wing_loading_psf": 60, "aero": {"constant": {"cl": 0.5, "cd": 0.25}}}
    assert other.post("/api/vehicles", json={"id": "cached-glider", "vehicle": vehicle}).status_code == 201
    assert ids()[-1] == "cached-glider"
    assert other.delete("/api/vehicles/cached-glider").status_code == 204
    assert "cached-glider" not in ids()


def test_a_job_stored_elsewhere_and_a_delete_are_read_at_once(api, other):
    total = api.get("/api/footprints").json()["total"]
    job = wait_for_job(other, other.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT}).json()["id"])
    listed = api.get("/api/footprints").json()
    assert listed["total"] == total + 1 and listed["items"][0]["job_id"] == job["id"]
    fp_id = listed["items"][0]["id"]
    assert api.get(f"/api/footprints/{fp_id}").status_code == 200
    assert other.delete(f"/api/footprints/{fp_id}").status_code == 204
    assert api.get(f"/api/footprints/{fp_id}").status_code == 404
    assert api.get("/api/footprints").json()["total"] == total


def test_concurrent_misses_build_once_and_the_cache_is_bounded():
    cache = read_cache.ReadCache(max_bytes=300)
    builds = []

    def build():
        builds.append(threading.get_ident())
        time.sleep(0.05)
        return read_cache.serialized(b"x" * 100, "text/plain")

    threads = [threading.Thread(target=cache.get, args=(("k",), 1, build)) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(builds) == 1
    assert cache.get(("k",), 1, build).body == b"x" * 100 and len(builds) == 1
    cache.get(("k",), 2, build)  # a new revision: built again
    assert len(builds) == 2
    for key in "abc":  # 3 more bodies of 100 bytes: the least recently used one goes
        cache.get((key,), 1, build)
    assert len(builds) == 5
    cache.get(("c",), 1, build)
    assert len(builds) == 5
    cache.get(("k",), 2, build)
    assert len(builds) == 6


def test_keys_count_against_the_cap_and_entries_are_capped():
    """Issue 24 item 4: the cap counted bodies only, so 2,000 keys of 90,000 characters were 177 MB kept."""
    small = read_cache.serialized(b"[]", "application/json")
    cache = read_cache.ReadCache(max_bytes=100_000)
    for i in range(20):
        cache.get(("list", f"{i:05d}" + "x" * 9_000), 1, lambda: small)
    entries, size = cache.size
    assert size <= 100_000 and entries == 100_000 // 9_050  # each key's 9,000 characters count
    capped = read_cache.ReadCache(max_entries=50)
    for i in range(200):
        capped.get(("list", i), 1, lambda: small)
    assert capped.size[0] == 50


def test_ids_that_cannot_be_ids_are_refused_and_kept_nowhere(api):
    """2,000 GET /api/footprints?job_id=<7,000 random characters> are 422s naming job_id (404s that each left a cache
    entry before), and well-formed unknown ids fill the cache only to its entry cap."""
    import random
    import string
    import uuid

    cache = api.app.state.read_cache
    before = cache.size
    rng = random.Random(24)
    for _ in range(2_000):
        bogus = "".join(rng.choices(string.ascii_letters + string.digits, k=7_000))
        r = api.get("/api/footprints", params={"job_id": bogus})
        assert r.status_code == 422 and r.json()["field"] == "job_id", r.text[:200]
    assert cache.size == before
    for path in ("/api/jobs/not-an-id", "/api/footprints/0f0e", "/api/jobs/0f0e/dispersion"):
        assert api.get(path).status_code == 422
    api.app.state.read_cache = read_cache.ReadCache(max_entries=50)
    try:
        for _ in range(200):
            assert api.get("/api/footprints", params={"job_id": str(uuid.uuid4())}).json()["items"] == []
        assert api.app.state.read_cache.size[0] == 50
    finally:
        api.app.state.read_cache = cache


def test_a_revision_read_begun_before_a_request_never_answers_it():
    """Issue 49: the cached reads share their revision reads (read_cache.SharedRead). A read that began before a write
    committed must not answer a request that came after the commit (it would be served the old answer: a client that
    wrote through another process and then read would not see its write); the requests that come while one read runs
    share the next one."""
    import asyncio

    stored = {"footprints": 0}
    began: list[int] = []
    gates: list[asyncio.Event] = []

    async def read():  # a transaction's snapshot is taken when it begins: the value read then is what it returns
        snapshot = dict(stored)
        began.append(snapshot["footprints"])
        gates.append(asyncio.Event())
        await gates[-1].wait()
        return snapshot

    async def scenario():
        revisions = read_cache.SharedRead(read)
        first = asyncio.create_task(revisions.current())
        await asyncio.sleep(0)
        await asyncio.sleep(0)
        assert began == [0]  # the first read runs
        stored["footprints"] = 1  # a write commits while it runs
        later = [asyncio.create_task(revisions.current()) for _ in range(5)]  # requests after the commit
        await asyncio.sleep(0)
        assert began == [0]  # they wait for the next read, not the running one
        gates[0].set()
        assert (await first) == {"footprints": 0}  # it came before the commit
        while len(gates) < 2:
            await asyncio.sleep(0)
        gates[1].set()
        assert [await t for t in later] == [{"footprints": 1}] * 5  # all five from one read begun after the commit
        assert began == [0, 1]

    asyncio.run(scenario())


def test_a_failed_revision_read_reaches_its_waiters_and_the_next_read_is_tried():
    import asyncio

    calls = []

    async def read():
        calls.append(1)
        if len(calls) == 1:
            raise ConnectionError("the database is away")
        return {"footprints": 7}

    async def scenario():
        revisions = read_cache.SharedRead(read)
        with pytest.raises(ConnectionError):
            await revisions.current()
        assert await revisions.current() == {"footprints": 7}

    asyncio.run(scenario())
