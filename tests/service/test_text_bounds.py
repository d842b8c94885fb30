"""Issue 24 item 3: every text a request writes to a String column is bounded by that column's length, from one
table (footprint.contracts.bounds); the migrations agree with it, and a name too long is a 422 naming the field and
the bound, never a 500 or a job that flies and then fails to store."""

import copy
import json
import subprocess
import sys

import pytest
from sqlalchemy import String, inspect

from footprint.contracts import parse
from footprint.contracts.bounds import FOOTPRINT_NAME_CHARS, JOB_NAME_CHARS, TEXT_COLUMNS, VEHICLE_NAME_CHARS, fitted
from footprint.service.db.engine import make_engine, migrate
from footprint.service.db.models import Base
from footprint.service.settings import MIGRATIONS_DIR

from .conftest import DATABASES, database_url, running_service, wait_for_job
from .sample_requests import FOOTPRINT


def named_vehicle_study(chars: int) -> dict:
    """FOOTPRINT with an inline vehicle (the sample's built-in one, written out) named with `chars` characters."""
    study = copy.deepcopy(FOOTPRINT)
    study["case"]["vehicle"] = {
        "name": "V" * chars,
        "wing_loading_psf": 50,
        "aero": {"constant": {"cl": 0.5, "cd": 0.27}},
    }
    return study


def test_the_migrated_columns_have_the_tables_bounds(tmp_path):
    engine = make_engine(f"sqlite:///{tmp_path / 'bounds.db'}")
    migrate(engine, MIGRATIONS_DIR)
    with engine.connect() as c:
        inspector = inspect(c)
        migrated = {
            (t, col["name"]): col["type"].length
            for t in inspector.get_table_names()
            for col in inspector.get_columns(t)
            if isinstance(col["type"], String)
        }
    engine.dispose()
    for column, chars in TEXT_COLUMNS.items():
        assert migrated[column] == chars, column
        assert Base.metadata.tables[column[0]].c[column[1]].type.length == chars, column


def test_a_derived_name_keeps_its_tail_and_fits():
    name = fitted("V" * 500, "single_parameter 22000 fps -3 deg", JOB_NAME_CHARS)
    assert len(name) == JOB_NAME_CHARS and name.endswith("… single_parameter 22000 fps -3 deg")
    assert fitted("lod-1.89", "x 1 fps 2 deg", JOB_NAME_CHARS) == "lod-1.89 x 1 fps 2 deg"
    study = parse("footprint", named_vehicle_study(VEHICLE_NAME_CHARS))
    assert len(study.default_name()) <= JOB_NAME_CHARS


def test_the_cli_refuses_a_vehicle_name_past_its_bound_in_one_line(tmp_path):
    path = tmp_path / "study.json"
    path.write_text(json.dumps(named_vehicle_study(VEHICLE_NAME_CHARS + 100)))
    r = subprocess.run(
        [sys.executable, "-m", "footprint.cli", "footprint", str(path)], capture_output=True, text=True, timeout=300
    )
    assert r.returncode == 2 and r.stdout == ""
    assert len(r.stderr.strip().splitlines()) == 1
    assert "vehicle.name" in r.stderr and f"{VEHICLE_NAME_CHARS}" in r.stderr


@pytest.fixture(scope="module", params=DATABASES)
def client(request, scheduler_address, tmp_path_factory):
    with (
        database_url(request.param, tmp_path_factory.mktemp(request.param)) as url,
        running_service(url, scheduler_address) as c,
    ):
        yield c


@pytest.mark.parametrize("job_name", [None, "named"])
def test_a_vehicle_name_past_its_bound_is_a_422_naming_the_field(client, job_name):
    body = {"kind": "footprint", "study": named_vehicle_study(VEHICLE_NAME_CHARS + 100)}
    if job_name:
        body["name"] = job_name
    r = client.post("/api/jobs", json=body)
    assert r.status_code == 422, r.text
    assert "vehicle.name" in r.text and f"{VEHICLE_NAME_CHARS}" in r.text


def test_a_vehicle_name_at_its_bound_flies_stores_and_maps(client):
    r = client.post("/api/jobs", json={"kind": "footprint", "study": named_vehicle_study(VEHICLE_NAME_CHARS)})
    assert r.status_code == 202, r.text
    job = wait_for_job(client, r.json()["id"])
    assert job["status"] == "succeeded", job["error"]
    assert len(job["name"]) <= JOB_NAME_CHARS
    [fp] = client.get("/api/footprints", params={"job_id": job["id"]}).json()["items"]
    assert fp["vehicle"] == "V" * VEHICLE_NAME_CHARS and len(fp["name"]) <= FOOTPRINT_NAME_CHARS
    page = client.get(f"/api/footprints/{fp['id']}/map")  # was a 422 on SQLite with a longer name stored
    assert page.status_code == 200, page.text
