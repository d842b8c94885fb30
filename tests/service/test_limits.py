"""Bad input over HTTP: every limit answered 422 naming the field, unknown ids 404, big bodies 413; bearer
auth on writes (reads stay open) and CORS from the settings."""

import copy

import pytest

from .conftest import database_url, running_service
from .sample_requests import CASE, FOOTPRINT, REACH, SWEEP, UNKNOWN_ID


def post_job(api, kind, study, **headers):
    return api.post("/api/jobs", json={"kind": kind, "study": study}, headers=headers)


def with_changes(study: dict, path: str, value) -> dict:
    """A deep copy of `study` with the dotted `path` set to `value`."""
    study = copy.deepcopy(study)
    *parents, last = path.split(".")
    node = study
    for key in parents:
        node = node[key]
    node[last] = value
    return study


@pytest.mark.parametrize(
    "path, value, field, allowed",
    [
        ("case.entry.velocity_fps", 50, "study.case.entry.velocity_fps", "1,000 to 40,000 ft/s"),
        ("case.entry.velocity_fps", 45_000, "study.case.entry.velocity_fps", "1,000 to 40,000 ft/s"),
        ("case.entry.gamma_deg", 20, "study.case.entry.gamma_deg", "-90 to 10 deg"),
        ("case.entry.latitude_deg", -91, "study.case.entry.latitude_deg", "-90 to 90 deg"),
        ("bank0_deg", [float(b) for b in range(101)], "study.bank0_deg", "1 to 200"),  # 101 x 2 sides
        ("bank0_deg", [200], "study.bank0_deg.0", "0 to 180 deg"),
    ],
)
def test_a_footprint_job_out_of_range_names_the_field(api, path, value, field, allowed):
    r = post_job(api, "footprint", with_changes(FOOTPRINT, path, value))
    assert r.status_code == 422
    assert r.json()["field"] == field and r.json()["detail"].startswith(field + ":") and allowed in r.json()["detail"]


def test_other_job_kinds_name_their_fields(api):
    r = post_job(api, "sweep", with_changes(SWEEP, "entry_velocity_fps", [500]))
    assert r.status_code == 422 and r.json()["field"] == "study.entry_velocity_fps.0"
    r = post_job(api, "sweep", with_changes(SWEEP, "vehicles", [{"stored": "nobody"}]))
    assert r.status_code == 422 and r.json()["field"] == "study.vehicles.0.stored"
    r = post_job(api, "optimize", {"case": CASE, "max_trajectories": 5})
    assert r.status_code == 422 and r.json()["field"] == "study.max_trajectories"
    r = post_job(api, "reach", with_changes(REACH, "orbit.inclination_deg", 200))
    assert r.status_code == 422 and r.json()["field"] == "study.orbit.inclination_deg"
    r = api.post("/api/jobs", json={"kind": "flight", "study": FOOTPRINT})
    assert r.status_code == 422 and r.json()["field"] == "kind"
    r = post_job(
        api,
        "footprint",
        with_changes(FOOTPRINT, "case.vehicle", {"aero": {"constant": {"cl": 1, "cd": 0}}, "wing_loading_psf": 50}),
    )
    assert r.status_code == 422 and r.json()["field"] == "study.case.vehicle.aero.constant.cd"
    assert api.get("/api/jobs", params={"kind": "footprint", "status": "queued"}).json()["total"] == 0  # none stored


def test_a_trajectory_out_of_range_names_the_field(api):
    r = api.post("/api/trajectories", json={**CASE, "bank": {"law": "constant", "bank_deg": 181}})
    assert r.status_code == 422 and r.json()["field"] == "bank.bank_deg" and "-180 to 180 deg" in r.json()["detail"]
    r = api.post("/api/trajectories", json={**CASE, "entry": {**CASE["entry"], "velocity_fps": 999}})
    assert r.status_code == 422 and r.json()["field"] == "entry.velocity_fps"
    r = api.post("/api/trajectories", content=b"{not json", headers={"content-type": "application/json"})
    assert r.status_code == 422 and "JSON" in r.json()["detail"]


def test_transform_points_are_limited_to_ten_thousand(api):
    body = {
        "points": [{"latitude_deg": 0, "longitude_deg": 0}] * 10_001,
        "from": {"latitude_deg": 0, "longitude_deg": 0, "heading_deg": 90},
        "to": {"latitude_deg": 0, "longitude_deg": 10, "heading_deg": 90},
    }
    r = api.post("/api/transform", json=body)
    assert r.status_code == 422 and r.json()["field"] == "points" and "10,000" in r.json()["detail"]
    assert api.post("/api/transform", json=body | {"points": body["points"][:10_000]}).status_code == 200


def test_a_body_over_one_megabyte_is_refused(api):
    big = {"kind": "footprint", "study": FOOTPRINT, "name": "x" * 1_000_001}
    r = api.post("/api/jobs", json=big)
    assert r.status_code == 413 and "1,000,000 bytes" in r.json()["detail"]

    def chunks():  # no content-length: counted as it streams
        for _ in range(11):
            yield b" " * 100_000

    r = api.post("/api/trajectories", content=chunks(), headers={"content-type": "application/json"})
    assert r.status_code == 413


@pytest.mark.parametrize(
    "path",
    [
        f"/api/jobs/{UNKNOWN_ID}",
        f"/api/footprints/{UNKNOWN_ID}",
        f"/api/footprints/{UNKNOWN_ID}?format=geojson",
        "/api/vehicles/0f0e",
        "/api/sites/999999",
    ],
)
def test_unknown_ids_are_404(api, path):
    r = api.get(path)
    assert r.status_code == 404 and r.json()["detail"]
    assert api.delete(path.split("?")[0]).status_code in (404, 405)


@pytest.fixture(scope="module")
def guarded(scheduler_address, tmp_path_factory):
    with (
        database_url("sqlite", tmp_path_factory.mktemp("guarded")) as url,
        running_service(
            url, scheduler_address, api_token="s3cret", cors_origins="https://planner.example, http://localhost:5173"
        ) as client,
    ):
        yield client


def test_writes_need_the_bearer_token_and_reads_do_not(guarded):
    site = {"name": "KSC", "latitude_deg": 28.6, "longitude_deg": -80.6}
    for headers in ({}, {"Authorization": "Bearer wrong"}, {"Authorization": "s3cret"}):
        r = guarded.post("/api/sites", json=site, headers=headers)
        assert r.status_code == 401 and r.headers["www-authenticate"] == "Bearer"
        assert post_job(guarded, "footprint", FOOTPRINT, **headers).status_code == 401
    ok = guarded.post("/api/sites", json=site, headers={"Authorization": "Bearer s3cret"})
    assert ok.status_code == 201
    assert guarded.delete(f"/api/sites/{ok.json()['id']}").status_code == 401
    assert guarded.get("/api/sites").status_code == 200 and guarded.get("/api/health").status_code == 200
    assert guarded.get(f"/api/sites/{ok.json()['id']}").json()["name"] == "KSC"


def test_computations_that_store_nothing_need_no_token(guarded):
    """Issue 15 item 4: every POST counted as a write, so with a token set the page could not even fly a trajectory
    or move a footprint. A computation that stores nothing is open like a read; a reach that keeps its verdicts
    with the stored sites is a write."""
    assert guarded.post("/api/trajectories", json=CASE).status_code == 200
    assert guarded.post("/api/reach", json=REACH).status_code == 200
    assert guarded.post("/api/reach?store_verdicts=true", json=REACH | {"sites": []}).status_code == 401
    assert (
        guarded.post(
            "/api/transform",
            json={
                "points": [{"latitude_deg": 0, "longitude_deg": 0}],
                "from": {"latitude_deg": 0, "longitude_deg": 0, "heading_deg": 90},
                "to": {"latitude_deg": 0, "longitude_deg": 10, "heading_deg": 90},
            },
        ).status_code
        == 200
    )


def test_cors_allows_the_configured_origins_only(guarded, api):
    preflight = {"Access-Control-Request-Method": "POST", "Access-Control-Request-Headers": "content-type"}
    allowed = guarded.options("/api/jobs", headers={"Origin": "http://localhost:5173", **preflight})
    assert allowed.status_code == 200
    assert allowed.headers["access-control-allow-origin"] == "http://localhost:5173"
    other = guarded.get("/api/health", headers={"Origin": "https://elsewhere.example"})
    assert "access-control-allow-origin" not in other.headers
    simple = guarded.get("/api/health", headers={"Origin": "https://planner.example"})
    assert simple.headers["access-control-allow-origin"] == "https://planner.example"
    unconfigured = api.get("/api/health", headers={"Origin": "https://planner.example"})
    assert "access-control-allow-origin" not in unconfigured.headers


def test_every_footprint_method_has_its_point_count_checked():
    """The count of boundary points lives on each study model and knows every method (a temperature-limited
    study reached `turn_deg` in the service's own switch and answered 500 on every route that accepts it)."""
    from pydantic import ValidationError

    from footprint import contracts
    from footprint.contracts.doors import HTTP, context
    from footprint.contracts.messages import error_line

    heated = CASE | {"heating": {"model": "reference"}}
    http = context(HTTP)
    contracts.parse("footprint", {"case": heated, "method": "temperature_limited", "limit_R": 2550}, http)
    contracts.parse("footprint", {"case": CASE, "method": "collocation", "points_per_half": 11}, http)
    wide = {
        "case": heated,
        "method": "temperature_limited",
        "limit_R": 2550,
        "bank0_deg": [float(b % 180) for b in range(181)],
    }
    with pytest.raises(ValidationError) as err:
        contracts.parse("footprint", wide, http)
    assert error_line(err.value).startswith(
        "bank0_deg: 181 settings x 2 sides = 362 footprint points is outside the allowed range 1 to 200 over HTTP"
    )
    assert contracts.parse("footprint", wide).settings() == ("bank0_deg", 181)  # the CLI's own machine: allowed


def test_a_synchronous_reach_is_bounded_to_seconds_and_the_same_reach_runs_as_a_job(api):
    """Issue 15 item 3: POST /api/reach at its documented caps took 44 s in the API process. A synchronous request
    is bounded to about two seconds of work (a 422 naming the field and the limit); the same request is a reach job,
    whose limit is the contract's; a collocation study (a minute of NLP solves) is only ever a job."""
    many = REACH | {
        "sites": [
            {"name": f"s{i}", "latitude_deg": (i % 170) - 85.0, "longitude_deg": float(i % 360)} for i in range(1_000)
        ],
        "revolutions": {"first": 1, "last": 60},
        "u_step_deg": 0.5,
    }  # 4 points, 43,200 placements
    r = api.post("/api/reach", json=many)
    assert r.status_code == 422 and r.json()["field"] == "sites", r.text
    assert "at most 2e+07 in a synchronous request" in r.json()["detail"]
    job = api.post("/api/jobs", json={"kind": "reach", "study": many})
    assert job.status_code == 202, job.text
    api.delete(f"/api/jobs/{job.json()['id']}")
    optimal = {"case": CASE, "method": "collocation", "points_per_half": 3}
    r = api.post("/api/reach", json=REACH | {"footprint": {"study": optimal}})
    assert r.status_code == 422 and r.json()["field"] == "footprint.study.method", r.text


@pytest.mark.parametrize(
    "query",
    [
        "store_verdicts=1",
        "store_verdicts=yes",
        "store_verdicts=on",
        "store_verdicts=t",
        "store_verdicts=y",
        "store_verdicts=%74rue",
        "store%5Fverdicts=true",
        "store_verdicts=TRUE",
        "store_verdicts=false&store_verdicts=1",
    ],
)
def test_every_spelling_of_store_verdicts_needs_the_token(guarded, query):
    """Issue 24 item 2: the guard looked for the text "store_verdicts=true", and each of these (true to the route's
    parser) overwrote the stored sites' verdicts without the token."""
    token = {"Authorization": "Bearer s3cret"}
    site = guarded.post(
        "/api/sites", json={"name": "Kourou", "latitude_deg": 5.2, "longitude_deg": -52.8}, headers=token
    ).json()
    try:
        before = guarded.get("/api/sites").json()
        assert guarded.post(f"/api/reach?{query}", json=REACH | {"sites": []}).status_code == 401
        assert guarded.get("/api/sites").json() == before
        assert guarded.post(f"/api/reach?{query}", json=REACH | {"sites": []}, headers=token).status_code == 200
    finally:
        guarded.delete(f"/api/sites/{site['id']}", headers=token)


@pytest.mark.parametrize("query", ["store_verdicts=false", "store_verdicts=0", "store_verdicts=off", ""])
def test_a_reach_that_keeps_nothing_stays_open(guarded, query):
    assert guarded.post(f"/api/reach?{query}", json=REACH).status_code == 200
