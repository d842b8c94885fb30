"""Issue 53 item 2: jobs waited invisibly ("queued · 0 %" for many minutes with no position, estimate, or sign of
what runs ahead). GET /api/queue lists the jobs not yet finished as the engine takes them (oldest first), each with
the jobs ahead of it and when it should end, from each kind's measured cost over the cluster's workers."""

import json
from datetime import datetime
from pathlib import Path

from .conftest import wait_for_job
from .sample_requests import FOOTPRINT

ROOT = Path(__file__).resolve().parents[2]
BETTS = json.loads((ROOT / "examples" / "optimize_betts_collocation.json").read_text())  # minutes of IPOPT


def seconds(job) -> float:
    at = [datetime.fromisoformat(job[k].replace("Z", "+00:00")) for k in ("started_at", "finished_at")]
    return (at[1] - at[0]).total_seconds()


def test_the_queue_says_what_is_ahead_and_when_each_job_ends(api):
    done = wait_for_job(api, api.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT}).json()["id"])
    assert done["status"] == "succeeded"
    # the kind's measured cost, by the jobs list's own times: the median of its succeeded jobs (up to 20)
    runs = api.get("/api/jobs", params={"kind": "footprint", "status": "succeeded", "limit": 20}).json()["items"]
    times = sorted(seconds(j) for j in runs)
    footprint_s = times[len(times) // 2]
    long_id = api.post("/api/jobs", json={"kind": "optimize", "study": BETTS}).json()["id"]
    behind = [api.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT}).json()["id"] for _ in range(2)]
    try:
        answer = api.get("/api/queue").json()
        jobs = answer["jobs"]
        ids = [j["id"] for j in jobs]
        assert long_id in ids, answer  # minutes of IPOPT: not finished yet
        assert all(j["status"] in ("queued", "running") for j in jobs)
        assert [j["created_at"] for j in jobs] == sorted(j["created_at"] for j in jobs)  # oldest first
        assert [j["ahead"] for j in jobs] == list(range(len(jobs)))
        assert abs(answer["costs"]["footprint"]["median_s"] - footprint_s) < 1e-3  # the list's timestamps are ms
        assert answer["workers"] >= 1
        # an optimization has no measured cost here: no estimate for it, nor for any job behind it
        k = ids.index(long_id)
        assert "optimize" not in answer["costs"] and all(j["ends_in_s"] is None for j in jobs[k:])
        # before it, each footprint ends its share of the measured work later than the one before
        ends = [j["ends_in_s"] for j in jobs[:k]]
        assert all(e is not None for e in ends) and ends == sorted(ends)
        for job in jobs[:k]:
            assert job["kind"] != "footprint" or job["ends_in_s"] <= footprint_s * (job["ahead"] + 1) + 1e-6
    finally:
        for job_id in [long_id, *behind]:
            api.delete(f"/api/jobs/{job_id}")
    for job_id in [long_id, *behind]:
        assert wait_for_job(api, job_id)["status"] in ("cancelled", "succeeded")
    assert not any(j["id"] in [long_id, *behind] for j in api.get("/api/queue").json()["jobs"])
