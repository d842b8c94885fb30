"""A small load test on loopback (the full one is bench/bench_service_load.py, whose code this runs):
the real `footprint serve` as a subprocess (SQLite, 2 local workers), 50 concurrent reads twice and
5 concurrent footprint jobs with 50 closed-loop readers while they run. No error, no lost job: every job
succeeds and owns exactly one stored footprint. Bounded: 60 s at most, about 10-20 s here."""

import importlib.util
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "bench" / "bench_service_load.py"


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("bench_service_load", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_reads_and_jobs_under_load_lose_nothing(bench):
    figures = bench.run(
        reads=50, rounds=2, jobs=5, workers=2, sequential=2, baseline=False, budget_s=600.0, readers=(50,)
    )  # the budget stops a hang, it bounds no speed
    assert figures["reads"]["n"] == 100 and figures["reads"]["errors"] == 0
    during = figures["readers_while_jobs_run"]["50"]
    assert during["errors"] == 0 and during["n"] >= 50 and figures["reads_one_at_a_time"]["n"] == 2 * 4
    jobs = during["jobs"]
    assert jobs["submitted"] == jobs["succeeded"] == jobs["footprints_stored"] == 5 and jobs["lost"] == 0
    # every small study flies its 3 bank settings plus the zero-lift minimum range
    assert jobs["trajectories"] >= 5 * 3


def test_the_load_checks_can_fail(bench):
    """check_jobs reports a job that did not succeed, and one whose footprint went missing."""
    import asyncio

    import httpx

    failed = {"a": {"status": "failed", "error": "boom", "result": None}}
    with pytest.raises(AssertionError, match="did not succeed"):
        asyncio.run(bench.check_jobs(None, failed))

    def handler(request):
        if request.url.path == "/api/footprints/fp-1":
            return httpx.Response(404, json={"detail": "no footprint fp-1"})
        raise AssertionError(request.url)

    async def missing():
        async with httpx.AsyncClient(transport=httpx.MockTransport(handler), base_url="http://x") as client:
            await bench.check_jobs(
                client, {"j": {"status": "succeeded", "result": {"footprints": ["/api/footprints/fp-1"]}}}
            )

    with pytest.raises(AssertionError, match="HTTP 404"):
        asyncio.run(missing())
