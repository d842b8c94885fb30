"""Issue 14: a temperature-limited footprint study runs through every route that accepts a footprint study (a
footprint job, a reach job, the synchronous reach, the exact transform). The service once learned the footprint
methods again in its own switch, reached `turn_deg` for this study and answered 500 on all of them; the count of
points now lives on the study's model. Each answer is checked against the Python door's footprint of the same
study (a second route to the same numbers)."""

import pytest

import footprint
from tests.service.conftest import wait_for_job
from tests.service.sample_requests import CASE

LIMITED = {"case": CASE | {"heating": {"model": "reference"}}, "method": "temperature_limited", "limit_R": 2_550,
           "bank0_deg": [0, 60]}
ORBIT = {"inclination_deg": 28.5, "altitude_nmi": 150, "node_longitude_deg": 0}
SITES = [{"name": "near the track", "latitude_deg": 10.0, "longitude_deg": 40.0},
         {"name": "antipode", "latitude_deg": -10.0, "longitude_deg": -140.0}]


@pytest.fixture(scope="module")
def direct():
    return footprint.footprint(LIMITED)


def test_a_temperature_limited_footprint_job_is_the_python_doors_footprint(api, direct):
    created = api.post("/api/jobs", json={"kind": "footprint", "study": LIMITED})
    assert created.status_code == 202, created.text
    job = wait_for_job(api, created.json()["id"])
    assert job["status"] == "succeeded", job
    stored = api.get(job["result"]["footprints"][0]).json()
    assert stored["method"] == "temperature_limited"
    assert [p["downrange_nmi"] for p in stored["points"]] == pytest.approx(
        [p.downrange_nmi for p in direct.points], rel=1e-9)


def test_a_reach_of_a_temperature_limited_study_runs_synchronously_and_as_a_job(api, direct):
    request = {"footprint": {"study": LIMITED}, "orbit": ORBIT, "sites": SITES, "revolutions": {"first": 1, "last": 2},
               "earth_rotation": "none"}
    now = api.post("/api/reach", json=request)
    assert now.status_code == 200, now.text
    assert now.json()["footprint"]["method"] == "temperature_limited"
    assert now.json()["footprint"]["max_downrange_nmi"] == pytest.approx(direct.max_downrange_nmi, rel=1e-9)
    created = api.post("/api/jobs", json={"kind": "reach", "study": request})
    job = wait_for_job(api, created.json()["id"])
    assert job["status"] == "succeeded", job
    assert job["result"]["reach"]["sites"] == now.json()["sites"]


def test_an_exact_transform_flies_a_temperature_limited_study_again(api, direct):
    entry = CASE["entry"]
    here = {"latitude_deg": entry["latitude_deg"], "longitude_deg": entry["longitude_deg"],
            "heading_deg": entry["heading_deg"]}
    r = api.post("/api/transform", json={"from": here, "to": here, "earth_rotation": "exact", "study": LIMITED})
    assert r.status_code == 200, r.text
    boundary = [p for p in r.json()["points"] if p["on_boundary"]]
    assert len(boundary) == len(direct.points)  # the same study flown from the same place: the same boundary
    assert max(p["downrange_nmi"] for p in boundary) == pytest.approx(direct.max_downrange_nmi, rel=1e-9)
