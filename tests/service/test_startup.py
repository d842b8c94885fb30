"""Start-up work that the first requests must not pay for: the built-in vehicles' summaries (the numba
kernels' first calls, seconds) are computed before the app reports ready, once, under a lock."""

import threading
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

from footprint.core.aero import builtin_vehicle_ids
from footprint.service.routers import vehicles

from .conftest import database_url, running_service

CONCURRENT = 20


def concurrent_gets(api, path: str, n: int = CONCURRENT) -> list:
    barrier = threading.Barrier(n)

    def get(_):
        barrier.wait()
        return api.get(path)

    with ThreadPoolExecutor(n) as pool:
        return list(pool.map(get, range(n)))


@pytest.fixture
def cold_service(scheduler_address, tmp_path):
    """A freshly created app, the built-in summaries forgotten before it starts."""
    vehicles.BUILTINS.clear()
    assert vehicles.BUILTINS.value is None
    with database_url("sqlite", tmp_path) as url, running_service(url, scheduler_address) as api:
        yield api


def test_builtin_vehicle_summaries_are_computed_before_the_app_is_ready(cold_service, monkeypatch):
    # started, and not one request yet: the summaries are there
    assert vehicles.BUILTINS.value is not None
    items, aero = vehicles.BUILTINS.value
    assert list(items) == builtin_vehicle_ids() and set(aero) == set(items)

    def no_second_computation():
        raise AssertionError("the built-in summaries were computed again on a request")

    monkeypatch.setattr(vehicles.BUILTINS, "_compute", no_second_computation)
    replies = concurrent_gets(cold_service, "/api/vehicles")
    assert [r.status_code for r in replies] == [200] * CONCURRENT
    assert len({r.content for r in replies}) == 1
    assert [v["id"] for v in replies[0].json()] == builtin_vehicle_ids()
    details = concurrent_gets(cold_service, "/api/vehicles/lod-2.2")
    assert [r.status_code for r in details] == [200] * CONCURRENT and len({r.content for r in details}) == 1
    assert details[0].json()["aero"] == aero["lod-2.2"]


def test_concurrent_first_requests_wait_for_one_computation(cold_service, monkeypatch):
    """Were the cache cold after all (cleared here), concurrent first requests compute it once, not each."""
    compute, calls = vehicles.BuiltinSummaries._compute, []

    def slow_counted_compute():
        calls.append(threading.get_ident())
        time.sleep(0.3)  # long enough for every request to arrive while it runs
        return compute()

    vehicles.BUILTINS.clear()
    monkeypatch.setattr(vehicles.BUILTINS, "_compute", slow_counted_compute)
    replies = concurrent_gets(cold_service, "/api/vehicles")
    assert [r.status_code for r in replies] == [200] * CONCURRENT
    assert len({r.content for r in replies}) == 1
    assert len(calls) == 1, f"computed {len(calls)} times"
