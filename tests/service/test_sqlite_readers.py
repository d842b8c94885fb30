"""SQLite: a GET reads beside a held write lock (WAL, deferred BEGIN); writes still take the lock in turn."""

import sqlite3

import pytest

from .conftest import database_url, running_service


@pytest.fixture
def sqlite_service(scheduler_address, tmp_path):
    with database_url("sqlite", tmp_path) as url, running_service(url, scheduler_address) as api:
        yield api, url.removeprefix("sqlite:///")


def test_reads_do_not_wait_for_a_writer(sqlite_service):
    api, path = sqlite_service
    assert (
        api.post("/api/sites", json={"name": "Edwards", "latitude_deg": 34.9, "longitude_deg": -117.9}).status_code
        == 201
    )
    writer = sqlite3.connect(path, isolation_level=None)
    writer.execute("BEGIN IMMEDIATE")  # another process holds the one write lock
    try:
        r = api.get("/api/sites")  # a read that took the write lock would wait out the busy timeout, then fail
        assert r.status_code == 200 and [s["name"] for s in r.json()] == ["Edwards"]
    finally:
        writer.execute("ROLLBACK")
        writer.close()
    assert (
        api.post("/api/sites", json={"name": "White Sands", "latitude_deg": 32.4, "longitude_deg": -106.4}).status_code
        == 201
    )  # the writer's turn came
