"""Guided entry through the service (issue 27): a guided case flown by POST /api/trajectories, a guided dispersion as
a job of chunk tasks on Dask with its stored result, a cancel that stops it, and bad guided input answered 422 naming
the field."""

import copy
import math

import pytest

from tests.core.test_guidance import INTERFACE_NMI, distance_nmi, guided, target
from tests.service.conftest import wait_for_job

STUDY = {
    "case": guided(5000.0, 600.0),
    "samples": 8,
    "chunk_samples": 4,
    "seed": 2,
    "radius_nmi": [5.0],
    "entry": {"gamma_deg": {"normal": {"std": 0.05}}},
    "vehicle": {"cd_multiplier": {"truncated_normal": {"std": 0.03, "sigmas": 3}}},
}

FOOTPRINT_STUDY = {
    "case": guided(5000.0, 600.0),
    "rays": 4,
    "samples": 4,
    "probability": 0.45,  # 4 of 4 show it with 95 % confidence (Clopper-Pearson bound 0.47)
    "optimal": False,
    "seed": 2,
    "entry": STUDY["entry"],
    "vehicle": STUDY["vehicle"],
}


def test_every_kind_fits_the_job_stores_kind_column():
    """guided_dispersion has 17 characters; the column had 16 (Postgres refused the job, SQLite stored it)."""
    from footprint.contracts import MODULES
    from footprint.service.db.models import Job

    assert max(len(kind) for kind in MODULES) <= Job.__table__.c.kind.type.length


def test_a_guided_case_flies_to_its_target(api):
    r = api.post("/api/trajectories", json=guided(5000.0, 600.0))
    assert r.status_code == 200, r.text
    s, h = r.json()["summary"], r.json()["history"]
    t = target(5000.0, 600.0)
    to_site = distance_nmi(h["latitude_deg"][-1], h["longitude_deg"][-1], t["latitude_deg"], t["longitude_deg"])
    miss = abs(to_site - INTERFACE_NMI)  # of the terminal-area interface circle (issue 50 item 3)
    assert miss == pytest.approx(s["guidance"]["miss_nmi"], abs=1e-6) and miss <= 1.0
    assert len(h["bank_command_deg"]) == len(h["time_s"]) == len(h["predicted_miss_nmi"])


def test_a_guided_dispersion_job_runs_chunk_by_chunk_and_stores_the_result(api):
    job = wait_for_job(api, api.post("/api/jobs", json={"kind": "guided_dispersion", "study": STUDY}).json()["id"])
    assert job["status"] == "succeeded", job
    got = job["result"]["guided_dispersion"]
    assert got["samples"] == 8 and got["run"]["tasks"] == 2 and got["run"]["workers"] >= 1
    t = got["target"]
    for mode in ("guided", "open_loop"):
        cloud = got["clouds"][mode]
        within = sum(
            lat is not None
            and abs(distance_nmi(lat, lon, t["latitude_deg"], t["longitude_deg"]) - INTERFACE_NMI) <= 5.0
            for lat, lon in zip(cloud["latitude_deg"], cloud["longitude_deg"])
        )
        assert got[mode]["within"][0]["samples_within"] == within
    assert got["nominal"]["guidance"]["miss_nmi"] <= 1.0
    assert got["guided"]["within"][0]["samples_within"] == 8
    assert len(got["nominal_flight"]["bank_command_deg"]) == len(got["nominal_flight"]["time_s"])


@pytest.mark.parametrize(
    "kind, long",
    [
        ("guided_dispersion", STUDY | {"samples": 5_000, "chunk_samples": 50}),
        ("guided_footprint", FOOTPRINT_STUDY | {"rays": 24, "samples": 1_000}),
    ],
)
def test_a_guided_job_is_cancelled(api, kind, long):
    job_id = api.post("/api/jobs", json={"kind": kind, "study": long}).json()["id"]
    r = api.delete(f"/api/jobs/{job_id}")
    assert r.status_code == 200 and r.json()["status"] == "cancelled" and r.json()["result"] is None
    assert wait_for_job(api, job_id)["status"] == "cancelled"


@pytest.mark.parametrize(
    "kind, base, change, field",
    [
        ("guided_dispersion", STUDY, {"samples": 50_000}, "study.samples"),
        (
            "guided_dispersion",
            STUDY,
            {"case": {**guided(5000.0, 600.0), "bank": {"law": "zero"}}},
            "study.case.bank.law",
        ),
        ("guided_dispersion", STUDY, {"case": guided(5000.0, 600.0, cycle_s=0.01)}, "study.case.bank.cycle_s"),
        ("guided_footprint", FOOTPRINT_STUDY, {"samples": 5_000}, "study.samples"),
        ("guided_footprint", FOOTPRINT_STUDY, {"rays": 3}, "study.rays"),
        (
            "guided_footprint",
            FOOTPRINT_STUDY,
            {"case": {**guided(5000.0, 600.0), "bank": {"law": "zero"}}},
            "study.case.bank.law",
        ),
    ],
)
def test_bad_guided_studies_are_422_naming_the_field(api, kind, base, change, field):
    r = api.post("/api/jobs", json={"kind": kind, "study": copy.deepcopy(base) | change})
    assert r.status_code == 422 and r.json()["field"].startswith(field), r.json()


def test_a_guided_footprint_job_traces_ray_by_ray_and_stores_its_boundaries(api):
    submitted = api.post("/api/jobs", json={"kind": "guided_footprint", "study": FOOTPRINT_STUDY})
    job = wait_for_job(api, submitted.json()["id"])
    assert job["status"] == "succeeded", job
    got = job["result"]["guided_footprint"]
    assert got["run"]["tasks"] == 1 + 4 and [r["angle_deg"] for r in got["rays"]] == [0.0, 90.0, 180.0, 270.0]
    f = got["frame"]
    for r in got["rays"]:  # each ray's boundary point is where its s puts it on the frame's ellipse
        a = math.radians(r["angle_deg"])
        assert r["guided"]["downrange_nmi"] == pytest.approx(
            f["center_nmi"] + r["s_guided"] * f["half_length_nmi"] * math.cos(a)
        )
        assert r["guided"]["crossrange_nmi"] == pytest.approx(
            r["s_guided"] * f["half_width_nmi"] * math.sin(a), abs=1e-9
        )
        assert 0.0 < r["s_guided"] <= r["s_nominal"] < r["s_report"]
    assert len(got["guided"]["latitude_deg"]) == 4 and got["margin_to_report"]["inside_at_every_ray"]


def test_a_guided_reach_job_says_each_sites_guided_probability(api):
    sites = [{"name": "A <b>site</b>", **target(5000.0, 600.0)}, {"name": "short", **target(1500.0, 0.0)}]
    study = {"case": guided(5000.0, 600.0), "sites": sites, "samples": 3, "seed": 2, "entry": STUDY["entry"]}
    job = wait_for_job(api, api.post("/api/jobs", json={"kind": "guided_reach", "study": study}).json()["id"])
    assert job["status"] == "succeeded", job
    got = job["result"]["guided_reach"]
    assert got["run"]["tasks"] == 2 and [s["name"] for s in got["sites"]] == ["A <b>site</b>", "short"]
    assert [s["samples_within"] for s in got["sites"]] == [3, 0]
    r = api.post("/api/jobs", json={"kind": "guided_reach", "study": study | {"samples": 15_000}})
    assert r.status_code == 422 and r.json()["field"] == "study.samples", r.json()
    assert "2 sites x 15,000 samples" in r.json()["detail"]
