"""Input that once answered 500 (issue 15 items 6 and 11): numbers past what the database holds, the NUL character
in any text (Postgres refuses it), huge values echoed back, invalid JSON, HEAD; each now a 4xx naming the field, on
SQLite and Postgres. Job errors and /api/health carry no SQL text and no internal address."""

import copy
import re

import pytest

from tests.authorities.report import example
from tests.test_error_words import OVERFLOWING_TLE

from .conftest import database_url, running_service
from .sample_requests import FOOTPRINT, SHUTTLE, UNKNOWN_ID

HUGE = "99999999999999999999"  # past SQLite's 64-bit integers
PAST_INT4 = "2147483648"  # past a Postgres integer column
GLIDER = {"aero": {"constant": {"cl": 0.5, "cd": 0.25}}, "wing_loading_psf": 50}


def assert_names(r, field: str, status: int = 422):
    assert r.status_code == status, r.text
    assert r.json()["field"] == field and r.json()["detail"].startswith(f"{field}: "), r.json()
    assert "\n" not in r.json()["detail"]


@pytest.mark.parametrize("path", ["/api/jobs", "/api/footprints"])
def test_an_offset_past_any_list_is_422(api, path):
    r = api.get(path, params={"offset": HUGE})
    assert_names(r, "offset")
    assert "2147483647" in r.json()["detail"]
    assert api.get(path, params={"offset": 2_147_483_647}).json()["items"] == []


@pytest.mark.parametrize("site_id", [HUGE, PAST_INT4])
def test_a_site_id_past_the_id_column_is_422(api, site_id):
    site = {"name": "KSC", "latitude_deg": 28.6, "longitude_deg": -80.6}
    assert_names(api.get(f"/api/sites/{site_id}"), "site_id")
    assert_names(api.put(f"/api/sites/{site_id}", json=site), "site_id")
    assert_names(api.delete(f"/api/sites/{site_id}"), "site_id")
    assert api.get("/api/sites/2147483647").status_code == 404


def test_nul_in_any_stored_text_is_422_naming_the_field(api):
    site = {"name": "K\x00SC", "latitude_deg": 28.6, "longitude_deg": -80.6}
    assert_names(api.post("/api/sites", json=site), "name")
    stored = api.post("/api/sites", json=site | {"name": "KSC"}).json()
    assert_names(api.put(f"/api/sites/{stored['id']}", json=site), "name")
    csv = b"name,latitude_deg,longitude_deg\nKSC,28.6,-80.6\nEd\x00wards,34.9,-117.9\n"
    assert_names(api.post("/api/sites/csv", content=csv, headers={"content-type": "text/csv"}), "line 3")
    job = {"kind": "footprint", "study": FOOTPRINT, "name": "nul\x00"}
    assert_names(api.post("/api/jobs", json=job), "name")
    study = copy.deepcopy(FOOTPRINT)
    study["case"]["vehicle"] = SHUTTLE | {"name": "Shuttle\x00"}  # once stored, then the job failed with its SQL
    assert_names(api.post("/api/jobs", json={"kind": "footprint", "study": study}), "study.case.vehicle.name")
    assert_names(api.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT | {"\x00": 1}}), "study")
    assert_names(api.post("/api/vehicles", json={"id": "g", "description": "\x00", "vehicle": GLIDER}), "description")
    assert_names(api.get("/api/footprints", params={"job_id": "\x00"}), "job_id")
    assert api.get("/api/jobs/%00").status_code == 404  # no stored id holds one
    assert api.get("/api/vehicles/a%00b").status_code == 404
    assert api.get("/api/sites").json() == [stored]  # nothing else stored


def test_a_backslash_before_u0000_is_not_nul(api):
    r = api.post("/api/sites", json={"name": "C:\\u0000", "latitude_deg": 0, "longitude_deg": 0})
    assert r.status_code == 201 and r.json()["name"] == "C:\\u0000"
    assert api.delete(f"/api/sites/{r.json()['id']}").status_code == 204


def test_a_job_error_carries_no_sql_and_no_address():
    from sqlalchemy import create_engine, text
    from sqlalchemy.exc import DBAPIError

    from footprint.service.jobs.engine import one_line

    engine = create_engine("sqlite://")
    with pytest.raises(DBAPIError) as err, engine.connect() as c:
        c.execute(text("SELECT * FROM footprints WHERE name = :name"), {"name": "secret"})
    line = one_line(err.value)
    assert line.startswith("OperationalError: ") and "no such table" in line, line
    assert "SELECT" not in line and "secret" not in line and "sqlalche.me" not in line
    died = RuntimeError(
        "Attempted to run task footprint_task-1 on 4 different workers, but all those workers died "
        "while running it. The last worker that attempt to run the task was tcp://10.1.2.3:40145."
    )
    assert "10.1.2.3" not in one_line(died) and "40145" not in one_line(died) and "worker" in one_line(died)


def test_health_shows_no_scheduler_address_without_the_token(api):
    cluster = api.get("/api/health").json()["cluster"]
    assert cluster["ok"] and cluster["workers"] == 2 and "scheduler" not in cluster


@pytest.fixture(scope="module")
def guarded(scheduler_address, tmp_path_factory):
    with (
        database_url("sqlite", tmp_path_factory.mktemp("guarded")) as url,
        running_service(url, scheduler_address, api_token="s3cret") as client,
    ):
        client.scheduler_address = scheduler_address
        yield client


def test_health_shows_the_scheduler_address_with_the_token_only(guarded):
    for headers in ({}, {"Authorization": "Bearer wrong"}):
        assert "scheduler" not in guarded.get("/api/health", headers=headers).json()["cluster"]
    cluster = guarded.get("/api/health", headers={"Authorization": "Bearer s3cret"}).json()["cluster"]
    assert cluster["scheduler"] == guarded.scheduler_address


def test_the_bearer_token_is_compared_in_constant_time(guarded, monkeypatch):
    import hmac

    from footprint.service import deps

    compared, original = [], hmac.compare_digest
    monkeypatch.setattr(deps.hmac, "compare_digest", lambda a, b: compared.append((a, b)) or original(a, b))
    assert guarded.post("/api/sites", json={}, headers={"Authorization": "Bearer wrong"}).status_code == 401
    assert compared == [(b"Bearer wrong", b"Bearer s3cret")]


# issue 15 item 11
@pytest.mark.parametrize(
    "path, body, field",
    [
        ("/api/sites", {"name": "x" * 200_000, "latitude_deg": 0, "longitude_deg": 0}, "name"),
        ("/api/sites", {"name": "KSC", "latitude_deg": 0, "longitude_deg": 0, "x" * 200_000: 1}, "x" * 77 + "..."),
        ("/api/jobs", {"kind": "footprint", "study": FOOTPRINT | {"y" * 200_000: 1}}, "study." + "y" * 77 + "..."),
        ("/api/trajectories", {"vehicle": {"stored": "z" * 200_000}}, "vehicle.stored"),
        (
            "/api/transform",
            {"points": [{"latitude_deg": "w" * 1_000, "longitude_deg": 0}] * 500},
            "points.0.latitude_deg",
        ),
    ],
)
def test_a_422_echoes_no_huge_value(api, path, body, field):
    r = api.post(path, json=body)
    assert r.status_code == 422 and r.json()["field"] == field, r.text[:300]
    assert len(r.content) < 12_000, r.text[:300]


def test_invalid_json_names_the_body(api):
    for path in ("/api/trajectories", "/api/sites", "/api/jobs"):
        r = api.post(path, content=b'{"name": ', headers={"content-type": "application/json"})
        assert_names(r, "body")
        assert "not valid JSON" in r.json()["detail"]


def test_head_is_answered_wherever_get_is(api):
    for path in (
        "/api/health",
        "/api/jobs",
        "/api/vehicles",
        "/api/sites",
        "/openapi.json",
        "/docs",
        "/",
        "/js/main.js",
    ):
        get, head = api.get(path), api.head(path)
        assert head.status_code == get.status_code == 200, path
        assert head.content == b"" and head.headers["content-type"] == get.headers["content-type"], path
    assert api.head("/api/sites/2147483647").status_code == 404
    r = api.head("/api/trajectories")
    assert r.status_code == 405 and r.headers["allow"] == "POST"


def test_a_head_of_a_job_events_stream_ends_at_once(api):
    job = api.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT}).json()
    r = api.head(job["events"])
    assert r.status_code == 200 and r.content == b"" and r.headers["content-type"].startswith("text/event-stream")
    api.delete(job["url"])


@pytest.mark.parametrize(
    "path",
    [
        "/package.json",
        "/package-lock.json",
        "/README.md",
        "/scripts/vendor.mjs",
        "/.gitignore",
        "/node_modules/leaflet/package.json",
        "/js/../package.json",
        "/vendor/../package-lock.json",
    ],
)
def test_only_the_pages_own_files_are_served(api, path):
    assert api.get(path).status_code == 404


def test_the_page_and_the_docs_find_every_file_they_load(api):
    import re

    page = api.get("/").text
    assert page == api.get("/index.html").text
    loaded = re.findall(r'(?:src|href)="((?:vendor|js)/[^"]+|styles\.css)"', page)
    loaded += re.findall(r'"(/vendor/[^"]+)"', api.get("/docs").text + api.get("/redoc").text)
    assert len(loaded) >= 8
    for path in loaded + ["vendor/world/land-110m.json", "vendor/leaflet/images/marker-icon.png"]:
        assert api.get("/" + path.lstrip("/")).status_code == 200, path


def test_every_path_of_the_api_document_names_its_methods_in_allow(api):
    """The guard's compiled path table (errors.ApiPaths) against a second source, the OpenAPI document: a method no
    route answers gets 405 with Allow naming exactly the document's methods at that path, and HEAD wherever GET."""
    document = api.get("/openapi.json").json()["paths"]
    order = ["GET", "HEAD", "POST", "PUT", "PATCH", "DELETE", "OPTIONS", "TRACE"]
    for template, operations in document.items():
        integers = {
            p["name"]
            for op in operations.values()
            for p in op.get("parameters", [])
            if p["in"] == "path" and p["schema"].get("type") == "integer"
        }
        path = re.sub(r"\{([^}]+)\}", lambda m: "7" if m[1] in integers else UNKNOWN_ID, template)
        methods = {m.upper() for m in operations} | ({"HEAD"} if "get" in operations else set())
        r = api.request("TRACE", path)
        assert r.status_code == 405, (template, r.text)
        assert r.headers["allow"] == ", ".join(m for m in order if m in methods), template


def test_a_study_whose_validation_breaks_pythons_arithmetic_is_422_naming_the_study(api):
    """Issue 49 item 2: an OverflowError inside a study's validator (elements whose epoch has lost its point) passed
    through pydantic and the service answered 500."""
    study = copy.deepcopy(example("opportunities_iss_20_sites")) | {"tle": OVERFLOWING_TLE}
    r = api.post("/api/jobs", json={"kind": "opportunities", "study": study})
    assert r.status_code == 422, r.text[:300]
    assert r.json()["field"].startswith("study") and "\n" not in r.json()["detail"]
