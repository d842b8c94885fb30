"""docs/api.md matches the service (issue 13 item 9): every JSON example in it is accepted as written."""

import json
import re
from pathlib import Path

import pytest

from .conftest import wait_for_job
from .sample_requests import UNKNOWN_ID

DOC = Path(__file__).resolve().parents[2] / "docs" / "api.md"
EXAMPLES = re.findall(r"```json (POST|PUT|PATCH) (\S+)\n(.*?)\n```", DOC.read_text(), flags=re.S)

# every job kind the issues asked for, each typed in the document
JOB_KINDS = {
    "footprint",
    "optimize",
    "sweep",
    "reach",
    "dispersion",
    "guided_dispersion",
    "guided_footprint",
    "guided_reach",
    "opportunities",
}


def test_the_document_has_examples_of_every_kind_of_write():
    paths = {p for _, p, _ in EXAMPLES}
    assert {"/api/trajectories", "/api/jobs", "/api/transform", "/api/sites", "/api/reach", "/api/vehicles"} <= paths


@pytest.mark.parametrize("method, path, body", EXAMPLES, ids=[f"{m} {p} {i}" for i, (m, p, _) in enumerate(EXAMPLES)])
def test_every_example_in_the_api_document_is_accepted(api, method, path, body):
    response = api.request(method, path, json=json.loads(body))
    assert response.status_code < 300, response.text
    if path == "/api/jobs":
        job = wait_for_job(api, response.json()["id"])
        assert job["status"] == "succeeded", job["error"]


def test_the_openapi_document_declares_the_error_body_the_service_sends(api):
    """Issue 14 item 2 (part): FastAPI's default 422 schema (a list of loc/msg) is not what the service answers;
    every operation declares ErrorBody for its errors, and real error answers fit it."""
    from footprint.service.errors import ErrorBody

    spec = api.get("/openapi.json").json()
    ref = {"$ref": "#/components/schemas/ErrorBody"}
    assert "HTTPValidationError" not in spec["components"]["schemas"]
    for path, operations in spec["paths"].items():
        for method, op in operations.items():
            errors = {c: r for c, r in op["responses"].items() if c.startswith(("4", "5"))}
            assert "422" in errors, (method, path)
            if path == "/api/health":  # a degraded service's 503 is its health, for a deployment's check to read
                health = errors.pop("503")["content"]["application/json"]["schema"]
                assert health == {"$ref": "#/components/schemas/Health"}
            assert all(r["content"]["application/json"]["schema"] == ref for r in errors.values()), (method, path)
            if "{" in path:
                assert "404" in errors, (method, path)
            if method in ("post", "put", "patch", "delete"):
                assert {"401", "413"} <= set(errors), (method, path)
    assert "409" in spec["paths"]["/api/vehicles"]["post"]["responses"]
    answers = [
        api.post(
            "/api/trajectories",
            json={
                "vehicle": {"builtin": "lod-1.89"},
                "entry": {"altitude_ft": 364800, "velocity_fps": 50, "gamma_deg": -2},
            },
        ),
        api.get(f"/api/footprints/{UNKNOWN_ID}"),
        api.post("/api/jobs", json={"kind": "nope"}),
        api.post(
            "/api/vehicles",
            json={"id": "lod-1.89", "vehicle": {"aero": {"constant": {"cl": 1, "cd": 1}}, "wing_loading_psf": 50}},
        ),
    ]
    assert [a.status_code for a in answers] == [422, 404, 422, 409]
    for a in answers:
        ErrorBody.model_validate(a.json(), strict=True)
        assert set(a.json()) <= {"detail", "field"}


def test_the_openapi_document_validates_and_types_every_job_and_study_kind(api):
    """Issue 14: a client generated from the document knows every job kind and every footprint method (the study
    was a free-form object); the document is valid OpenAPI."""
    from openapi_spec_validator import validate

    spec = api.get("/openapi.json").json()
    validate(spec)
    jobs = spec["paths"]["/api/jobs"]["post"]["requestBody"]["content"]["application/json"]["schema"]
    assert jobs["discriminator"]["propertyName"] == "kind"
    assert set(jobs["discriminator"]["mapping"]) == JOB_KINDS
    study = spec["components"]["schemas"]["FootprintJob"]["properties"]["study"]
    assert study["discriminator"]["propertyName"] == "method"
    assert set(study["discriminator"]["mapping"]) == {
        "single_parameter",
        "constant_bank",
        "staged",
        "two_parameter",
        "constant_altitude",
        "temperature_limited",
        "collocation",
    }
    for path in ("/api/trajectories", "/api/transform", "/api/reach"):  # typed, not an object of anything
        body = spec["paths"][path]["post"]["requestBody"]["content"]["application/json"]["schema"]
        assert body.get("$ref") or body.get("properties"), (path, body)


OPERATION = re.compile(r"^- `(GET|POST|PUT|PATCH|DELETE) (/api/[^`?\s]*)", flags=re.M)


def _operations(pairs) -> set[tuple[str, str]]:
    """(method, path) with every path parameter written {}: the document says {id} where the OpenAPI says {job_id}."""
    return {(m.upper(), re.sub(r"\{[^}]*\}", "{}", p)) for m, p in pairs}


def test_the_document_lists_every_operation_of_the_openapi_and_no_other(api):
    """Issue 25 item 7: PATCH /api/footprints/{id} was in the service and not in docs/api.md."""
    spec = api.get("/openapi.json").json()
    served = _operations((m, p) for p, ops in spec["paths"].items() for m in ops if p.startswith("/api/"))
    assert _operations(OPERATION.findall(DOC.read_text())) == served
    readme = (DOC.parents[1] / "README.md").read_text()
    counted = re.search(r"every one of its (\d+) operations", readme)
    assert counted and int(counted.group(1)) == sum(len(ops) for ops in spec["paths"].values()), counted


def test_a_body_that_is_not_json_gets_the_status_the_document_gives(api):
    r = api.post("/api/trajectories", content=b"{not json", headers={"Content-Type": "application/json"})
    assert r.status_code == 422 and r.json()["field"] == "body", r.text
    assert "A body that is not valid JSON: 422" in DOC.read_text()


def test_an_unknown_vehicle_names_its_field_once(api):
    r = api.post(
        "/api/jobs",
        json={
            "kind": "footprint",
            "study": {
                "case": {
                    "vehicle": {"builtin": "nope"},
                    "entry": {
                        "altitude_ft": 364800,
                        "velocity_fps": 22000,
                        "gamma_deg": -3,
                        "heading_deg": 90,
                        "latitude_deg": 0,
                        "longitude_deg": 0,
                    },
                    "stop": {"altitude_ft": 50000},
                },
                "method": "single_parameter",
                "bank0_deg": [0],
            },
        },
    )
    assert r.status_code == 422
    assert r.json()["detail"].count("vehicle.builtin") == 1 and "lod-1.89" in r.json()["detail"], r.text


def test_every_json_body_is_read_by_the_framework_as_its_contract_model():
    """Issue 26: the document is generated from the routes, not patched in; each route's body is the contract's
    model (no dict[str, Any]), parsed once by FastAPI with the door's context (deps.job_door, deps.sync_door)."""
    from typing import get_args

    from footprint.contracts.case import Case
    from footprint.contracts.reach import ReachRequest
    from footprint.contracts.transform import TransformRequest
    from footprint.service.routers import geometry, jobs, sites, trajectories

    def body_type(router, path: str):
        (route,) = [r for r in router.routes if r.path == path and "POST" in r.methods]
        return route.body_field.field_info.annotation

    assert body_type(trajectories.router, "/trajectories") is Case
    assert body_type(geometry.router, "/transform") is TransformRequest
    assert body_type(sites.router, "/reach") is ReachRequest
    job_models = get_args(body_type(jobs.submit_router(), "/jobs"))
    kinds = {get_args(m.model_fields["kind"].annotation)[0]: m.model_fields["study"].annotation for m in job_models}
    assert set(kinds) == JOB_KINDS
    assert kinds["reach"] is ReachRequest
