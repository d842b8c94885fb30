"""Issue 14: a temperature-limited footprint study runs through every route that accepts a footprint study (a
footprint job, a reach job, the synchronous reach, the exact transform). The service once learned the footprint
methods again in its own switch, reached `turn_deg` for this study and answered 500 on all of them; the count of
points now lives on the study's model. Each answer is checked against the Python door's footprint of the same
study (a second route to the same numbers)."""

import pytest

import footprint
from footprint import parallel
from tests.authorities.report import example
from tests.service.conftest import wait_for_job
from tests.service.sample_requests import CASE

LIMITED = example("footprint_lod189_limited_2550R") | {"bank0_deg": [0, 60]}  # Section III's limit, 0.8 s
ORBIT = {"inclination_deg": 28.5, "altitude_nmi": 150, "node_longitude_deg": 0}
SITES = [
    {"name": "near the track", "latitude_deg": 0.0, "longitude_deg": 60.0},
    {"name": "antipode", "latitude_deg": 0.0, "longitude_deg": 180.0},
]


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
        [p.downrange_nmi for p in direct.points], rel=1e-9
    )


def test_a_reach_of_a_temperature_limited_study_runs_synchronously_and_as_a_job(api, direct):
    request = {
        "footprint": {"study": LIMITED},
        "orbit": ORBIT,
        "sites": SITES,
        "revolutions": {"first": 1, "last": 2},
        "earth_rotation": "none",
    }
    now = api.post("/api/reach", json=request)
    assert now.status_code == 200, now.text
    assert now.json()["footprint"]["method"] == "temperature_limited"
    assert now.json()["footprint"]["max_downrange_nmi"] == pytest.approx(direct.max_downrange_nmi, rel=1e-9)
    created = api.post("/api/jobs", json={"kind": "reach", "study": request})
    job = wait_for_job(api, created.json()["id"])
    assert job["status"] == "succeeded", job
    assert job["result"]["reach"]["sites"] == now.json()["sites"]


def test_an_exact_transform_flies_a_temperature_limited_study_again(api, direct):
    """The exact transform flies the study again on the rotating earth from the destination: over HTTP as from
    Python (footprint.contracts.transform), one point per flown point of the footprint."""

    entry = LIMITED["case"]["entry"]
    here = {
        "latitude_deg": entry["latitude_deg"],
        "longitude_deg": entry["longitude_deg"],
        "heading_deg": entry["heading_deg"],
    }
    request = {"from": here, "to": here | {"longitude_deg": 30.0}, "earth_rotation": "exact", "study": LIMITED}
    r = api.post("/api/transform", json=request)
    assert r.status_code == 200, r.text
    python = parallel.run("transform", request)
    served = r.json()["points"]
    assert [sorted(p) for p in served] == [sorted(p) for p in python["points"]]
    numbers = [(k, p[k]) for p in python["points"] for k in sorted(p) if isinstance(p[k], float)]
    assert [p[k] for p in served for k in sorted(p) if isinstance(p[k], float)] == pytest.approx(
        [v for _, v in numbers], rel=1e-12
    )  # pytest 9.2's approx takes no list of dicts
    assert [{k: v for k, v in p.items() if not isinstance(v, float)} for p in served] == [
        {k: v for k, v in p.items() if not isinstance(v, float)} for p in python["points"]
    ]
    assert sum(p["on_boundary"] for p in r.json()["points"]) == len(direct.points)


def test_a_limit_no_setting_can_meet_fails_the_job_with_one_line(api):
    """At 22,000 ft/s and -3 deg no single-parameter setting of the L/D 1.89 vehicle cools to 2,550 degR with any
    alpha floor: the job fails and says so (it once failed with "max() arg is an empty sequence")."""
    hot = {
        "case": CASE | {"heating": {"model": "reference"}},
        "method": "temperature_limited",
        "limit_R": 2_550,
        "bank0_deg": [0, 60],
    }
    job = wait_for_job(api, api.post("/api/jobs", json={"kind": "footprint", "study": hot}).json()["id"])
    assert job["status"] == "failed"
    assert job["error"].startswith("InputError: limit_R: 2550 degR cannot be met: no bank setting of bank0_deg")
